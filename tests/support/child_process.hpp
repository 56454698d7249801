// Test helper: runs a program as a real child process (posix_spawn), with its output to a file, and
// waits for it or stops it with a signal.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace ogf::testing {

class ChildProcess {
 public:
  // Starts `argv[0]` with `argv`; stdout and stderr go to `log_path`.
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool started() const { return pid_ > 0; }
  // The child's process id (-1 when it did not start), e.g. to read /proc/<pid>/status.
  pid_t pid() const { return pid_; }
  // The exit status once it has exited within `timeout` (-signal when killed by one), else nullopt.
  std::optional<int> wait(std::chrono::milliseconds timeout);
  void signal(int sig);
  std::string log() const;

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
  std::string log_path_;
};

// A program run to its end: its exit status (-1000 when it did not end within the limit, then killed)
// and everything it printed.
struct Finished {
  int rc = -1000;
  std::string output;
};
Finished runAndCapture(const std::vector<std::string>& argv, const std::string& log_path,
                  std::chrono::milliseconds limit = std::chrono::seconds(120));

}  // namespace ogf::testing
