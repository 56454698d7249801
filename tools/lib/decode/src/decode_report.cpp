#include "ogf/decode/decode_report.hpp"

#include <fmt/format.h>

namespace ogf::decode {

void ScanTotals::add(const velodyne::Scan& scan) {
  points += static_cast<std::int64_t>(scan.points.size());
  packets += scan.packets_received;
  lost += scan.packets_lost;
}

std::string scanLine(const velodyne::Scan& scan) {
  return fmt::format("scan {} points {} packets {} lost {}", scan.seq, scan.points.size(),
                     scan.packets_received, scan.packets_lost);
}

std::string totalsLine(const velodyne::PacketStream& stream, const ScanTotals& scans,
                       const FeedCounts& feed) {
  const velodyne::StreamCounters& c = stream.counters();
  const auto model = stream.model();
  const auto mode = stream.returnMode();
  return fmt::format(
      "total scans {} points {} packets {} lost {} position {} bad_size {} bad_block_flag {} bad_other {} "
      "other_port {} fragments {} cut_short {} model {} return_mode {}",
      c.scans, scans.points, c.data_packets, scans.lost, c.position_packets, c.bad_size, c.bad_block_flag,
      c.bad_other, feed.other_ports, feed.fragments, feed.cut_short,
      model ? std::string(velodyne::modelName(*model)) : "unknown",
      mode ? std::string(velodyne::returnModeName(*mode)) : "unknown");
}

std::string calibrationNote(const std::string& calib_path, std::optional<velodyne::Model> model) {
  if (!calib_path.empty()) return "calibration: " + calib_path + " (--calib)";
  if (model)
    return "calibration: the nominal " + std::string(velodyne::modelName(*model)) +
           " table, built in (no --calib; give the sensor's own file for its exact angles)";
  return "calibration: none: no data packet told the sensor model";
}

}  // namespace ogf::decode
