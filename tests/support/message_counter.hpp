// Test helper: counts the messages on one LCM channel, received on its own thread with a deep queue, and
// hands each to a hook (to keep or sum what the test needs of it). For a daemon's latest status, see
// latest_message.hpp.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <atomic>
#include <chrono>
#include <functional>
#include <string>

#include "support/lcm_thread.hpp"

namespace ogf::testing {

template <class Message>
class MessageCounter {
 public:
  using Hook = std::function<void(const Message&)>;

  // `hook` runs on the counter's thread for every message.
  MessageCounter(const std::string& url, const std::string& channel, Hook hook = {})
      : hook_(std::move(hook)), receiver_(url) {
    if (auto* sub = receiver_.lcm().subscribe(channel, &MessageCounter::onMessage, this)) {
      sub->setQueueCapacity(100000);
    }
    receiver_.start(std::chrono::milliseconds(20));
  }

  std::int64_t count() const { return count_; }

 private:
  void onMessage(const lcm::ReceiveBuffer*, const std::string&, const Message* m) {
    if (hook_) hook_(*m);
    ++count_;
  }

  Hook hook_;
  std::atomic<std::int64_t> count_{0};
  LcmThread receiver_;  // last: stops before the members above go
};

}  // namespace ogf::testing
