#include "ogf/velodyne/packet_decoder.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace ogf::velodyne {
namespace {

constexpr int kTurn = wire::kAzimuthUnitsPerTurn;

// Forward azimuth advance from `from` to `to`, 0.01 degree. A backwards step (a stopped or jittering
// rotor) counts as no advance rather than as almost a full turn.
int forwardAdvance(int from, int to) {
  const int d = (to - from + kTurn) % kTurn;
  return d > kTurn / 2 ? 0 : d;
}

// Interpolated azimuth, rounded to the 0.01 degree grid and wrapped before any table lookup
// (ros rawdata.cc:709-710 rounds the same way; its changelog's "azimuth overflow" fix; vd wrap()).
std::uint16_t interpolate(int base, int advance, float fraction) {
  const int a = base + static_cast<int>(static_cast<float>(advance) * fraction + 0.5f);
  return static_cast<std::uint16_t>(a >= kTurn ? a - kTurn : a);
}

struct AzimuthTable {
  std::array<float, 2 * kTurn> cos_sin{};  // interleaved: one cache line holds both
};

// cos and sin of every 0.01 degree azimuth, computed once per process.
const AzimuthTable& azimuthTable() {
  static const AzimuthTable table = [] {
    AzimuthTable t;
    for (int a = 0; a < kTurn; ++a) {
      const double rad = a * 0.01 * M_PI / 180.0;
      t.cos_sin[2 * static_cast<std::size_t>(a)] = static_cast<float>(std::cos(rad));
      t.cos_sin[2 * static_cast<std::size_t>(a) + 1] = static_cast<float>(std::sin(rad));
    }
    return t;
  }();
  return table;
}

}  // namespace

Result<PacketDecoder> PacketDecoder::create(const DecoderConfig& config) {
  if (config.model == Model::Unknown) return Error::configuration("decoder: the model is unknown");
  if (!(config.min_range_m >= 0.0) || !(config.max_range_m > config.min_range_m))
    return Error::configuration("decoder: need 0 <= min_range < max_range, got min_range " +
                 std::to_string(config.min_range_m) + " max_range " + std::to_string(config.max_range_m));
  PacketDecoder d(config);
  const ModelTraits& t = traits(config.model);
  const Calibration calib = config.calibration ? *config.calibration : nominalCalibration(config.model);
  if (static_cast<int>(calib.lasers.size()) < t.lasers)
    return Error::configuration("calibration " + calib.source + ": " + std::to_string(calib.lasers.size()) +
                 " lasers, the " + std::string(t.name) + " needs " + std::to_string(t.lasers));
  const double t_block = t.block_duration_us;
  d.resolution_m_ = calib.distance_resolution_m;
  d.resolution_f_ = static_cast<float>(calib.distance_resolution_m);
  d.min_range_m_ = static_cast<float>(config.min_range_m);
  d.max_range_m_ = static_cast<float>(config.max_range_m);
  for (int i = 0; i < t.lasers; ++i) {
    const LaserCorrection& c = calib.lasers[static_cast<std::size_t>(i)];
    d.lasers_[static_cast<std::size_t>(i)] = LaserTable{static_cast<float>(std::cos(c.vert_correction_rad)),
                                                        static_cast<float>(std::sin(c.vert_correction_rad)),
                                                        static_cast<float>(std::cos(c.rot_correction_rad)),
                                                        static_cast<float>(std::sin(c.rot_correction_rad)),
                                                        static_cast<float>(c.dist_correction_m),
                                                        static_cast<float>(c.vert_offset_m),
                                                        static_cast<float>(c.horiz_offset_m)};
  }
  // Ring = rank by elevation, lowest first (ros calibration.cc:166-195 sorts vert_correction).
  std::vector<int> order(static_cast<std::size_t>(t.lasers));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return calib.lasers[static_cast<std::size_t>(a)].vert_correction_rad <
           calib.lasers[static_cast<std::size_t>(b)].vert_correction_rad;
  });
  for (std::size_t r = 0; r < order.size(); ++r)
    d.ring_[static_cast<std::size_t>(order[r])] = static_cast<std::uint8_t>(r);
  const AzimuthTable& table = azimuthTable();
  d.cos_sin_azimuth_ = table.cos_sin.data();
  for (int ch = 0; ch < wire::kChannelsPerBlock; ++ch) {
    const auto c = static_cast<std::size_t>(ch);
    const double in_block = channelTimeInBlockUs(config.model, ch);
    d.channel_fraction_[c] = static_cast<float>(in_block / t_block);
    d.channel_time_ns_[c] = static_cast<std::int32_t>(std::lround(in_block * 1000.0));
    d.channel_laser_[c] = static_cast<std::uint8_t>(laserOfChannel(config.model, ch));
    d.channel_sequence_[c] = static_cast<std::uint8_t>(sequenceOfChannel(config.model, ch));
  }
  d.block_ns_ = static_cast<std::int32_t>(std::lround(t.block_duration_us * 1000.0));
  d.sequence_ns_ = static_cast<std::int32_t>(std::lround(t.sequence_duration_us * 1000.0));
  return d;
}

