#include "ogf/transport/logging.hpp"

#include <cstdio>

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_sinks.h>

#include <cstdlib>
#include <memory>
#include <string>

namespace ogf::transport {
namespace {

// sd-daemon(3) priorities: <7> debug, <6> info, <4> warning, <3> err, <2> crit.
class SdPriorityFlag final : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&, spdlog::memory_buf_t& dest) override {
    const char* prefix = "<6>";
    switch (msg.level) {
      case spdlog::level::trace:
      case spdlog::level::debug: prefix = "<7>"; break;
      case spdlog::level::info: prefix = "<6>"; break;
      case spdlog::level::warn: prefix = "<4>"; break;
      case spdlog::level::err: prefix = "<3>"; break;
      case spdlog::level::critical: prefix = "<2>"; break;
      default: break;
    }
    dest.append(prefix, prefix + 3);
  }
  std::unique_ptr<custom_flag_formatter> clone() const override {
    return std::make_unique<SdPriorityFlag>();
  }
};

}  // namespace

void setupLogging(std::string_view program, spdlog::level::level_enum level) {
  auto sink = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  auto logger = std::make_shared<spdlog::logger>(std::string(program), sink);
  const char* journal = std::getenv("JOURNAL_STREAM");
  if (journal != nullptr && *journal != '\0') {
    auto formatter = std::make_unique<spdlog::pattern_formatter>();
    formatter->add_flag<SdPriorityFlag>('*').set_pattern("%*%v");
    logger->set_formatter(std::move(formatter));
  } else {
    logger->set_pattern("%Y-%m-%d %H:%M:%S.%e %^%-5l%$ [%n] %v");
  }
  logger->set_level(level);
  logger->flush_on(spdlog::level::warn);
  spdlog::set_default_logger(std::move(logger));
}

std::optional<spdlog::level::level_enum> parseLogLevel(std::string_view name) {
  if (name == "trace") return spdlog::level::trace;
  if (name == "debug") return spdlog::level::debug;
  if (name == "info") return spdlog::level::info;
  if (name == "warn" || name == "warning") return spdlog::level::warn;
  if (name == "error") return spdlog::level::err;
  if (name == "critical") return spdlog::level::critical;
  if (name == "off") return spdlog::level::off;
  return std::nullopt;
}

bool setupLoggingAt(std::string_view program, std::string_view option, std::string_view level) {
  const auto parsed = parseLogLevel(level);
  if (!parsed) {
    std::fprintf(stderr, "%.*s: %.*s: unknown level '%.*s' (trace, debug, info, warn, error, critical, off)\n",
                 static_cast<int>(program.size()), program.data(), static_cast<int>(option.size()), option.data(),
                 static_cast<int>(level.size()), level.data());
    return false;
  }
  setupLogging(program, *parsed);
  return true;
}

std::optional<std::uint64_t> LogRateLimiter::allow(std::chrono::steady_clock::time_point now) {
  if (last_ && now - *last_ < period_) {
    ++suppressed_;
    return std::nullopt;
  }
  last_ = now;
  const auto held = suppressed_;
  suppressed_ = 0;
  return held;
}

}  // namespace ogf::transport
