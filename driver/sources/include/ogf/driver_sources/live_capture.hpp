// Live capture of the sensor's UDP traffic on a network interface through libpcap (needs only
// CAP_NET_RAW), watched from a Boost.Asio io_context through libpcap's selectable descriptor. Useful when
// the sensor's broadcast should be seen without binding its ports, or on a mirror port.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <functional>
#include <string>

#include "ogf/driver_sources/link_layer.hpp"
#include "ogf/common/result.hpp"

struct pcap;
struct pcap_pkthdr;

namespace ogf::driver_sources {

class LiveCapture {
 public:
  // Every captured frame, with its kind; `record.datagram` is valid for Udp frames.
  using Handler = std::function<void(FrameKind kind, const UdpDatagram& datagram)>;

  // Opens `interface` with a kernel filter for UDP to `data_port` or `position_port`.
  static ogf::Result<std::unique_ptr<LiveCapture>> open(boost::asio::io_context& io,
                                                             const std::string& interface,
                                                             std::uint16_t data_port,
                                                             std::uint16_t position_port, Handler handler);
  ~LiveCapture();
  LiveCapture(const LiveCapture&) = delete;
  LiveCapture& operator=(const LiveCapture&) = delete;

  // Frames the kernel dropped (pcap_stats ps_drop).
  std::uint64_t kernelDrops() const;

 private:
  LiveCapture(boost::asio::io_context& io, pcap* handle, int fd, Handler handler);
  void arm();
  static void onFrame(unsigned char* user, const ::pcap_pkthdr* header, const unsigned char* data);

  pcap* handle_;
  int link_type_;
  boost::asio::posix::stream_descriptor descriptor_;
  Handler handler_;
};

}  // namespace ogf::driver_sources
