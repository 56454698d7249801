#include "ogf/transport/lcm_asio_bridge.hpp"

#include <unistd.h>

#include <boost/system/error_code.hpp>

namespace ogf::transport {

std::optional<std::string> receiveProblem(lcm::LCM& lcm, std::string_view url) {
  if (lcm.getFileno() >= 0) return std::nullopt;
  return "cannot receive on the LCM bus " + std::string(url) + ": the port is held by a socket that does not share it";
}

// The descriptor is dup()ed: Asio closes what it owns, and LCM must keep its own.
LcmAsioBridge::LcmAsioBridge(boost::asio::io_context& io, lcm::LCM& lcm, std::function<void()> on_end)
    : lcm_(lcm), descriptor_(io, ::dup(lcm.getFileno())), on_end_(std::move(on_end)) {
  arm();
}

LcmAsioBridge::~LcmAsioBridge() {
  boost::system::error_code ec;
  descriptor_.cancel(ec);
  descriptor_.close(ec);
}

void LcmAsioBridge::arm() {
  descriptor_.async_wait(boost::asio::posix::stream_descriptor::wait_read,
                         [this](const boost::system::error_code& ec) {
                           if (ec) return;  // cancelled: the bridge is going away
                           int rc = 0;
                           // Drain everything queued: fewer wake-ups than one handle() per event.
                           while ((rc = lcm_.handleTimeout(0)) > 0) ++dispatched_;
                           if (rc < 0) {
                             if (!ended_) {
                               ended_ = true;
                               if (on_end_) on_end_();
                             }
                             return;
                           }
                           arm();
                         });
}

}  // namespace ogf::transport
