#include "ogf/log_io/log_events.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

namespace ogf::log_io {

Result<LogEvents> LogEvents::open(const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return Error{fmt::format("{}: {}", path.string(), ec.message())};
  auto log = std::make_unique<lcm::LogFile>(path.string(), "r");
  if (!log->good()) return Error{fmt::format("{}: cannot open as an LCM log", path.string())};
  return LogEvents(std::move(log), size);
}

double LogEvents::fractionRead() const {
  const long pos = std::ftell(log_->getFilePtr());
  if (pos < 0 || size_ == 0) return 0.0;
  return std::min(1.0, static_cast<double>(pos) / static_cast<double>(size_));
}

}  // namespace ogf::log_io
