// Receives UDP datagrams on one port through Boost.Asio, with the kernel receive timestamp (SO_TIMESTAMP)
// of each, and asks for a large SO_RCVBUF so a burst at the sensor's packet rate is not dropped by the
// kernel. Non-blocking: datagrams are drained on each readiness notification. Datagrams the kernel dropped
// on this socket (receive buffer full) are counted: SO_RXQ_OVFL hands the socket's drop counter to every
// received datagram (socket(7)), and SO_MEMINFO reads it at any moment, so drops after the last datagram
// are counted too.
#pragma once

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <functional>
#include <string>

#include "ogf/driver_sources/udp_datagram.hpp"
#include "ogf/common/result.hpp"

namespace ogf::driver_sources {

struct UdpReceiverConfig {
  std::string bind_address = "0.0.0.0";
  std::uint16_t port = 2368;
  int receive_buffer_bytes = 8 * 1024 * 1024;
};

class UdpReceiver {
 public:
  using Handler = std::function<void(const UdpDatagram&)>;

  // Binds and starts receiving; fails with the address and the system's reason.
  static ogf::Result<std::unique_ptr<UdpReceiver>> open(boost::asio::io_context& io,
                                                             const UdpReceiverConfig& config,
                                                             Handler handler);
  ~UdpReceiver();
  UdpReceiver(const UdpReceiver&) = delete;
  UdpReceiver& operator=(const UdpReceiver&) = delete;

  // The receive buffer the kernel granted, bytes, comparable with what was asked: the size asked for, or
  // net.core.rmem_max when that is less (Linux caps it there; the raw getsockopt reports twice this).
  int grantedReceiveBuffer() const { return granted_buffer_; }
  std::uint16_t port() const { return port_; }
  // Whether a datagram waits in the kernel's queue, not yet handed to the handler (the process was
  // descheduled or busy): the stream is not idle then.
  bool datagramWaiting();
  // Datagrams longer than the buffer (cut by the kernel): counted, not delivered.
  std::uint64_t oversized() const { return oversized_; }
  // Datagrams the kernel dropped on this socket since it was opened (its receive buffer was full), as of
  // now: the latest of SO_RXQ_OVFL's count and SO_MEMINFO's (the same kernel counter, sk_drops).
  std::uint64_t kernelDrops();

 private:
  UdpReceiver(boost::asio::io_context& io, Handler handler);
  void arm();
  void drain();

  boost::asio::ip::udp::socket socket_;
  Handler handler_;
  int granted_buffer_ = 0;
  std::uint16_t port_ = 0;
  std::uint64_t oversized_ = 0;
  std::uint64_t kernel_drops_ = 0;
  std::array<std::uint8_t, 65536> buffer_{};
};

}  // namespace ogf::driver_sources
