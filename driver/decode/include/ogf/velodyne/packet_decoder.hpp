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
#include "ogf/common/result.hpp"
#include "ogf/velodyne/wire_format.hpp"

namespace ogf::velodyne {

struct DecoderConfig {
  Model model = Model::Vlp16;              // must be known here; see ModelDetector
  std::optional<Calibration> calibration;  // nullopt: the model's nominal table
  // Which returns to keep. nullopt: as byte 1204 says. Strongest or Last on dual packets keeps that
  // return only (a pair that agrees counts for both); on single-return packets it names the mode when
  // the packet does not (old HDL-32E firmware) or overrides it. Dual decodes the packet as block pairs.
  std::optional<ReturnMode> return_mode;
  double min_range_m = 0.4;  // the ROS VLP16_points.launch default; 0 keeps all non-zero
  double max_range_m = 250.0;
};

struct Point {
  float x, y, z;                // metres, REP-103
  float distance_m;             // raw distance x resolution (before dist_correction)
  std::int32_t time_offset_ns;  // firing time minus the packet timestamp
  std::uint16_t azimuth;        // interpolated azimuth of the firing, 0.01 degree, [0, 36000)
  std::uint8_t intensity;       // calibrated reflectivity
  std::uint8_t ring;            // rank by elevation, 0 = lowest
  std::uint8_t laser_id;
  ReturnType return_type;
  std::uint8_t firing;  // index into DecodedPacket::firing_azimuth

  float azimuthDeg() const { return static_cast<float>(azimuth) * 0.01f; }
  double timeOffsetUs() const { return time_offset_ns * 1e-3; }
};

// BadTimeOfHour: the timestamp is past the hour. UnknownReturnMode / UnknownProduct: byte 1204 / 1205 is
// none the manuals define (0 stands for "not reported" on old firmware).
enum class PacketStatus : std::uint8_t { Ok, WrongSize, BadBlockFlag, BadAzimuth, BadTimeOfHour, UnknownReturnMode, UnknownProduct };

// The checks of the factory bytes and the timestamp (1200..1205), which do not depend on the model: for a
// packet that waits for the model to be known.
PacketStatus checkPacketTrailer(std::span<const std::uint8_t> payload);

struct DecodedPacket {
  static constexpr int kMaxPoints = wire::kBlocksPerPacket * wire::kChannelsPerBlock;
  static constexpr int kMaxFirings = 24;

  std::uint32_t toh_us = 0;                        // bytes 1200..1203
  ReturnMode return_mode = ReturnMode::Strongest;  // of the points (a kept return when filtering dual data)
  bool dual_layout = false;                        // the packet is block pairs (fixes the packet period)
  std::uint8_t product_id = 0;
  int firing_count = 0;                                     // firing sequences in the packet, in time order
  std::array<std::uint16_t, kMaxFirings> firing_azimuth{};  // 0.01 degree, first laser of the firing
  std::array<std::int32_t, kMaxFirings> firing_time_ns{};   // from the packet timestamp
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
  std::span<const std::uint8_t> rings() const {
    return {ring_.data(), static_cast<std::size_t>(traits(config_.model).lasers)};
  }

 private:
  explicit PacketDecoder(DecoderConfig config) : config_(std::move(config)) {}

  struct LaserTable {
    float cos_vert, sin_vert, cos_rot_corr, sin_rot_corr, dist_corr, vert_offset, horiz_offset;
  };
  // Appends the point of one channel unless its range is zero or outside the limits. The azimuth is
  // interpolated only for points that are kept.
  void emit(DecodedPacket& out, const wire::RawChannel& ch, int channel, int base, int advance,
            std::int32_t time_ns, ReturnType type, int firing) const;

  DecoderConfig config_;
  double resolution_m_ = 0.002;
  float resolution_f_ = 0.002f;
  std::array<LaserTable, wire::kChannelsPerBlock> lasers_{};
  std::array<std::uint8_t, wire::kChannelsPerBlock> ring_{};
  const float* cos_sin_azimuth_ = nullptr;  // cos, sin of every 0.01 degree, shared by all decoders
  std::array<float, wire::kChannelsPerBlock> channel_fraction_{};  // time in block / block duration
  std::array<std::int32_t, wire::kChannelsPerBlock> channel_time_ns_{};
  std::int32_t block_ns_ = 0, sequence_ns_ = 0;
  float min_range_m_ = 0.0f, max_range_m_ = 0.0f;
  std::array<std::uint8_t, wire::kChannelsPerBlock> channel_laser_{};
  std::array<std::uint8_t, wire::kChannelsPerBlock> channel_sequence_{};
};

}  // namespace ogf::velodyne
