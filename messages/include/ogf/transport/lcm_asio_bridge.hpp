// Drives an LCM instance from a Boost.Asio io_context: LCM's file descriptor (one byte per queued message,
// for every provider) is watched with a stream_descriptor, and all queued messages are dispatched on the
// io_context thread. There is no upstream Asio example; this is the select() pattern of
// LCM's examples/c/listener-async.c moved onto Asio.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace ogf::transport {

// Why `lcm`, joined to `url`, cannot receive, or nothing when it can. udpm opens its receive socket when
// first asked, binding the URL's port and joining its group; when that fails (a socket that does not share
// the port holds it: "bind: Address already in use" on stderr, from LCM) it has no descriptor to watch,
// though good() was true.
std::optional<std::string> receiveProblem(lcm::LCM& lcm, std::string_view url);

class LcmAsioBridge {
 public:
  // `lcm` must be able to receive (receiveProblem). `on_end` runs once when LCM reports an error or the
  // end of a file:// log (handle returns < 0); the bridge then stops watching. Without it an exhausted log
  // would spin the loop.
  LcmAsioBridge(boost::asio::io_context& io, lcm::LCM& lcm, std::function<void()> on_end = {});
  ~LcmAsioBridge();
  LcmAsioBridge(const LcmAsioBridge&) = delete;
  LcmAsioBridge& operator=(const LcmAsioBridge&) = delete;

  // Messages dispatched so far.
  std::uint64_t dispatched() const { return dispatched_; }

 private:
  void arm();

  lcm::LCM& lcm_;
  boost::asio::posix::stream_descriptor descriptor_;
  std::function<void()> on_end_;
  std::uint64_t dispatched_ = 0;
  bool ended_ = false;
};

}  // namespace ogf::transport
