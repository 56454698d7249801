// Reads UDP datagrams out of a capture file through libpcap (classic pcap in either byte order and
// precision, and pcapng where libpcap reads it). A truncated or corrupt file ends the reading with a
// message while every record before the damage has been delivered.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "ogf/driver_sources/link_layer.hpp"
#include "ogf/common/result.hpp"

struct pcap;

namespace ogf::driver_sources {

enum class ReadStatus : std::uint8_t {
  Datagram,  // `record.datagram` holds a UDP datagram
  Skipped,   // a record that is not IPv4/UDP, a fragment or a cut-short frame: see record.kind
  End,       // clean end of file
  Error      // the file is damaged here (error() says how); nothing more can be read
};

struct PcapRecord {
  FrameKind kind = FrameKind::NotUdp;
  UdpDatagram datagram;
  std::int64_t index = 0;  // 0-based record number in the file
};

class PcapFileReader {
 public:
  static ogf::Result<std::unique_ptr<PcapFileReader>> open(const std::filesystem::path& path);
  // Reads from an open stream (tests and fuzzing use fmemopen); the reader closes it.
  static ogf::Result<std::unique_ptr<PcapFileReader>> open(std::FILE* stream, std::string name);
  ~PcapFileReader();
  PcapFileReader(const PcapFileReader&) = delete;
  PcapFileReader& operator=(const PcapFileReader&) = delete;

  ReadStatus next(PcapRecord& record);
  const std::string& error() const { return error_; }
  int linkType() const { return link_type_; }
  std::int64_t records() const { return records_; }
  const std::string& name() const { return name_; }

 private:
  PcapFileReader(pcap* handle, std::string name);
  pcap* handle_;
  std::string name_;
  std::string error_;
  int link_type_ = 0;
  std::int64_t records_ = 0;
  bool nanosecond_ = false;
};

}  // namespace ogf::driver_sources
