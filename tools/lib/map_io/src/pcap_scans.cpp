#include "ogf/map_io/pcap_scans.hpp"

#include <fmt/format.h>

#include <ogf/driver_sources/pcap_file_reader.hpp>
#include <ogf/velodyne/calibration.hpp>
#include <ogf/velodyne/packet_stream.hpp>
#include <string>
#include <vector>

#include "ogf/log_io/packet_log.hpp"
#include "ogf/rosbag/bag_packets.hpp"

namespace ogf::map_io {
namespace {

namespace ov = ogf::velodyne;
namespace os = ogf::driver_sources;

// Bytes a capture spends on one data packet: 16 (record header) + 42 (Ethernet, IPv4, UDP) + 1206.
constexpr double kBytesPerPacket = 1264.0;

}  // namespace

namespace {

// A decoder configured as `config` says, whose scans go to `visit` and are counted in `counts`.
Result<ov::PacketStream> decoderFor(const PcapScanConfig& config, PcapScanCounts& counts,
                                    const std::function<void(const ScanRecord&)>& visit,
                                    const std::function<void()>& after_scan) {
  ov::StreamConfig stream_config;
  if (config.calibration) {
    auto calib = ov::loadCalibrationFile(*config.calibration);
    if (!calib) return Error{"--calib: " + calib.error().message};
    stream_config.calibration = std::move(*calib);
  }
  stream_config.min_range_m = config.min_range_m;
  stream_config.max_range_m = config.max_range_m;
  auto stream = ov::PacketStream::create(stream_config);
  if (!stream) return Error{stream.error().message};
  stream->setScanSink([&counts, &visit, after_scan, record = ScanRecord{}](const ov::Scan& scan) mutable {
    assignScan(scan, record);
    ++counts.scans;
    counts.points += static_cast<std::int64_t>(scan.points.size());
    counts.packets_lost += scan.packets_lost;
    visit(record);
    if (after_scan) after_scan();
  });
  return stream;
}

void finishCounts(const ov::PacketStream& stream, PcapScanCounts& counts) {
  const ov::StreamCounters& c = stream.counters();
  counts.data_packets = c.data_packets;
  counts.bad_packets = c.bad_size + c.bad_block_flag + c.bad_other;
  if (const auto& file = stream.config().calibration) {
    counts.calibration = fmt::format("{} (--calib)", file->source);
  } else if (const auto model = stream.model()) {
    counts.calibration = fmt::format("the nominal {} table, built in (no --calib; give the sensor's own file for "
                                     "its exact angles)",
                                     ov::modelName(*model));
  } else {
    counts.calibration = "none: no data packet told the sensor model";
  }
}

// The end of a recording's packets: the last scan out, the decoder's counts, what the reader skipped and
// the recording's gaps.
void finishRecording(ov::PacketStream& stream, PcapScanCounts& counts,
                     const std::vector<std::string>& problems, std::string gaps) {
  stream.finish();
  finishCounts(stream, counts);
  for (const auto& p : problems) counts.warning += (counts.warning.empty() ? "" : "; ") + p;
  counts.gaps = std::move(gaps);
}

}  // namespace

Result<PcapScanCounts> readPcapScans(const std::filesystem::path& path, const PcapScanConfig& config,
                                     const std::function<void(const ScanRecord&)>& visit,
                                     const std::function<void(double)>& progress) {
  auto reader = os::PcapFileReader::open(path);
  if (!reader) return Error{reader.error().message};
  std::error_code ec;
  const auto file_size = std::filesystem::file_size(path, ec);
  const double expected_records = ec ? 0.0 : static_cast<double>(file_size) / kBytesPerPacket;

  PcapScanCounts counts;
  auto stream = decoderFor(config, counts, visit, [&] {
    if (progress && expected_records > 0.0)
      progress(std::min(1.0, static_cast<double>((*reader)->records()) / expected_records));
  });
  if (!stream) return stream.error();
  os::PcapRecord rec;
  os::ReadStatus status;
  while ((status = (*reader)->next(rec)) != os::ReadStatus::End && status != os::ReadStatus::Error) {
    if (status != os::ReadStatus::Datagram) continue;
    const os::UdpDatagram& d = rec.datagram;
    if (d.destination_port == config.data_port) stream->addDataPacket(d.payload, d.utime);
    else if (d.destination_port == config.position_port) stream->addPositionPacket(d.payload, d.utime);
  }
  stream->finish();
  if (status == os::ReadStatus::Error)
    counts.warning = fmt::format("{}; kept the {} records before it", (*reader)->error(), (*reader)->records());
  finishCounts(*stream, counts);
  return counts;
}

Result<PcapScanCounts> readLcmLogPacketScans(const std::filesystem::path& path, const std::string& channel,
                                             const PcapScanConfig& config,
                                             const std::function<void(const ScanRecord&)>& visit,
                                             const std::function<void(double)>& progress) {
  PcapScanCounts counts;
  auto stream = decoderFor(config, counts, visit, {});
  if (!stream) return stream.error();
  auto log = log_io::readPacketLog(
      path, channel,
      [&](const log_io::LoggedPacket& p) {
        if (p.port == config.data_port) stream->addDataPacket(p.payload, p.host_utime);
        else if (p.port == config.position_port) stream->addPositionPacket(p.payload, p.host_utime);
      },
      progress);
  if (!log) return log.error();
  finishRecording(*stream, counts, log->problems,
                  log->gaps.summary(path.string() + ": " + channel + " batches"));
  return counts;
}

Result<PcapScanCounts> readRosbagPacketScans(const rosbag::Rosbag2Storage& bag, const std::string& topic,
                                             const PcapScanConfig& config,
                                             const std::function<void(const ScanRecord&)>& visit,
                                             const std::function<void(double)>& progress) {
  PcapScanCounts counts;
  auto stream = decoderFor(config, counts, visit, {});
  if (!stream) return stream.error();
  auto read = rosbag::readBagPackets(
      bag, topic, [&](const rosbag::BagPacket& p) { stream->addDataPacket(p.payload, p.host_utime); },
      progress);
  if (!read) return read.error();
  finishRecording(*stream, counts, read->problems,
                  read->gaps.summary(bag.path().string() + ": " + topic + " messages"));
  return counts;
}

}  // namespace ogf::map_io
