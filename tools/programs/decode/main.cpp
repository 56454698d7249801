// ogf-decode: decodes a Velodyne capture file (pcap, a packets LCM log or a ROS 2 bag) into scans with the
// driver's own library and prints one line per scan, then totals; optionally writes every point as CSV or
// binary PLY. This file owns the command line, the printing and the exit code; the work is in
// ogf::decode (tools/lib/decode) and the driver's libraries.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "ogf/common/command_line.hpp"
#include "ogf/decode/decode_report.hpp"
#include "ogf/decode/point_writers.hpp"
#include "ogf/decode/recorded_packets.hpp"
#include "ogf/decode/stream_settings.hpp"
#include "ogf/rosbag/bag_packets.hpp"
#include "ogf/rosbag/ros_messages.hpp"
#include "ogf/velodyne/packet_stream.hpp"

namespace {

namespace ov = ogf::velodyne;
namespace od = ogf::decode;

struct Options {
  std::string pcap, lcm_log, rosbag2, packets_topic, packets_channel = "VELODYNE_PACKETS";
  od::StreamSettings stream;
  std::string csv, ply;
  od::Ports ports;
  bool quiet = false;
};

const char* const kDescription =
    "Decodes a Velodyne capture (pcap or pcapng, an LCM log of raw packets, or a ROS 2 bag) into scans and\n"
    "prints one line per scan:\n"
    "  scan <i> points <n> packets <k> lost <l>\n"
    "then a totals line. Points are in the sensor frame, REP-103 (x forward, y left, z up, metres).\n"
    "CSV columns: scan,x,y,z,intensity,ring,laser_id,azimuth_deg,distance_m,time_s,return_type\n"
    "  distance_m is the raw distance (count x resolution), azimuth_deg the interpolated azimuth of the\n"
    "  firing, time_s the firing time in seconds RELATIVE TO THE SCAN START (device time of its first\n"
    "  firing), return_type one of strongest, last, both.";

void defineCommandLine(CLI::App& app, Options& o) {
  app.description(kDescription);
  auto* pcap_opt = app.add_option("--pcap", o.pcap, "Capture file to decode");
  auto* log_opt =
      app.add_option("--lcm-log", o.lcm_log,
                     "LCM log to decode: the raw packet batches ogf-driver published (--packets-channel)");
  auto* bag_opt =
      app.add_option("--rosbag2", o.rosbag2,
                     "ROS 2 bag folder (sqlite3 or MCAP), or one .db3 or .mcap file, to decode: its "
                     "velodyne_msgs/msg/VelodyneScan "
                     "packets");
  pcap_opt->excludes(log_opt)->excludes(bag_opt);
  log_opt->excludes(bag_opt);
  app.add_option("--packets-topic", o.packets_topic,
                 "VelodyneScan topic of --rosbag2 (default: the only one)")
      ->needs(bag_opt);
  app.add_option("--packets-channel", o.packets_channel, "Channel of the raw packet batches in --lcm-log")
      ->capture_default_str();
  app.add_option("--calib", o.stream.calib_path,
                 "Calibration: VeloView XML or ROS YAML (default: the model's nominal table)");
  app.add_option("--model", o.stream.model_name,
                 "VLP-16, VLP-16-HiRes, VLP-32C or HDL-32E (default: detected)");
  app.add_option(
         "--return-mode", o.stream.return_mode_name,
         "strongest, last or dual (default: from each packet; strongest/last on dual data keep that return)")
      ->check(CLI::IsMember({"strongest", "last", "dual"}));
  app.add_option("--min-range", o.stream.min_range_m,
                 "Drop returns closer than this, metres (0 keeps every non-zero return)")
      ->capture_default_str()
      ->check(ogf::cli::nonNegative());
  app.add_option("--max-range", o.stream.max_range_m, "Drop returns farther than this, metres")
      ->capture_default_str()
      ->check(ogf::cli::positive());
  app.add_option("--cut-angle", o.stream.cut_angle_deg,
                 "Azimuth where scans are cut, degrees clockwise from x")
      ->capture_default_str()
      ->check(ogf::cli::between(-360, 360));
  app.add_option("--csv", o.csv, "Write every point to this CSV file");
  app.add_option("--ply", o.ply, "Write every point to this binary PLY file");
  app.add_option("--data-port", o.ports.data, "UDP destination port of data packets")
      ->capture_default_str()
      ->check(ogf::cli::between(1, 65535));
  app.add_option("--position-port", o.ports.position, "UDP destination port of position packets")
      ->capture_default_str()
      ->check(ogf::cli::between(1, 65535));
  app.add_flag("--quiet", o.quiet, "Print only the totals line");
}

// Each step returns nullopt to go on, or the exit code ogf-decode stops with (its reason printed).
using Stop = std::optional<int>;

// "ogf-decode: <message>" on stderr.
void say(const std::string& message) { std::fprintf(stderr, "ogf-decode: %s\n", message.c_str()); }

void printWarnings(const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) std::fprintf(stderr, "ogf-decode: warning: %s\n", w.c_str());
}

