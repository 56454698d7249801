// Test helper: the latest message of one type on one channel (a daemon's status), received on its own
// thread, and a wait for one that satisfies a condition.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "support/lcm_thread.hpp"

namespace ogf::testing {

template <class Message>
class LatestMessage {
 public:
  LatestMessage(const std::string& url, const std::string& channel) : receiver_(url) {
    receiver_.lcm().subscribe(channel, &LatestMessage::onMessage, this);
    receiver_.start(std::chrono::milliseconds(50));
  }

  std::optional<Message> latest() const {
    std::lock_guard lk(mu_);
    return latest_;
  }
  // Forgets the latest message (a process was restarted: only its own messages count from now on).
  void reset() {
    std::lock_guard lk(mu_);
    latest_.reset();
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
  mutable std::mutex mu_;
  std::optional<Message> latest_;
  LcmThread receiver_;  // last: stops before the members above go
};

}  // namespace ogf::testing
