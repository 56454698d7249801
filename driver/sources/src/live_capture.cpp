#include "ogf/driver_sources/live_capture.hpp"

#include <pcap/pcap.h>
#include <unistd.h>

namespace ogf::driver_sources {

LiveCapture::LiveCapture(boost::asio::io_context& io, pcap* handle, int fd, Handler handler)
    : handle_(handle), link_type_(pcap_datalink(handle)), descriptor_(io, fd), handler_(std::move(handler)) {}

LiveCapture::~LiveCapture() {
  boost::system::error_code ec;
  descriptor_.cancel(ec);
  descriptor_.close(ec);
  pcap_close(handle_);
}

ogf::Result<std::unique_ptr<LiveCapture>> LiveCapture::open(boost::asio::io_context& io,
                                                                 const std::string& interface,
                                                                 std::uint16_t data_port,
                                                                 std::uint16_t position_port,
                                                                 Handler handler) {
  char error[PCAP_ERRBUF_SIZE] = {};
  pcap* handle = pcap_create(interface.c_str(), error);
  if (handle == nullptr) return ogf::Error::io("pcap-live " + interface + ": " + error);
  pcap_set_snaplen(handle, 65535);
  pcap_set_promisc(handle, 0);
  pcap_set_immediate_mode(handle, 1);
  pcap_set_buffer_size(handle, 8 * 1024 * 1024);
  pcap_set_tstamp_precision(handle, PCAP_TSTAMP_PRECISION_MICRO);
  if (pcap_activate(handle) < 0) {
    std::string why = pcap_geterr(handle);
    pcap_close(handle);
    return ogf::Error::io("pcap-live " + interface + ": " + why + " (needs CAP_NET_RAW)");
  }
  const std::string filter = "udp and (dst port " + std::to_string(data_port) + " or dst port " +
                             std::to_string(position_port) + ")";
  bpf_program program{};
  if (pcap_compile(handle, &program, filter.c_str(), 1, PCAP_NETMASK_UNKNOWN) != 0 ||
      pcap_setfilter(handle, &program) != 0) {
    std::string why = pcap_geterr(handle);
    pcap_freecode(&program);
    pcap_close(handle);
    return ogf::Error::io("pcap-live " + interface + ": filter '" + filter + "': " + why);
  }
  pcap_freecode(&program);
  if (pcap_setnonblock(handle, 1, error) != 0) {
    pcap_close(handle);
    return ogf::Error::io("pcap-live " + interface + ": " + error);
  }
  const int fd = pcap_get_selectable_fd(handle);
  if (fd < 0) {
    pcap_close(handle);
    return ogf::Error::io("pcap-live " + interface + ": no selectable descriptor");
  }
  std::unique_ptr<LiveCapture> capture(new LiveCapture(io, handle, ::dup(fd), std::move(handler)));
  capture->arm();
  return capture;
}

void LiveCapture::onFrame(unsigned char* user, const ::pcap_pkthdr* header, const unsigned char* data) {
  auto* self = reinterpret_cast<LiveCapture*>(user);
  LinkFrame frame = parseLinkFrame(self->link_type_, {data, header->caplen});
  frame.datagram.utime = static_cast<std::int64_t>(header->ts.tv_sec) * 1'000'000 + header->ts.tv_usec;
  self->handler_(frame.kind, frame.datagram);
}

void LiveCapture::arm() {
  descriptor_.async_wait(
      boost::asio::posix::stream_descriptor::wait_read, [this](const boost::system::error_code& ec) {
        if (ec) return;
        pcap_dispatch(handle_, 1024, &LiveCapture::onFrame, reinterpret_cast<unsigned char*>(this));
        arm();
      });
}

std::uint64_t LiveCapture::kernelDrops() const {
  pcap_stat stats{};
  if (pcap_stats(handle_, &stats) != 0) return 0;
  return stats.ps_drop;
}

}  // namespace ogf::driver_sources
