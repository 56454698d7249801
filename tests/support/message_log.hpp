// Test helper: every message on one LCM channel, in the order received, on its own thread with a deep
// queue (message_counter.hpp), and a wait for one that satisfies a condition. For a daemon's latest status,
// see latest_message.hpp.
#pragma once

#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "support/message_counter.hpp"

namespace ogf::testing {

template <class Message>
class MessageLog {
 public:
  MessageLog(const std::string& url, const std::string& channel)
      : counter_(url, channel, [this](const Message& m) {
          std::lock_guard lk(mu_);
          messages_.push_back(m);
        }) {}

  std::vector<Message> messages() const {
    std::lock_guard lk(mu_);
    return messages_;
  }
  // The first message received for which `pred` holds, or nullopt after `limit`.
  template <class Pred>
  std::optional<Message> waitFor(Pred pred, std::chrono::milliseconds limit) const {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    do {
      {
        std::lock_guard lk(mu_);
        for (const auto& m : messages_)
          if (pred(m)) return m;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    } while (std::chrono::steady_clock::now() < deadline);
    return std::nullopt;
  }

 private:
  mutable std::mutex mu_;
  std::vector<Message> messages_;
  MessageCounter<Message> counter_;  // last: its thread stops before the members above go
};

}  // namespace ogf::testing
