// Test helper: ogf-view as a real child process (build/bin/ogf-view, or the program $OGF_VIEW_PROGRAM
// names, to measure another build with the same test), and the map files the tests show with --map.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "support/child_process.hpp"

namespace ogf::testing {

class ViewProcess {
 public:
  // `wrapper` goes before the program (e.g. {"prlimit", "--nofile=48:48", "--"}).
  ViewProcess(std::vector<std::string> args, const std::string& name, std::vector<std::string> wrapper = {});
  // Stops it with SIGTERM and expects exit status 0.
  ~ViewProcess();
  ViewProcess(const ViewProcess&) = delete;
  ViewProcess& operator=(const ViewProcess&) = delete;

  // The address it printed at start ("http://127.0.0.1:PORT/", with "?token=..." when it made a token);
  // "" (and a test failure) when it printed none within 20 s.
  std::string url();
  // The port of url().
  std::uint16_t port();
  pid_t pid() const { return process_->pid(); }
  std::string log() const { return process_->log(); }

 private:
  std::string log_path_;
  std::unique_ptr<ChildProcess> process_;
  std::string url_;
};

// Saves a map file of a solid block of `nx` x `ny` x `nz` cells of 0.2 m, each measured occupied three
// times; returns how many cells it publishes as occupied (what ogf-view draws).
std::size_t writeBlockMap(const std::filesystem::path& path, int nx, int ny, int nz);

}  // namespace ogf::testing
