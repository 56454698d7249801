// The process skeleton both daemons share: one Boost.Asio io_context, clean shutdown on SIGINT and
// SIGTERM (STOPPING=1, then the loop stops), READY=1 once the daemon says it is ready, and WATCHDOG=1 at
// half the interval systemd asked for (sd_watchdog_enabled(3)) as long as the daemon reports itself
// healthy.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include <functional>
#include <string>
#include <string_view>

#include "ogf/transport/sd_notify.hpp"

namespace ogf::transport {

class DaemonLoop {
 public:
  DaemonLoop();
  DaemonLoop(const DaemonLoop&) = delete;
  DaemonLoop& operator=(const DaemonLoop&) = delete;

  boost::asio::io_context& io() { return io_; }
  const SystemdNotifier& notifier() const { return notifier_; }

  // Runs `fn` once when a shutdown starts (signal or requestStop), before the loop stops.
  void onShutdown(std::function<void()> fn) { on_shutdown_ = std::move(fn); }

  // The watchdog is fed only while `fn` returns true; a wedged daemon then gets restarted by systemd.
  void setHealthCheck(std::function<bool()> fn) { healthy_ = std::move(fn); }

  // Tells systemd the daemon is ready and starts the watchdog pings.
  void ready(std::string_view status = {});

  // Starts a clean shutdown from inside the program (e.g. the input ended). `exit_code` is what run()
  // returns.
  void requestStop(int exit_code = 0);

  // Runs the loop until shutdown; returns the exit code (0 on a signal).
  int run();

  // The signal that stopped the loop, 0 if none.
  int stopSignal() const { return stop_signal_; }

 private:
  void armWatchdog();

  boost::asio::io_context io_;
  boost::asio::signal_set signals_;
  boost::asio::steady_timer watchdog_timer_;
  SystemdNotifier notifier_;
  std::function<void()> on_shutdown_;
  std::function<bool()> healthy_;
  bool stopping_ = false;
  int exit_code_ = 0;
  int stop_signal_ = 0;
};

}  // namespace ogf::transport
