// A stream of the mapper followed from Python: an LCM subscription feeding a receiver (delta::MapReceiver for
// OGF_MAP_DELTA, navigation::NavReceiver for OGF_NAV_GRID) and a keyframe request (map_request_t) published
// while the receiver needs one, as ogf-map-client does: at start, after a gap, after the mapper started a
// new map, and again every kKeyframeRetry while none arrives. The bus is handled without the GIL, so other
// Python threads run while a client waits; Ctrl-C interrupts a wait within kSlice.
#pragma once

#include <pybind11/pybind11.h>

#include <lcm/lcm-cpp.hpp>

#include <ogf/map_request_t.hpp>

#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "errors.hpp"
#include "ogf/delta/keyframe_request.hpp"
#include "ogf/transport/lcm_asio_bridge.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/subscriber.hpp"

namespace ogf::python {

template <class Message, class Receiver>
class StreamFollower {
 public:
  static constexpr std::chrono::milliseconds kSlice{100};
  static constexpr std::chrono::seconds kKeyframeRetry{1};

  // ValueError when the URL is not one LCM can join, or its port is held by a socket that does not share it.
  StreamFollower(const std::optional<std::string>& url, const std::string& channel, const std::string& request_channel)
      : url_(transport::withReceiveBuffer(transport::resolveLcmUrl(url.value_or("")))),
        channel_(channel), request_channel_(request_channel), lcm_(url_) {
    if (!lcm_.good()) raiseValueError("cannot join the LCM bus '" + url_ + "' (is it a valid LCM URL?)");
    if (const auto why = transport::receiveProblem(lcm_, url_)) raiseValueError(*why);
    subscriber_.emplace(
        lcm_, channel_,
        [this](const Message& m, const lcm::ReceiveBuffer&, const std::string&) {
          ++messages_;
          const bool needed_before = receiver_.needsKeyframe();
          receiver_.accept(m);
          if (receiver_.needsKeyframe() && !needed_before) requestKeyframe();
        },
        [this](const std::string&, std::size_t, const std::string&) { ++decode_errors_; });
  }

  // Handles the bus for timeout_s seconds; the number of messages received.
  std::uint64_t poll(double timeout_s) {
    const std::uint64_t before = messages_;
    run(timeout_s, [] { return false; });
    return messages_ - before;
  }

  // Handles the bus until the receiver is consistent with the mapper's checksum or timeout_s passes.
  bool waitConsistent(double timeout_s) {
    return run(timeout_s, [this] { return !receiver_.needsKeyframe() && receiver_.consistent(); });
  }

  // f(receiver) while no other thread handles the bus (a client may be polled from one thread and read
  // from another).
  template <class F>
  auto withReceiver(F f) {
    std::lock_guard<std::mutex> lock(mutex_);
    return f(receiver_);
  }
  const std::string& url() const { return url_; }
  const std::string& channel() const { return channel_; }
  std::uint64_t messages() {
    std::lock_guard<std::mutex> lock(mutex_);
    return messages_;
  }
  std::uint64_t malformed() {
    std::lock_guard<std::mutex> lock(mutex_);
    return receiver_.malformed() + decode_errors_;
  }

 private:
  template <class Done>
  bool run(double timeout_s, Done done) {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(timeout_s > 0 ? timeout_s : 0));
    for (;;) {
      bool finished = false;
      {
        pybind11::gil_scoped_release unlocked;
        std::lock_guard<std::mutex> lock(mutex_);
        const auto slice_end = std::min(deadline, std::chrono::steady_clock::now() + kSlice);
        for (;;) {
          if (done()) { finished = true; break; }
          const auto now = std::chrono::steady_clock::now();
          if (now >= slice_end) break;
          if (receiver_.needsKeyframe() && (!last_request_ || now - *last_request_ >= kKeyframeRetry)) requestKeyframe();
          const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(slice_end - now).count();
          lcm_.handleTimeout(static_cast<int>(std::max<std::int64_t>(1, left)));
        }
      }
      if (finished) return true;
      if (PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
      if (std::chrono::steady_clock::now() >= deadline) return done();
    }
  }

  void requestKeyframe() {
    ogf::map_request_t req{};
    req.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                    std::chrono::system_clock::now().time_since_epoch()).count();
    req.requester = requester_;
    req.last_seq = receiver_.appliedSeq();
    lcm_.publish(request_channel_, &req);
    last_request_ = std::chrono::steady_clock::now();
  }

  std::string url_, channel_, request_channel_;
  lcm::LCM lcm_;
  Receiver receiver_;
  std::optional<transport::Subscriber<Message>> subscriber_;
  std::mutex mutex_;
  std::uint64_t messages_ = 0;
  std::uint64_t decode_errors_ = 0;
  std::optional<std::chrono::steady_clock::time_point> last_request_;
  const std::string requester_ = delta::requesterName();
};

}  // namespace ogf::python