[[gnu::always_inline]] inline void PacketDecoder::emit(DecodedPacket& out, const wire::RawChannel& ch,
                                                       int channel, int base, int advance,
                                                       std::int32_t time_ns, ReturnType type,
                                                       int firing) const {
  const std::uint16_t raw = wire::readLe16(ch.distance);
  if (raw == 0) return;  // no return
  const auto c = static_cast<std::size_t>(channel);
  const int laser = channel_laser_[c];
  const LaserTable& l = lasers_[static_cast<std::size_t>(laser)];
  const float distance = static_cast<float>(raw) * resolution_f_;
  const float r = distance + l.dist_corr;
  if (r < min_range_m_ || r > max_range_m_) return;
  const std::uint16_t azimuth = interpolate(base, advance, channel_fraction_[c]);
  // cos/sin(azimuth - rot_correction) (ros rawdata.cc; vd unpackPoint).
  const float ca = cos_sin_azimuth_[2 * azimuth], sa = cos_sin_azimuth_[2 * azimuth + 1];
  const float cos_a = ca * l.cos_rot_corr + sa * l.sin_rot_corr;
  const float sin_a = sa * l.cos_rot_corr - ca * l.sin_rot_corr;
  const float xy = r * l.cos_vert - l.vert_offset * l.sin_vert;
  Point& p = out.points[static_cast<std::size_t>(out.point_count++)];
  // The Velodyne frame (x right, y forward) turned into REP-103: x = r cos(w) cos(a), y = -r cos(w) sin(a).
  p.x = xy * cos_a + l.horiz_offset * sin_a;
  p.y = -(xy * sin_a - l.horiz_offset * cos_a);
  p.z = r * l.sin_vert + l.vert_offset * l.cos_vert;
  p.distance_m = distance;
  p.time_offset_ns = time_ns;
  p.azimuth = azimuth;
  p.intensity = ch.reflectivity;
  p.ring = ring_[static_cast<std::size_t>(laser)];
  p.laser_id = static_cast<std::uint8_t>(laser);
  p.return_type = type;
  p.firing = static_cast<std::uint8_t>(firing);
}

PacketStatus checkPacketTrailer(std::span<const std::uint8_t> payload) {
  if (payload.size() != wire::kDataPacketSize) return PacketStatus::WrongSize;
  if (wire::readLe32(payload.data() + 1200) >= wire::kMicrosecondsPerHour) return PacketStatus::BadTimeOfHour;
  const std::uint8_t mode = payload[1204];
  if (mode != wire::kReturnModeUnreported && !returnModeFromByte(mode)) return PacketStatus::UnknownReturnMode;
  const std::uint8_t product = payload[1205];
  if (product != 0 && !modelFromProductId(product)) return PacketStatus::UnknownProduct;
  return PacketStatus::Ok;
}

