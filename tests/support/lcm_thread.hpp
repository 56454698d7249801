// Test helper: an lcm::LCM whose messages are handled on its own thread, from start() until it is
// destroyed. The listeners (latest_message.hpp, message_counter.hpp) declare it as their last member, so
// the thread stops before the state its handlers write is gone.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

namespace ogf::testing {

class LcmThread {
 public:
  explicit LcmThread(const std::string& url) : lcm_(url) {}
  ~LcmThread() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  LcmThread(const LcmThread&) = delete;
  LcmThread& operator=(const LcmThread&) = delete;

  // Subscribe through this before start().
  lcm::LCM& lcm() { return lcm_; }
  // Handles messages, waking at least every `poll` to see whether to stop.
  void start(std::chrono::milliseconds poll) {
    thread_ = std::thread([this, poll] {
      while (!stop_) lcm_.handleTimeout(static_cast<int>(poll.count()));
    });
  }

 private:
  lcm::LCM lcm_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ogf::testing
