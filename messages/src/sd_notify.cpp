#include "ogf/transport/sd_notify.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstddef>
#include <cstdlib>
#include <cstring>

namespace ogf::transport {
namespace {

std::optional<long long> envNumber(const char* name) {
  const char* v = std::getenv(name);
  if (v == nullptr || *v == '\0') return std::nullopt;
  long long out = 0;
  const char* end = v + std::strlen(v);
  auto [ptr, ec] = std::from_chars(v, end, out);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return out;
}

}  // namespace

SystemdNotifier::SystemdNotifier() {
  if (const char* s = std::getenv("NOTIFY_SOCKET"); s != nullptr && *s != '\0') socket_path_ = s;
  const auto usec = envNumber("WATCHDOG_USEC");
  const auto pid = envNumber("WATCHDOG_PID");
  if (usec && *usec > 0 && (!pid || *pid == static_cast<long long>(::getpid()))) {
    watchdog_ = std::chrono::microseconds(*usec);
  }
}

bool SystemdNotifier::notify(std::string_view state) const {
  if (socket_path_.empty()) return false;
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (socket_path_.size() >= sizeof(addr.sun_path)) return false;
  std::memcpy(addr.sun_path, socket_path_.data(), socket_path_.size());
  if (addr.sun_path[0] == '@') addr.sun_path[0] = '\0';  // abstract socket
  const auto len = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + socket_path_.size());

  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  const ssize_t sent = ::sendto(fd, state.data(), state.size(), MSG_NOSIGNAL,
                                reinterpret_cast<const sockaddr*>(&addr), len);
  ::close(fd);
  return sent == static_cast<ssize_t>(state.size());
}

bool SystemdNotifier::ready(std::string_view status) const {
  if (status.empty()) return notify("READY=1");
  std::string msg = "READY=1\nSTATUS=";
  msg += status;
  return notify(msg);
}

bool SystemdNotifier::status(std::string_view text) const {
  std::string msg = "STATUS=";
  msg += text;
  return notify(msg);
}

}  // namespace ogf::transport