PacketStatus PacketDecoder::decode(std::span<const std::uint8_t> payload, DecodedPacket& out) const {
  out.point_count = 0;
  out.firing_count = 0;
  if (payload.size() != wire::kDataPacketSize) return PacketStatus::WrongSize;
  wire::RawDataPacket packet;
  std::copy(payload.begin(), payload.end(), reinterpret_cast<std::uint8_t*>(&packet));
  std::array<int, wire::kBlocksPerPacket> az{};
  for (int b = 0; b < wire::kBlocksPerPacket; ++b) {
    const wire::RawBlock& block = packet.blocks[b];
    if (wire::readLe16(block.flag) != wire::kUpperBankFlag) return PacketStatus::BadBlockFlag;
    // Real sensors do send 36000 (both VeloView test captures hold one): it is 0. Beyond is corrupt.
    const int azimuth = wire::readLe16(block.azimuth);
    if (azimuth > kTurn) return PacketStatus::BadAzimuth;
    az[static_cast<std::size_t>(b)] = azimuth % kTurn;
  }
  if (const PacketStatus trailer = checkPacketTrailer(payload); trailer != PacketStatus::Ok) return trailer;
  out.toh_us = wire::readLe32(packet.timestamp);
  out.product_id = packet.product_id;
  // Byte 1204 names the mode; firmware without it (HDL-32E before 2.2.20) is dual when a block pair shares
  // its azimuth (VeloView vtkDataPacket.h:264-267).
  const ReturnMode packet_mode = returnModeFromByte(packet.return_mode)
                                     .value_or(az[0] == az[1] ? ReturnMode::Dual : ReturnMode::Strongest);
  const std::optional<ReturnMode> wanted = config_.return_mode;
  const bool dual = packet_mode == ReturnMode::Dual || wanted == ReturnMode::Dual;
  out.dual_layout = dual;

  const int fpb = traits(config_.model).firings_per_block;
  const float sequence_fraction = static_cast<float>(sequence_ns_) / static_cast<float>(block_ns_);

  if (!dual) {
    out.return_mode = wanted.value_or(packet_mode);
    const ReturnType type = out.return_mode == ReturnMode::Last ? ReturnType::Last : ReturnType::Strongest;
    int advance = 0;
    for (int b = 0; b < wire::kBlocksPerPacket; ++b) {
      // Azimuth advance over the block from the next block (ros rawdata.cc:679); the last block reuses
      // the previous advance.
      if (b + 1 < wire::kBlocksPerPacket)
        advance = forwardAdvance(az[static_cast<std::size_t>(b)], az[static_cast<std::size_t>(b) + 1]);
      const int base = az[static_cast<std::size_t>(b)];
      for (int s = 0; s < fpb; ++s) {
        const auto f = static_cast<std::size_t>(b * fpb + s);
        out.firing_azimuth[f] = interpolate(base, advance, static_cast<float>(s) * sequence_fraction);
        out.firing_time_ns[f] = b * block_ns_ + s * sequence_ns_;
      }
      const wire::RawBlock& block = packet.blocks[b];
      const std::int32_t block_ns = b * block_ns_;
      for (int ch = 0; ch < wire::kChannelsPerBlock; ++ch) {
        const auto c = static_cast<std::size_t>(ch);
        emit(out, block.channels[ch], ch, base, advance, block_ns + channel_time_ns_[c], type,
             b * fpb + channel_sequence_[c]);
      }
    }
    out.firing_count = wire::kBlocksPerPacket * fpb;
    return PacketStatus::Ok;
  }

  // Dual: blocks 2q (last return) and 2q+1 (strongest, or second strongest when the strongest is also
  // the last) are one firing (manual §9.3.2; vd packet_decoder.cpp:371-372). The advance comes from the
  // next pair (nebula vlp16_decoder.cpp:163-168); time offsets use the pair index (VeloView :204-207).
  const bool keep_last = wanted != ReturnMode::Strongest;
  const bool keep_strongest = wanted != ReturnMode::Last;
  out.return_mode =
      (wanted == ReturnMode::Strongest || wanted == ReturnMode::Last) ? *wanted : ReturnMode::Dual;
  constexpr int kPairs = wire::kBlocksPerPacket / 2;
  int advance = 0;
  for (int q = 0; q < kPairs; ++q) {
    const auto even = static_cast<std::size_t>(2 * q);
    if (q + 1 < kPairs) advance = forwardAdvance(az[even], az[even + 2]);
    const int base = az[even];
    for (int s = 0; s < fpb; ++s) {
      const auto f = static_cast<std::size_t>(q * fpb + s);
      out.firing_azimuth[f] = interpolate(base, advance, static_cast<float>(s) * sequence_fraction);
      out.firing_time_ns[f] = q * block_ns_ + s * sequence_ns_;
    }
    const wire::RawBlock& last = packet.blocks[even];
    const wire::RawBlock& strongest = packet.blocks[even + 1];
    for (int ch = 0; ch < wire::kChannelsPerBlock; ++ch) {
      const auto c = static_cast<std::size_t>(ch);
      const std::int32_t time = q * block_ns_ + channel_time_ns_[c];
      const int firing = q * fpb + channel_sequence_[c];
      const wire::RawChannel& a = last.channels[ch];
      const wire::RawChannel& b = strongest.channels[ch];
      const bool same = a.distance[0] == b.distance[0] && a.distance[1] == b.distance[1] &&
                        a.reflectivity == b.reflectivity;
      if (same) {
        emit(out, a, ch, base, advance, time, ReturnType::Both, firing);  // one point for both
        continue;
      }
      if (keep_last) emit(out, a, ch, base, advance, time, ReturnType::Last, firing);
      if (keep_strongest) emit(out, b, ch, base, advance, time, ReturnType::Strongest, firing);
    }
  }
  out.firing_count = kPairs * fpb;
  return PacketStatus::Ok;
}

}  // namespace ogf::velodyne
