// ogf-decode: decodes a Velodyne capture file (pcap, a packets LCM log or a ROS 2 bag) into scans with the
// driver's own library and prints one line per scan, then totals; optionally writes every point as CSV or
// binary PLY.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <string>

#include "ogf/common/command_line.hpp"
#include "ogf/log_io/packet_log.hpp"
#include "ogf/driver_sources/pcap_file_reader.hpp"
#include "ogf/rosbag/bag_packets.hpp"
#include "ogf/rosbag/ros_messages.hpp"
#include "ogf/velodyne/calibration.hpp"
#include "ogf/velodyne/packet_stream.hpp"
#include "ogf/decode/point_writers.hpp"

namespace {

namespace ov = ogf::velodyne;
namespace os = ogf::driver_sources;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Decodes a Velodyne capture (pcap or pcapng, an LCM log of raw packets, or a ROS 2 bag) into scans and\n"
      "prints one line per scan:\n"
      "  scan <i> points <n> packets <k> lost <l>\n"
      "then a totals line. Points are in the sensor frame, REP-103 (x forward, y left, z up, metres).\n"
      "CSV columns: scan,x,y,z,intensity,ring,laser_id,azimuth_deg,distance_m,time_s,return_type\n"
      "  distance_m is the raw distance (count x resolution), azimuth_deg the interpolated azimuth of the\n"
      "  firing, time_s the firing time in seconds RELATIVE TO THE SCAN START (device time of its first\n"
      "  firing), return_type one of strongest, last, both."};
  std::string pcap_path, lcm_log_path, bag_path, packets_topic, packets_channel = "VELODYNE_PACKETS",
      calib_path, model_name, return_mode_name,
      csv_path, ply_path;
  double min_range = 0.4, max_range = 250.0, cut_angle = 0.0;
  int data_port = 2368, position_port = 8308;
  bool quiet = false;
  auto* pcap_opt = app.add_option("--pcap", pcap_path, "Capture file to decode");
  auto* log_opt = app.add_option("--lcm-log", lcm_log_path,
                                 "LCM log to decode: the raw packet batches ogf-driver published (--packets-channel)");
  auto* bag_opt = app.add_option("--rosbag2", bag_path,
                                 "ROS 2 bag folder (or one .db3) to decode: its velodyne_msgs/msg/VelodyneScan "
                                 "packets");
  pcap_opt->excludes(log_opt)->excludes(bag_opt);
  log_opt->excludes(bag_opt);
  app.add_option("--packets-topic", packets_topic, "VelodyneScan topic of --rosbag2 (default: the only one)")
      ->needs(bag_opt);
  app.add_option("--packets-channel", packets_channel, "Channel of the raw packet batches in --lcm-log")
      ->capture_default_str();
  app.add_option("--calib", calib_path,
                 "Calibration: VeloView XML or ROS YAML (default: the model's nominal table)");
  app.add_option("--model", model_name, "VLP-16, VLP-16-HiRes, VLP-32C or HDL-32E (default: detected)");
  app.add_option(
         "--return-mode", return_mode_name,
         "strongest, last or dual (default: from each packet; strongest/last on dual data keep that return)")
      ->check(CLI::IsMember({"strongest", "last", "dual"}));
  app.add_option("--min-range", min_range,
                 "Drop returns closer than this, metres (0 keeps every non-zero return)")
      ->capture_default_str()->check(ogf::cli::nonNegative());
  app.add_option("--max-range", max_range, "Drop returns farther than this, metres")->capture_default_str()
      ->check(ogf::cli::positive());
  app.add_option("--cut-angle", cut_angle, "Azimuth where scans are cut, degrees clockwise from x")
      ->capture_default_str()->check(ogf::cli::between(-360, 360));
  app.add_option("--csv", csv_path, "Write every point to this CSV file");
  app.add_option("--ply", ply_path, "Write every point to this binary PLY file");
  app.add_option("--data-port", data_port, "UDP destination port of data packets")->capture_default_str()
      ->check(ogf::cli::between(1, 65535));
  app.add_option("--position-port", position_port, "UDP destination port of position packets")
      ->capture_default_str()->check(ogf::cli::between(1, 65535));
  app.add_flag("--quiet", quiet, "Print only the totals line");
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (pcap_path.empty() && lcm_log_path.empty() && bag_path.empty()) {
    std::fprintf(stderr, "ogf-decode: give --pcap FILE, --lcm-log FILE or --rosbag2 DIR\n");
    return ogf::cli::kExitUsage;
  }

  ov::StreamConfig config;
  if (!model_name.empty()) {
    config.model = ov::parseModelName(model_name);
    if (!config.model) {
      std::fprintf(stderr,
                   "ogf-decode: --model: unknown model '%s' (VLP-16, VLP-16-HiRes, VLP-32C, HDL-32E)\n",
                   model_name.c_str());
      return 2;
    }
  }
  if (!return_mode_name.empty()) config.return_mode = ov::parseReturnModeName(return_mode_name);
  if (!calib_path.empty()) {
    auto calib = ov::loadCalibrationFile(calib_path);
    if (!calib) {
      std::fprintf(stderr, "ogf-decode: --calib: %s\n", calib.error().message.c_str());
      return ogf::cli::exitCodeFor(calib.error());
    }
    config.calibration = std::move(*calib);
  }
  config.min_range_m = min_range;
  config.max_range_m = max_range;
  config.assembler.cut_angle_deg = cut_angle;
  auto stream = ov::PacketStream::create(config);
  if (!stream) {
    std::fprintf(stderr, "ogf-decode: %s\n", stream.error().message.c_str());
    return ogf::cli::exitCodeFor(stream.error());
  }
  std::optional<ogf::tools::CsvPointWriter> csv;
  if (!csv_path.empty()) {
    csv.emplace(csv_path);
    if (!csv->ok()) {
      std::fprintf(stderr, "ogf-decode: --csv: %s\n", csv->error().c_str());
      return 1;
    }
  }
  std::optional<ogf::tools::PlyPointWriter> ply;
  if (!ply_path.empty()) ply.emplace(ply_path);

  std::int64_t total_points = 0, total_packets = 0, total_lost = 0;
  stream->setScanSink([&](const ov::Scan& scan) {
    if (!quiet)
      std::printf("scan %lld points %zu packets %d lost %d\n", static_cast<long long>(scan.seq),
                  scan.points.size(), scan.packets_received, scan.packets_lost);
    total_points += static_cast<std::int64_t>(scan.points.size());
    total_packets += scan.packets_received;
    total_lost += scan.packets_lost;
    if (csv) csv->write(scan);
    if (ply) ply->write(scan);
  });

  std::int64_t other_records = 0, fragments = 0, cut_short = 0, other_ports = 0;
  if (!lcm_log_path.empty()) {
    auto counts = ogf::log_io::readPacketLog(lcm_log_path, packets_channel, [&](const ogf::log_io::LoggedPacket& p) {
      if (p.port == data_port)
        stream->addDataPacket(p.payload, p.host_utime);
      else if (p.port == position_port)
        stream->addPositionPacket(p.payload, p.host_utime);
      else
        ++other_ports;
    });
    if (!counts) {
      std::fprintf(stderr, "ogf-decode: %s\n", counts.error().message.c_str());
      return ogf::cli::kExitFailure;
    }
    stream->finish();
    for (const auto& p : counts->problems) std::fprintf(stderr, "ogf-decode: warning: %s\n", p.c_str());
    if (counts->batches == 0)
      std::fprintf(stderr, "ogf-decode: warning: %s: no packet batches on %s\n", lcm_log_path.c_str(),
                   packets_channel.c_str());
    if (const auto gaps = counts->gaps.summary(lcm_log_path + ": " + packets_channel + " batches"); !gaps.empty())
      std::fprintf(stderr, "ogf-decode: warning: %s\n", gaps.c_str());
  } else if (!bag_path.empty()) {
    auto bag = ogf::rosbag::Rosbag2Storage::open(bag_path);
    if (!bag) {
      std::fprintf(stderr, "ogf-decode: %s\n", bag.error().message.c_str());
      return ogf::cli::kExitFailure;
    }
    if (const auto found = bag->whereFound(); !found.empty()) std::fprintf(stderr, "ogf-decode: %s\n", found.c_str());
    if (const auto others = ogf::rosbag::undecodedTopicsSummary(bag->topics()); !others.empty())
      std::fprintf(stderr, "ogf-decode: %s: not read (types ogf does not decode): %s\n", bag_path.c_str(),
                   others.c_str());
    auto topic = ogf::rosbag::choosePacketTopic(*bag, packets_topic);
    if (!topic) {
      std::fprintf(stderr, "ogf-decode: --packets-topic: %s\n", topic.error().message.c_str());
      return ogf::cli::kExitUsage;
    }
    if (*topic) {
      auto counts = ogf::rosbag::readBagPackets(*bag, **topic, [&](const ogf::rosbag::BagPacket& p) {
        stream->addDataPacket(p.payload, p.host_utime);
      });
      if (!counts) {
        std::fprintf(stderr, "ogf-decode: %s\n", counts.error().message.c_str());
        return ogf::cli::kExitFailure;
      }
      for (const auto& p : counts->problems) std::fprintf(stderr, "ogf-decode: warning: %s\n", p.c_str());
      if (const auto gaps = counts->gaps.summary(bag_path + ": " + **topic + " messages"); !gaps.empty())
        std::fprintf(stderr, "ogf-decode: warning: %s\n", gaps.c_str());
    } else {
      std::fprintf(stderr, "ogf-decode: warning: %s: no %s topic\n", bag_path.c_str(),
                   std::string(ogf::rosbag::kVelodyneScanType).c_str());
    }
    stream->finish();
  } else {
    auto reader = os::PcapFileReader::open(pcap_path);
    if (!reader) {
      std::fprintf(stderr, "ogf-decode: %s\n", reader.error().message.c_str());
      return ogf::cli::kExitFailure;
    }
    os::PcapRecord record;
    os::ReadStatus status;
    while ((status = (*reader)->next(record)) != os::ReadStatus::End && status != os::ReadStatus::Error) {
      if (status == os::ReadStatus::Skipped) {
        if (record.kind == os::FrameKind::Fragment)
          ++fragments;
        else if (record.kind == os::FrameKind::Truncated)
          ++cut_short;
        else
          ++other_records;
        continue;
      }
      const os::UdpDatagram& d = record.datagram;
      if (d.destination_port == data_port)
        stream->addDataPacket(d.payload, d.utime);
      else if (d.destination_port == position_port)
        stream->addPositionPacket(d.payload, d.utime);
      else
        ++other_ports;
    }
    stream->finish();
    if (status == os::ReadStatus::Error)
      std::fprintf(stderr, "ogf-decode: warning: %s; kept the %lld records before it\n",
                   (*reader)->error().c_str(), static_cast<long long>((*reader)->records()));
  }
  const ov::StreamCounters& c = stream->counters();
  const auto model = stream->model();
  const auto mode = stream->returnMode();
  std::printf(
      "total scans %lld points %lld packets %lld lost %lld position %lld bad_size %lld bad_block_flag %lld "
      "bad_other %lld other_port %lld fragments %lld cut_short %lld model %s return_mode %s\n",
      static_cast<long long>(c.scans), static_cast<long long>(total_points),
      static_cast<long long>(c.data_packets), static_cast<long long>(total_lost),
      static_cast<long long>(c.position_packets), static_cast<long long>(c.bad_size),
      static_cast<long long>(c.bad_block_flag), static_cast<long long>(c.bad_other),
      static_cast<long long>(other_ports), static_cast<long long>(fragments),
      static_cast<long long>(cut_short), model ? std::string(ov::modelName(*model)).c_str() : "unknown",
      mode ? std::string(ov::returnModeName(*mode)).c_str() : "unknown");
  // Which angles the points were computed with: a silent default would hide a missing --calib.
  if (!calib_path.empty())
    std::fprintf(stderr, "ogf-decode: calibration: %s (--calib)\n", calib_path.c_str());
  else if (model)
    std::fprintf(stderr,
                 "ogf-decode: calibration: the nominal %s table, built in (no --calib; give the sensor's own file "
                 "for its exact angles)\n",
                 std::string(ov::modelName(*model)).c_str());
  else
    std::fprintf(stderr, "ogf-decode: calibration: none: no data packet told the sensor model\n");
  if (const auto& pos = stream->lastPosition()) {
    std::printf("position pps %d gps_fix %s nmea %.*s\n", static_cast<int>(pos->pps),
                pos->gpsFixValid() ? "valid" : "none", static_cast<int>(pos->nmea().size()),
                pos->nmea().data());
  }
  int rc = 0;
  if (csv && !csv->close()) {
    std::fprintf(stderr, "ogf-decode: --csv: %s\n", csv->error().c_str());
    rc = 1;
  }
  if (ply && !ply->close()) {
    std::fprintf(stderr, "ogf-decode: --ply: %s\n", ply->error().c_str());
    rc = 1;
  }
  (void)total_packets;
  return rc;
}
