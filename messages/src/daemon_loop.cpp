#include "ogf/transport/daemon_loop.hpp"

#include <spdlog/spdlog.h>

#include <csignal>

namespace ogf::transport {

DaemonLoop::DaemonLoop() : signals_(io_, SIGINT, SIGTERM), watchdog_timer_(io_) {
  signals_.async_wait([this](const boost::system::error_code& ec, int signo) {
    if (ec) return;
    stop_signal_ = signo;
    spdlog::info("{} received, shutting down", signo == SIGINT ? "SIGINT" : "SIGTERM");
    requestStop(0);
  });
}

void DaemonLoop::ready(std::string_view status) {
  notifier_.ready(status);
  armWatchdog();
}

void DaemonLoop::armWatchdog() {
  const auto interval = notifier_.watchdogInterval();
  if (!interval) return;
  watchdog_timer_.expires_after(*interval / 2);
  watchdog_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || stopping_) return;
    if (!healthy_ || healthy_()) {
      notifier_.watchdog();
    } else {
      spdlog::warn("health check failed: not feeding the systemd watchdog");
    }
    armWatchdog();
  });
}

void DaemonLoop::requestStop(int exit_code) {
  if (stopping_) return;
  stopping_ = true;
  exit_code_ = exit_code;
  notifier_.stopping();
  if (on_shutdown_) on_shutdown_();
  boost::system::error_code ec;
  signals_.cancel(ec);
  watchdog_timer_.cancel();
  io_.stop();
}

int DaemonLoop::run() {
  io_.run();
  return exit_code_;
}

}  // namespace ogf::transport
