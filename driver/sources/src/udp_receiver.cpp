#include "ogf/driver_sources/udp_receiver.hpp"

#include <arpa/inet.h>
#include <linux/sock_diag.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <boost/asio/ip/address.hpp>
#include <cerrno>
#include <cstring>

namespace ogf::driver_sources {
namespace {

// The kernel's counter is 32 bits; carry its wraps into 64. A datagram queued before the last SO_MEMINFO
// read carries an older (smaller) count: a step back, not a wrap, so it changes nothing.
std::uint64_t widenDropCount(std::uint32_t now, std::uint64_t previous) {
  const auto step = static_cast<std::int32_t>(now - static_cast<std::uint32_t>(previous));
  return step > 0 ? previous + static_cast<std::uint64_t>(step) : previous;
}

}  // namespace

UdpReceiver::UdpReceiver(boost::asio::io_context& io, Handler handler)
    : socket_(io), handler_(std::move(handler)) {}

UdpReceiver::~UdpReceiver() {
  boost::system::error_code ec;
  socket_.close(ec);
}

ogf::Result<std::unique_ptr<UdpReceiver>> UdpReceiver::open(boost::asio::io_context& io,
                                                                 const UdpReceiverConfig& config,
                                                                 Handler handler) {
  std::unique_ptr<UdpReceiver> r(new UdpReceiver(io, std::move(handler)));
  boost::system::error_code ec;
  const auto address = boost::asio::ip::make_address(config.bind_address, ec);
  if (ec) return ogf::Error::configuration("bind address '" + config.bind_address + "': " + ec.message());
  const boost::asio::ip::udp::endpoint endpoint(address, config.port);
  const std::string where = config.bind_address + ":" + std::to_string(config.port);
  r->socket_.open(endpoint.protocol(), ec);
  if (ec) return ogf::Error::io("udp " + where + ": " + ec.message());
  r->socket_.set_option(boost::asio::socket_base::reuse_address(true), ec);
  r->socket_.set_option(boost::asio::socket_base::receive_buffer_size(config.receive_buffer_bytes), ec);
  boost::asio::socket_base::receive_buffer_size granted;
  r->socket_.get_option(granted, ec);
  // Linux reports twice what it grants (the doubling is its bookkeeping overhead, socket(7)); Boost.Asio's
  // get_option halves SO_RCVBUF on Linux already (boost/asio/detail/impl/socket_ops.ipp, getsockopt), so
  // the value is the size granted, at most net.core.rmem_max.
  r->granted_buffer_ = granted.value();
  const int on = 1;
  ::setsockopt(r->socket_.native_handle(), SOL_SOCKET, SO_TIMESTAMP, &on, sizeof(on));
  ::setsockopt(r->socket_.native_handle(), SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof(on));
  r->socket_.bind(endpoint, ec);
  if (ec) return ogf::Error::io("udp " + where + ": bind: " + ec.message());
  r->socket_.non_blocking(true, ec);
  r->port_ = r->socket_.local_endpoint(ec).port();
  r->arm();
  return r;
}

void UdpReceiver::arm() {
  socket_.async_wait(boost::asio::ip::udp::socket::wait_read, [this](const boost::system::error_code& ec) {
    if (ec) return;  // closed
    drain();
    arm();
  });
}

void UdpReceiver::drain() {
  // At most a bounded number per wake-up so other handlers (status timer, signals) still run.
  for (int i = 0; i < 1024; ++i) {
    sockaddr_in from{};
    iovec iov{buffer_.data(), buffer_.size()};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timeval)) + CMSG_SPACE(sizeof(std::uint32_t))];
    msghdr msg{};
    msg.msg_name = &from;
    msg.msg_namelen = sizeof(from);
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof(control);
    const ssize_t n = ::recvmsg(socket_.native_handle(), &msg, MSG_DONTWAIT);
    if (n < 0) return;  // EAGAIN: drained (or an error the next wake-up reports again)
    if ((msg.msg_flags & MSG_TRUNC) != 0) {
      ++oversized_;
      continue;
    }
    UdpDatagram d;
    d.source_ip = ntohl(from.sin_addr.s_addr);
    d.source_port = ntohs(from.sin_port);
    d.destination_port = port_;
    d.payload = {buffer_.data(), static_cast<std::size_t>(n)};
    timeval stamp{};
    bool have_stamp = false;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMP) {
        std::memcpy(&stamp, CMSG_DATA(c), sizeof(stamp));
        have_stamp = true;
      } else if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
        // The socket's cumulative drop counter (a u32 that wraps) as this datagram was queued.
        std::uint32_t drops = 0;
        std::memcpy(&drops, CMSG_DATA(c), sizeof(drops));
        kernel_drops_ = widenDropCount(drops, kernel_drops_);
      }
    }
    if (!have_stamp) ::gettimeofday(&stamp, nullptr);
    d.utime = static_cast<std::int64_t>(stamp.tv_sec) * 1'000'000 + stamp.tv_usec;
    handler_(d);
  }
}

bool UdpReceiver::datagramWaiting() {
  int bytes = 0;  // FIONREAD on a UDP socket: the size of the next datagram, 0 when none waits
  return ::ioctl(socket_.native_handle(), FIONREAD, &bytes) == 0 && bytes > 0;
}

std::uint64_t UdpReceiver::kernelDrops() {
  // SO_MEMINFO (Linux 4.6) fills SK_MEMINFO_VARS u32 values, the drop counter among them.
  std::uint32_t meminfo[SK_MEMINFO_VARS] = {};
  socklen_t len = sizeof(meminfo);
  if (::getsockopt(socket_.native_handle(), SOL_SOCKET, SO_MEMINFO, meminfo, &len) == 0 &&
      len >= (SK_MEMINFO_DROPS + 1) * sizeof(std::uint32_t))
    kernel_drops_ = widenDropCount(meminfo[SK_MEMINFO_DROPS], kernel_drops_);
  return kernel_drops_;
}

}  // namespace ogf::driver_sources