// The decoder the flags ask for.
Stop createStream(const Options& o, std::optional<ov::PacketStream>& stream) {
  auto config = od::streamConfig(o.stream);
  if (!config) {
    say(config.error().message);
    return ogf::cli::exitCodeFor(config.error());
  }
  auto created = ov::PacketStream::create(*config);
  if (!created) {
    say(created.error().message);
    return ogf::cli::exitCodeFor(created.error());
  }
  stream.emplace(std::move(*created));
  return std::nullopt;
}

// The --csv and --ply writers; stops when the CSV file cannot be created (the PLY is written at the end).
struct PointOutputs {
  std::optional<ogf::tools::CsvPointWriter> csv;
  std::optional<ogf::tools::PlyPointWriter> ply;

  void write(const ov::Scan& scan) {
    if (csv) csv->write(scan);
    if (ply) ply->write(scan);
  }
  // The exit code after closing both: 1 when one could not be written.
  int close() {
    int rc = ogf::cli::kExitOk;
    if (csv && !csv->close()) {
      say("--csv: " + csv->error());
      rc = ogf::cli::kExitFailure;
    }
    if (ply && !ply->close()) {
      say("--ply: " + ply->error());
      rc = ogf::cli::kExitFailure;
    }
    return rc;
  }
};

Stop openOutputs(const Options& o, PointOutputs& out) {
  if (!o.csv.empty()) {
    out.csv.emplace(o.csv);
    if (!out.csv->ok()) {
      say("--csv: " + out.csv->error());
      return ogf::cli::kExitFailure;
    }
  }
  if (!o.ply.empty()) out.ply.emplace(o.ply);
  return std::nullopt;
}

// After a capture file or a log: the scan in progress out, then what the input lacked or where it was
// damaged.
Stop finishInput(ogf::Result<od::FeedCounts> counts, ov::PacketStream& stream, od::FeedCounts& fed) {
  if (!counts) {
    say(counts.error().message);
    return ogf::cli::kExitFailure;
  }
  stream.finish();
  printWarnings(counts->warnings);
  fed = std::move(*counts);
  return std::nullopt;
}

// A bag: where it was found, the topics not read, then the packets of its VelodyneScan topic.
Stop decodeBag(const Options& o, ov::PacketStream& stream, od::FeedCounts& fed) {
  auto bag = ogf::rosbag::Rosbag2Storage::open(o.rosbag2);
  if (!bag) {
    say(bag.error().message);
    return ogf::cli::kExitFailure;
  }
  if (const auto found = bag->whereFound(); !found.empty()) say(found);
  if (const auto others = ogf::rosbag::undecodedTopicsSummary(bag->topics()); !others.empty())
    say(o.rosbag2 + ": not read (types ogf does not decode): " + others);
  auto topic = ogf::rosbag::choosePacketTopic(*bag, o.packets_topic);
  if (!topic) {
    say("--packets-topic: " + topic.error().message);
    return ogf::cli::kExitUsage;
  }
  if (*topic) {
    auto counts = od::feedBagPackets(*bag, o.rosbag2, **topic, stream);
    if (!counts) {
      say(counts.error().message);
      return ogf::cli::kExitFailure;
    }
    printWarnings(counts->warnings);
    fed = std::move(*counts);
  } else {
    printWarnings({o.rosbag2 + ": no " + std::string(ogf::rosbag::kVelodyneScanType) + " topic"});
  }
  stream.finish();
  return std::nullopt;
}

Stop decodeInput(const Options& o, ov::PacketStream& stream, od::FeedCounts& fed) {
  if (!o.lcm_log.empty())
    return finishInput(od::feedPacketLog(o.lcm_log, o.packets_channel, o.ports, stream), stream, fed);
  if (!o.rosbag2.empty()) return decodeBag(o, stream, fed);
  return finishInput(od::feedPcap(o.pcap, o.ports, stream), stream, fed);
}

// The totals line, the calibration the points were computed with, and the last position packet.
void printTotals(const Options& o, const ov::PacketStream& stream, const od::ScanTotals& scans,
                 const od::FeedCounts& fed) {
  std::printf("%s\n", od::totalsLine(stream, scans, fed).c_str());
  say(od::calibrationNote(o.stream.calib_path, stream.model()));
  if (const auto& pos = stream.lastPosition()) {
    std::printf("position pps %d gps_fix %s nmea %.*s\n", static_cast<int>(pos->pps),
                pos->gpsFixValid() ? "valid" : "none", static_cast<int>(pos->nmea().size()),
                pos->nmea().data());
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app;
  defineCommandLine(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (o.pcap.empty() && o.lcm_log.empty() && o.rosbag2.empty()) {
    say("give --pcap FILE, --lcm-log FILE or --rosbag2 DIR");
    return ogf::cli::kExitUsage;
  }
  std::optional<ov::PacketStream> stream;
  if (const Stop stop = createStream(o, stream)) return *stop;
  PointOutputs outputs;
  if (const Stop stop = openOutputs(o, outputs)) return *stop;
  od::ScanTotals scans;
  stream->setScanSink([&](const ov::Scan& scan) {
    if (!o.quiet) std::printf("%s\n", od::scanLine(scan).c_str());
    scans.add(scan);
    outputs.write(scan);
  });
  od::FeedCounts fed;
  if (const Stop stop = decodeInput(o, *stream, fed)) return *stop;
  printTotals(o, *stream, scans, fed);
  return outputs.close();
}
