#include "ogf/driver_sources/pcap_file_reader.hpp"

#include <pcap/pcap.h>

namespace ogf::driver_sources {

PcapFileReader::PcapFileReader(pcap* handle, std::string name) : handle_(handle), name_(std::move(name)) {
  link_type_ = pcap_datalink(handle_);
  nanosecond_ = pcap_get_tstamp_precision(handle_) == PCAP_TSTAMP_PRECISION_NANO;
}

PcapFileReader::~PcapFileReader() { pcap_close(handle_); }

ogf::Result<std::unique_ptr<PcapFileReader>> PcapFileReader::open(const std::filesystem::path& path) {
  char error[PCAP_ERRBUF_SIZE] = {};
  pcap* handle = pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_MICRO, error);
  if (handle == nullptr) {
    // libpcap names the file itself when it cannot open it ("<path>: No such file or directory").
    const std::string why = error;
    if (why.rfind(path.string() + ":", 0) == 0) return ogf::Error::io(why);
    return ogf::Error::io(path.string() + ": " + why);
  }
  return std::unique_ptr<PcapFileReader>(new PcapFileReader(handle, path.string()));
}

ogf::Result<std::unique_ptr<PcapFileReader>> PcapFileReader::open(std::FILE* stream, std::string name) {
  char error[PCAP_ERRBUF_SIZE] = {};
  pcap* handle = pcap_fopen_offline_with_tstamp_precision(stream, PCAP_TSTAMP_PRECISION_MICRO, error);
  if (handle == nullptr) {
    std::fclose(stream);
    return ogf::Error::io(name + ": " + error);
  }
  return std::unique_ptr<PcapFileReader>(new PcapFileReader(handle, std::move(name)));
}

ReadStatus PcapFileReader::next(PcapRecord& record) {
  if (!error_.empty()) return ReadStatus::Error;
  pcap_pkthdr* header = nullptr;
  const u_char* data = nullptr;
  const int rc = pcap_next_ex(handle_, &header, &data);
  if (rc == PCAP_ERROR_BREAK) return ReadStatus::End;
  if (rc != 1) {
    error_ = name_ + ": record " + std::to_string(records_) + ": " + pcap_geterr(handle_);
    return ReadStatus::Error;
  }
  record.index = records_++;
  const LinkFrame frame = parseLinkFrame(link_type_, {data, header->caplen});
  record.kind = frame.kind;
  record.datagram = frame.datagram;
  const std::int64_t fraction = nanosecond_ ? header->ts.tv_usec / 1000 : header->ts.tv_usec;
  record.datagram.utime = static_cast<std::int64_t>(header->ts.tv_sec) * 1'000'000 + fraction;
  return frame.kind == FrameKind::Udp ? ReadStatus::Datagram : ReadStatus::Skipped;
}

}  // namespace ogf::driver_sources
