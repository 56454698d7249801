// Test helper: the latest message of one type on one channel (a daemon's status), received on its own
// thread, and a wait for one that satisfies a condition.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace ogf::testing {

template <class Message>
class LatestMessage {
 public:
  LatestMessage(const std::string& url, const std::string& channel) : lcm_(url) {
    lcm_.subscribe(channel, &LatestMessage::onMessage, this);
    thread_ = std::thread([this] {
      while (!stop_) lcm_.handleTimeout(50);
    });
  }
  ~LatestMessage() {
    stop_ = true;
    thread_.join();
  }
  LatestMessage(const LatestMessage&) = delete;
  LatestMessage& operator=(const LatestMessage&) = delete;

  std::optional<Message> latest() const {
    std::lock_guard lk(mu_);
    return latest_;
  }
  // The first message (the latest at each poll) for which `pred` holds, or nullopt after `limit`.
  template <class Pred>
  std::optional<Message> waitFor(Pred pred, std::chrono::milliseconds limit) const {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    do {
      if (auto m = latest(); m && pred(*m)) return m;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    } while (std::chrono::steady_clock::now() < deadline);
    return std::nullopt;
  }

 private:
  void onMessage(const lcm::ReceiveBuffer*, const std::string&, const Message* m) {
    std::lock_guard lk(mu_);
    latest_ = *m;
  }
  lcm::LCM lcm_;
  mutable std::mutex mu_;
  std::optional<Message> latest_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ogf::testing
