#include "support/daemon_process.hpp"

#include <csignal>

namespace ogf::testing {

::testing::AssertionResult reportedStatus(ChildProcess& process, bool status_seen, std::chrono::milliseconds limit) {
  if (!process.started()) return ::testing::AssertionFailure() << "the daemon did not start";
  if (status_seen) return ::testing::AssertionSuccess();
  auto failure = ::testing::AssertionFailure() << "no status within " << limit.count() << " ms";
  if (const auto rc = process.wait(std::chrono::milliseconds(0))) failure << " (it exited with " << *rc << ")";
  return failure << "; its log:\n" << process.log();
}

::testing::AssertionResult stopWithSigterm(ChildProcess& process, std::chrono::milliseconds limit) {
  process.signal(SIGTERM);
  const auto rc = process.wait(limit);
  if (rc == 0) return ::testing::AssertionSuccess();
  auto failure = ::testing::AssertionFailure();
  if (rc) {
    failure << "exited with " << *rc << " after SIGTERM";
  } else {
    failure << "still running " << limit.count() << " ms after SIGTERM";
  }
  return failure << "; its log:\n" << process.log();
}

::testing::AssertionResult killNine(ChildProcess& process) {
  process.signal(SIGKILL);
  if (process.wait(std::chrono::seconds(10))) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "still running 10 s after SIGKILL";
}

}  // namespace ogf::testing
