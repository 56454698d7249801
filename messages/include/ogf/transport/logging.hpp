// Logging set-up every program shares: spdlog to stderr in a form journald understands.
#pragma once

#include <spdlog/spdlog.h>

#include <chrono>
#include <optional>
#include <string_view>

namespace ogf::transport {

// Makes the default logger a stderr logger named `program`. Under systemd ($JOURNAL_STREAM set) each
// line starts with an sd-daemon priority prefix ("<6>", "<4>", "<3>": journald's SyslogLevelPrefix= reads
// it) and carries no timestamp, since journald adds one. On a terminal lines carry time and level.
void setupLogging(std::string_view program, spdlog::level::level_enum level = spdlog::level::info);

// "trace", "debug", "info", "warn", "error", "critical", "off"; nullopt for anything else.
std::optional<spdlog::level::level_enum> parseLogLevel(std::string_view name);

// A program's start: parseLogLevel(level), then setupLogging(program, it). For an unknown name it sets up
// nothing and returns false after saying so on stderr, naming the option it came from ("ogf-map:
// --log-level: unknown level 'loud' (trace, debug, info, warn, error, critical, off)"); the caller exits.
bool setupLoggingAt(std::string_view program, std::string_view option, std::string_view level);

// Lets one kind of message through at most once per `period`, and says how many were held back, so bad
// input at packet rate never floods the journal:
//   if (auto n = limiter.allow(now)) spdlog::warn("... ({} more since last report)", *n);
class LogRateLimiter {
 public:
  explicit LogRateLimiter(std::chrono::steady_clock::duration period = std::chrono::seconds(1))
      : period_(period) {}
  // Returns the number suppressed since the last allowed message when this one may be logged.
  std::optional<std::uint64_t> allow(std::chrono::steady_clock::time_point now =
                                         std::chrono::steady_clock::now());

 private:
  std::chrono::steady_clock::duration period_;
  std::optional<std::chrono::steady_clock::time_point> last_;
  std::uint64_t suppressed_ = 0;
};

}  // namespace ogf::transport
