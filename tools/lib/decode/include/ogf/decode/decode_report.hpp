// The lines ogf-decode prints: one per scan, the totals of the whole input, and which angles the points
// were computed with (a silent default would hide a missing --calib).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "ogf/decode/recorded_packets.hpp"
#include "ogf/velodyne/model.hpp"
#include "ogf/velodyne/packet_stream.hpp"
#include "ogf/velodyne/scan.hpp"

namespace ogf::decode {

// The scans' own counts, summed.
struct ScanTotals {
  std::int64_t points = 0;
  std::int64_t packets = 0;  // data packets the scans were assembled from
  std::int64_t lost = 0;     // packets missing inside scans

  void add(const velodyne::Scan& scan);
};

// "scan <i> points <n> packets <k> lost <l>"
std::string scanLine(const velodyne::Scan& scan);

// "total scans ... model VLP-16 return_mode strongest": the decoder's counters, the scans' totals and what
// the input held besides packets.
std::string totalsLine(const velodyne::PacketStream& stream, const ScanTotals& scans, const FeedCounts& feed);

// "calibration: <file> (--calib)", the nominal table of the detected model, or none.
std::string calibrationNote(const std::string& calib_path, std::optional<velodyne::Model> model);

}  // namespace ogf::decode
