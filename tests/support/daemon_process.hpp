// Test helper: a daemon (ogf-mapper, ogf-driver) as a real child process on a udpm URL of its own
// (multicast.hpp), with its status channel heard from before it starts. Waits for its first status or for
// one that satisfies a condition, says what its log holds when a wait fails, and stops it the way systemd
// does (SIGTERM), checking that it exits 0.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "support/child_process.hpp"
#include "support/latest_message.hpp"

namespace ogf::testing {

// The daemons' status channels when no --status-channel is given (mapper/daemon/include/ogf/mapper_daemon/
// mapper_options.hpp, driver/daemon/driver_config.hpp).
inline constexpr const char* kMapperStatusChannel = "OGF_MAPPER_STATUS";
inline constexpr const char* kDriverStatusChannel = "VELODYNE_STATUS";

// Success when `process` started and `status_seen`; else why not, with the process's log.
::testing::AssertionResult reportedStatus(ChildProcess& process, bool status_seen, std::chrono::milliseconds limit);
// Sends SIGTERM and waits `limit` for the exit: success on exit status 0, else the status (or that it did not
// end) and the log. A process that does not end is killed when its ChildProcess goes.
::testing::AssertionResult stopWithSigterm(ChildProcess& process, std::chrono::milliseconds limit);
// SIGKILL, then waits for the process to be gone (so a restart never meets it on the bus or its files).
::testing::AssertionResult killNine(ChildProcess& process);

template <class Status>
class DaemonProcess {
 public:
  // Subscribes to `status_channel` on `url`, then starts `argv` (whose --lcm-url should be `url`) with its
  // output to `log_path`: no status the daemon sends is missed.
  DaemonProcess(const std::vector<std::string>& argv, const std::string& log_path, const std::string& url,
                const std::string& status_channel)
      : status_(url, status_channel), process_(argv, log_path) {}

  ChildProcess& process() { return process_; }
  bool started() const { return process_.started(); }
  std::string log() const { return process_.log(); }
  // Still running (it has not exited, or been killed).
  bool running() { return process_.started() && !process_.wait(std::chrono::milliseconds(0)).has_value(); }

  std::optional<Status> latestStatus() const { return status_.latest(); }
  // The first status (the latest at each poll) for which `pred` holds, or nullopt after `limit`.
  template <class Pred>
  std::optional<Status> waitForStatus(Pred pred, std::chrono::milliseconds limit) const {
    return status_.waitFor(pred, limit);
  }
  // Started, and sent a status within `limit`; else the log (at once when the daemon exits before any
  // status, as one refusing its configuration does). For ASSERT_TRUE.
  ::testing::AssertionResult reportsStatus(std::chrono::milliseconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!status_.latest() && running() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return reportedStatus(process_, status_.latest().has_value(), limit);
  }
  // SIGTERM, then exit status 0 within `limit`; else the status and the log. For EXPECT_TRUE.
  ::testing::AssertionResult stop(std::chrono::milliseconds limit = std::chrono::seconds(20)) {
    return stopWithSigterm(process_, limit);
  }
  ::testing::AssertionResult kill() { return killNine(process_); }

 private:
  LatestMessage<Status> status_;  // first: listening before the daemon starts, and until it is gone
  ChildProcess process_;
};

}  // namespace ogf::testing
