// A typed LCM subscription that decodes itself, so a malformed message (wrong fingerprint, truncated,
// absurd lengths) is reported to the caller and counted instead of LCM's "error -1 decoding" on stderr.
// A message longer than the subscription's `max_bytes` is refused from its received length alone, before
// any of it is decoded. LCM 1.3.1 has no lambda subscribe (it arrived in 1.4), hence the trampoline.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <string_view>

#include "ogf/messages/decode_message.hpp"
#include "ogf/transport/lcm_url.hpp"

namespace ogf::transport {

template <class Message>
class Subscriber {
 public:
  using Handler = std::function<void(const Message& msg, const lcm::ReceiveBuffer& rbuf,
                                     const std::string& channel)>;
  // Called with the channel, the received size and a reason when a message does not decode.
  using ErrorHandler =
      std::function<void(const std::string& channel, std::size_t size, const std::string& reason)>;

  Subscriber(lcm::LCM& lcm, const std::string& channel, Handler on_message, ErrorHandler on_error,
             int queue_capacity = kSubscriptionQueueCapacity,
             std::size_t max_bytes = std::numeric_limits<std::size_t>::max())
      : lcm_(lcm), on_message_(std::move(on_message)), on_error_(std::move(on_error)), max_bytes_(max_bytes) {
    subscription_ = lcm_.subscribeFunction(channel, &Subscriber::trampoline, this);
    if (subscription_ != nullptr) subscription_->setQueueCapacity(queue_capacity);
  }
  ~Subscriber() {
    if (subscription_ != nullptr) lcm_.unsubscribe(subscription_);
  }
  Subscriber(const Subscriber&) = delete;
  Subscriber& operator=(const Subscriber&) = delete;

  bool ok() const { return subscription_ != nullptr; }

 private:
  static void trampoline(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Subscriber* self) {
    self->dispatch(*rbuf, channel);
  }
  void dispatch(const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
    if (rbuf.data_size > max_bytes_) {
      if (on_error_)
        on_error_(channel, rbuf.data_size, "is longer than the " + std::to_string(max_bytes_) + " bytes a message on " +
                                               channel + " may be (refused before decoding)");
      return;
    }
    // Reused between messages: generated decode() leaves stale elements for zero-length arrays, so
    // every message decodes into a fresh object.
    Message msg;
    if (auto why = ogf::messages::decodeMessage(rbuf.data, rbuf.data_size, msg)) {
      if (on_error_) on_error_(channel, rbuf.data_size, *why);
      return;
    }
    on_message_(msg, rbuf, channel);
  }

  lcm::LCM& lcm_;
  Handler on_message_;
  ErrorHandler on_error_;
  std::size_t max_bytes_;
  lcm::Subscription* subscription_ = nullptr;
};

}  // namespace ogf::transport
