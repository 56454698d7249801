// Test helper: counts the messages on one LCM channel, received on its own thread with a deep queue, and
// hands each to a hook (to keep or sum what the test needs of it). For a daemon's latest status, see
// latest_message.hpp.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace ogf::testing {

template <class Message>
class MessageCounter {
 public:
  using Hook = std::function<void(const Message&)>;

  // `hook` runs on the counter's thread for every message.
  MessageCounter(const std::string& url, const std::string& channel, Hook hook = {})
      : lcm_(url), hook_(std::move(hook)) {
    if (auto* sub = lcm_.subscribe(channel, &MessageCounter::onMessage, this)) sub->setQueueCapacity(100000);
    thread_ = std::thread([this] {
      while (!stop_) lcm_.handleTimeout(20);
    });
  }
  ~MessageCounter() {
    stop_ = true;
    thread_.join();
  }
  MessageCounter(const MessageCounter&) = delete;
  MessageCounter& operator=(const MessageCounter&) = delete;

  std::int64_t count() const { return count_; }

 private:
  void onMessage(const lcm::ReceiveBuffer*, const std::string&, const Message* m) {
    if (hook_) hook_(*m);
    ++count_;
  }

  lcm::LCM lcm_;
  Hook hook_;
  std::atomic<std::int64_t> count_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ogf::testing
