#include "ogf/driver_sources/udp_receiver.hpp"

#include <arpa/inet.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <boost/asio/ip/address.hpp>
#include <cerrno>
#include <cstring>

namespace ogf::driver_sources {

UdpReceiver::UdpReceiver(boost::asio::io_context& io, Handler handler)
    : socket_(io), handler_(std::move(handler)) {}

UdpReceiver::~UdpReceiver() {
  boost::system::error_code ec;
  socket_.close(ec);
}

velodyne::Result<std::unique_ptr<UdpReceiver>> UdpReceiver::open(boost::asio::io_context& io,
                                                                 const UdpReceiverConfig& config,
                                                                 Handler handler) {
  std::unique_ptr<UdpReceiver> r(new UdpReceiver(io, std::move(handler)));
  boost::system::error_code ec;
  const auto address = boost::asio::ip::make_address(config.bind_address, ec);
  if (ec) return velodyne::Error{"bind address '" + config.bind_address + "': " + ec.message()};
  const boost::asio::ip::udp::endpoint endpoint(address, config.port);
  const std::string where = config.bind_address + ":" + std::to_string(config.port);
  r->socket_.open(endpoint.protocol(), ec);
  if (ec) return velodyne::Error{"udp " + where + ": " + ec.message()};
  r->socket_.set_option(boost::asio::socket_base::reuse_address(true), ec);
  r->socket_.set_option(boost::asio::socket_base::receive_buffer_size(config.receive_buffer_bytes), ec);
  boost::asio::socket_base::receive_buffer_size granted;
  r->socket_.get_option(granted, ec);
  r->granted_buffer_ = granted.value();
  const int on = 1;
  ::setsockopt(r->socket_.native_handle(), SOL_SOCKET, SO_TIMESTAMP, &on, sizeof(on));
  r->socket_.bind(endpoint, ec);
  if (ec) return velodyne::Error{"udp " + where + ": bind: " + ec.message()};
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
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timeval))];
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
      }
    }
    if (!have_stamp) ::gettimeofday(&stamp, nullptr);
    d.utime = static_cast<std::int64_t>(stamp.tv_sec) * 1'000'000 + stamp.tv_usec;
    handler_(d);
  }
}

}  // namespace ogf::driver_sources
