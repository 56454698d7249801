// Decodes one 1206-byte data packet into points in the sensor frame (REP-103: x forward, y left, z up;
// azimuth clockwise seen from above), with per-point time offsets from the packet's timestamp, and
// records the azimuth and time of every firing so a ScanAssembler can cut scans inside a packet.
// Pure and allocation-free per packet: the calibration is turned into tables once, at construction.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ogf/velodyne/calibration.hpp"
#include "ogf/velodyne/model.hpp"
#include "ogf/velodyne/result.hpp"
#include "ogf/velodyne/wire_format.hpp"

namespace ogf::velodyne {

struct DecoderConfig {
  Model model = Model::Vlp16;                // must be known here; see ModelDetector
  std::optional<Calibration> calibration;    // nullopt: the model's nominal table
  // Which returns to keep. nullopt: as byte 1204 says. Strongest or Last on dual packets keeps that
  // return only (a pair that agrees counts for both); on single-return packets it names the mode when
  // the packet does not (old HDL-32E firmware) or overrides it. Dual decodes the packet as block pairs.
  std::optional<ReturnMode> return_mode;
  double min_range_m = 0.4;                  // the ROS VLP16_points.launch default; 0 keeps all non-zero
  double max_range_m = 250.0;
};

struct Point {
  float x, y, z;           // metres, REP-103
  float distance_m;        // raw distance x resolution (before dist_correction)
  float azimuth_deg;       // interpolated azimuth of the firing, [0, 360)
  float time_offset_us;    // firing time minus the packet timestamp
  std::uint8_t intensity;  // calibrated reflectivity
  std::uint8_t ring;       // rank by elevation, 0 = lowest
  std::uint8_t laser_id;
  ReturnType return_type;
  std::uint8_t firing;     // index into DecodedPacket::firing_azimuth
};

enum class PacketStatus : std::uint8_t { Ok, WrongSize, BadBlockFlag, BadAzimuth };

struct DecodedPacket {
  static constexpr int kMaxPoints = wire::kBlocksPerPacket * wire::kChannelsPerBlock;
  static constexpr int kMaxFirings = 24;

  std::uint32_t toh_us = 0;    // bytes 1200..1203
  ReturnMode return_mode = ReturnMode::Strongest;  // of the points (a kept return when filtering dual data)
  bool dual_layout = false;                         // the packet is block pairs (fixes the packet period)
  std::uint8_t product_id = 0;
  int firing_count = 0;        // firing sequences in the packet, in time order
  std::array<std::uint16_t, kMaxFirings> firing_azimuth{};  // 0.01 degree, first laser of the firing
  std::array<float, kMaxFirings> firing_time_us{};          // from the packet timestamp
  int point_count = 0;
  std::array<Point, kMaxPoints> points;  // in firing order; dual: per channel the last, then strongest
};

class PacketDecoder {
 public:
  // Fails when the calibration has fewer lasers than the model or a range limit is nonsense.
  static Result<PacketDecoder> create(const DecoderConfig& config);

  // Decodes `payload` into `out` (overwritten). Anything but Ok leaves `out` with no points.
  PacketStatus decode(std::span<const std::uint8_t> payload, DecodedPacket& out) const;

  const DecoderConfig& config() const { return config_; }
  Model model() const { return config_.model; }
  // Ring of each laser id (rank by elevation).
  const std::vector<std::uint8_t>& rings() const { return ring_; }

 private:
  explicit PacketDecoder(DecoderConfig config) : config_(std::move(config)) {}

  struct LaserTable {
    float cos_vert, sin_vert, cos_rot_corr, sin_rot_corr, dist_corr, vert_offset, horiz_offset;
  };
  void emit(DecodedPacket& out, const wire::RawChannel& ch, int laser, std::uint16_t azimuth, float time_us,
            ReturnType type, int firing) const;

  DecoderConfig config_;
  double resolution_m_ = 0.002;
  std::vector<LaserTable> lasers_;
  std::vector<std::uint8_t> ring_;
  const float* cos_azimuth_ = nullptr;  // 36000 entries, 0.01 degree steps, shared by all decoders
  const float* sin_azimuth_ = nullptr;
  std::array<double, wire::kChannelsPerBlock> channel_time_us_{};
  float min_range_m_ = 0.0f, max_range_m_ = 0.0f;
  std::array<std::uint8_t, wire::kChannelsPerBlock> channel_laser_{};
  std::array<std::uint8_t, wire::kChannelsPerBlock> channel_sequence_{};
};

}  // namespace ogf::velodyne
