// Test helper: a robot standing still whose odometry (ogf.odometry_t on POSE) is stamped with the host
// clock, published at 50 Hz on its own thread until destroyed.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/odometry_t.hpp>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

namespace ogf::testing {

class HostOdometry {
 public:
  explicit HostOdometry(const std::string& url) : lcm_(url), thread_([this] { run(); }) {}
  ~HostOdometry() {
    stop_ = true;
    thread_.join();
  }
  HostOdometry(const HostOdometry&) = delete;
  HostOdometry& operator=(const HostOdometry&) = delete;

  // Poses published so far.
  std::int64_t published() const { return published_; }

 private:
  void run() {
    while (!stop_) {
      ogf::odometry_t m{};
      m.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                    std::chrono::system_clock::now().time_since_epoch())
                    .count();
      m.frame_id = "odom";
      m.child_frame_id = "body";
      m.orientation[0] = 1;
      m.num_covariance = 0;
      if (lcm_.publish("POSE", &m) == 0) ++published_;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  lcm::LCM lcm_;
  std::atomic<bool> stop_{false};
  std::atomic<std::int64_t> published_{0};
  std::thread thread_;
};

}  // namespace ogf::testing
