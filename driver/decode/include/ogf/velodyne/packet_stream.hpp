// The push interface both ogf-driver and ogf-decode use: data and position payloads in (with their host
// receive time), scans out through a callback, with every rejected input counted. Holds the model
// detector, the packet decoder, the device clock and the scan assembler. Data packets are held (a bounded
// copy) and decoded later while an ambiguous model is undecided, and at start until the time base is known:
// a sensor sends a position packet only every ~14 data packets (VLP-16 manual), and stamping the packets
// before it on the host's hour while the rest follow the GPS would put the first scan hours away from the
// second whenever the two clocks disagree (any replayed capture).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ogf/velodyne/device_clock.hpp"
#include "ogf/velodyne/model_detector.hpp"
#include "ogf/velodyne/packet_decoder.hpp"
#include "ogf/velodyne/position_packet.hpp"
#include "ogf/velodyne/scan_assembler.hpp"

namespace ogf::velodyne {

struct StreamConfig {
  std::optional<Model> model;              // nullopt: detect (configuration always wins)
  std::optional<Calibration> calibration;  // nullopt: the model's nominal table
  std::optional<ReturnMode> return_mode;   // see DecoderConfig::return_mode
  double min_range_m = 0.4;
  double max_range_m = 250.0;
  ScanAssemblerConfig assembler;
  // Data packets held at start while no position packet has arrived (64 ~ 85 ms, four to five position
  // packet periods). After that many the host's hour is the time base (no GPS, or the position port is
  // not read). 0: stamp from the first packet on.
  int clock_settle_packets = 64;
};

struct StreamCounters {
  std::int64_t data_packets = 0;      // decoded
  std::int64_t position_packets = 0;  // parsed
  std::int64_t bad_size = 0;
  std::int64_t bad_block_flag = 0;
  std::int64_t bad_other = 0;  // bad azimuth, model never known
  std::int64_t bad_time_of_hour = 0;     // data or position packet timestamp past the hour
  std::int64_t unknown_return_mode = 0;  // data packet byte 1204
  std::int64_t unknown_model = 0;        // data packet byte 1205
  std::int64_t bad_position = 0;         // position packet failing its structure checks
  std::int64_t nmea_time_refused = 0;    // position packets accepted, their NMEA time too far from the host's
  std::int64_t points = 0;
  std::int64_t scans = 0;
};

class PacketStream {
 public:
  // Fails when the configuration cannot decode (range limits, a calibration too small for the model).
  static Result<PacketStream> create(const StreamConfig& config);

  void setScanSink(ScanAssembler::Sink sink) { sink_ = std::move(sink); }

  // A payload from the data port. Returns how it was taken.
  PacketStatus addDataPacket(std::span<const std::uint8_t> payload, std::int64_t host_utime);
  // A payload from the position port; false when it was rejected (counted in bad_size, bad_time_of_hour
  // or bad_position).
  bool addPositionPacket(std::span<const std::uint8_t> payload, std::int64_t host_utime);
  // End of input: decodes what waited for the model and emits the scan in progress.
  void finish();
  // The stream went idle: emits the scan in progress now, with its own times, rather than holding it
  // across the pause (ScanAssembler drops a scan held open across one). Packets still waiting for the
  // model or the time base stay held.
  void flushScan();
  // Whether a scan is in progress.
  bool holdsScan() const { return assembler_.holdsScan(); }

  const StreamCounters& counters() const { return counters_; }
  std::optional<Model> model() const { return detector_.model(); }
  std::optional<ReturnMode> returnMode() const { return last_mode_; }
  float rpm() const { return assembler_.lastRpm(); }
  std::int64_t packetsLost() const { return assembler_.packetsLost(); }
  std::int64_t scansDroppedAtPause() const { return assembler_.scansDroppedAtPause(); }
  const std::optional<PositionPacket>& lastPosition() const { return last_position_; }
  const StreamConfig& config() const { return config_; }

 private:
  explicit PacketStream(const StreamConfig& config);
  bool ensureDecoder();
  void count(PacketStatus status);  // the trailer's rejections
  PacketStatus decodeAndAssemble(std::span<const std::uint8_t> payload, std::int64_t host_utime);
  void holdPacket(std::span<const std::uint8_t> payload, std::int64_t host_utime);
  void decodeHeldPackets();

  struct Pending {
    std::array<std::uint8_t, wire::kDataPacketSize> bytes;
    std::int64_t host_utime;
  };

  StreamConfig config_;
  ModelDetector detector_;
  std::optional<PacketDecoder> decoder_;
  DeviceClock clock_;
  ScanAssembler assembler_;
  ScanAssembler::Sink sink_;
  DecodedPacket decoded_;
  std::vector<Pending> pending_;
  bool clock_settled_ = false;  // a position packet arrived, or clock_settle_packets passed without one
  std::optional<PositionPacket> last_position_;
  std::optional<ReturnMode> last_mode_;
  StreamCounters counters_;
};

}  // namespace ogf::velodyne
