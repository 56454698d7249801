// The systemd notification protocol without libsystemd: one AF_UNIX datagram to $NOTIFY_SOCKET per state
// change (sd_notify(3), "Standalone Implementations"; the protocol is declared stable API). Outside
// systemd (no NOTIFY_SOCKET) every call is a no-op that returns false.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <string_view>

namespace ogf::transport {

class SystemdNotifier {
 public:
  // Reads NOTIFY_SOCKET, WATCHDOG_USEC and WATCHDOG_PID from the environment.
  SystemdNotifier();

  // Whether a notification socket is configured.
  bool enabled() const { return !socket_path_.empty(); }

  // The watchdog interval systemd expects pings within, when the watchdog is on for this process
  // (WATCHDOG_PID, when set, must be our PID: sd_watchdog_enabled(3)).
  std::optional<std::chrono::microseconds> watchdogInterval() const { return watchdog_; }

  // Sends `state` ("READY=1", "WATCHDOG=1", "STOPPING=1", "STATUS=...", newline-separated). True when the
  // datagram was sent.
  bool notify(std::string_view state) const;

  bool ready(std::string_view status = {}) const;
  bool watchdog() const { return notify("WATCHDOG=1"); }
  bool stopping() const { return notify("STOPPING=1"); }
  bool status(std::string_view text) const;

 private:
  std::string socket_path_;  // leading '@' = abstract namespace
  std::optional<std::chrono::microseconds> watchdog_;
};

}  // namespace ogf::transport
