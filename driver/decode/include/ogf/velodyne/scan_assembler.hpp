// Turns decoded packets into scans: cuts at the configured azimuth at the firing that crosses it (inside
// a packet, so no scan holds more than 360 degrees), detects lost packets from device-time gaps (packets
// carry no sequence number; docs/wire-format.md §4.4) and ends a scan at a long gap. Buffers are reserved
// once, so steady-state assembly does not allocate.
//
// A pause in the stream (no packet for `pause_us` of host receive time: the sensor stopped, its cable was
// out, a replay paused) is never bridged by emitting the scan held open before it with the first packet
// after it: that scan would reach subscribers long after its own time, dated before the time they have
// since followed. The scan open at a pause is dropped instead, counted in scansDroppedAtPause(), and
// takes no sequence number. A program reading a live stream calls flush() once the stream has been idle
// for a few scan periods, well under `pause_us` (ogf-driver does), so that scan is emitted promptly with
// its own times and nothing is dropped there; offline readers of a capture with a pause drop it.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "ogf/velodyne/packet_decoder.hpp"
#include "ogf/velodyne/scan.hpp"

namespace ogf::velodyne {

struct ScanAssemblerConfig {
  double cut_angle_deg = 0.0;
  // A device-time gap longer than this ends the scan instead of counting lost packets. 20 ms is 15 VLP-16
  // packets: less than half a turn at 1200 rpm, so the cut can still be found after a shorter gap.
  double long_gap_us = 20'000.0;
  // Host receive time between two packets that makes a pause in the stream (see above). One second is ten
  // scan periods at 600 rpm and five at 300 rpm, the slowest a Velodyne turns (5 to 20 Hz, VLP-16 manual).
  double pause_us = 1'000'000.0;
  std::size_t reserve_points = 1u << 17;
};

// Where a packet came from in time.
struct PacketTime {
  DeviceTime device;        // absolute time of the packet timestamp (its first firing)
  std::int64_t host_utime;  // receive time
};

class ScanAssembler {
 public:
  using Sink = std::function<void(const Scan&)>;

  explicit ScanAssembler(ScanAssemblerConfig config);

  // Adds a decoded packet from a sensor of `model`; calls `sink` for every scan it completes.
  void add(const DecodedPacket& packet, const PacketTime& time, Model model, const Sink& sink);
  // Emits the scan in progress, if any (end of input, or the stream went idle); the next packet starts a
  // new scan without counting the time since as lost packets.
  void flush(const Sink& sink);
  // Whether a scan is in progress (flush() would emit one).
  bool holdsScan() const { return open_; }

  const ScanAssemblerConfig& config() const { return config_; }
  std::int64_t scansEmitted() const { return next_seq_; }
  std::int64_t packetsLost() const { return lost_total_; }
  // Scans dropped because a pause in the stream came before they ended, and their packets.
  std::int64_t scansDroppedAtPause() const { return dropped_at_pause_; }
  std::int64_t packetsDroppedAtPause() const { return packets_dropped_at_pause_; }
  float lastRpm() const { return last_rpm_; }

 private:
  void finish(const Sink& sink, bool at_cut);
  void begin(std::int64_t start_ns, const PacketTime& time, Model model, ReturnMode mode, bool at_cut);
  void countPacket(const PacketTime& time);

  ScanAssemblerConfig config_;
  int cut_units_ = 0;  // cut angle in 0.01 degree
  Scan scan_;
  bool open_ = false;
  std::int64_t start_ns_ = 0;
  std::int32_t pending_lost_ = 0;  // lost before the next packet, not yet given to a scan
  std::int64_t last_firing_ns_ = 0;
  std::int64_t advance_units_ = 0;  // azimuth covered by the open scan
  bool packet_counted_ = false;
  double period_us_ = 1327.104;

  std::optional<std::int64_t> prev_packet_utime_;
  std::optional<std::int64_t> prev_host_utime_;
  std::optional<int> prev_azimuth_;
  std::int64_t next_seq_ = 0;
  std::int64_t lost_total_ = 0;
  std::int64_t dropped_at_pause_ = 0;
  std::int64_t packets_dropped_at_pause_ = 0;
  float last_rpm_ = 0.0f;
};

}  // namespace ogf::velodyne
