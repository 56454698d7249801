// Filling a data packet: fire each channel at its time, trace the beam, apply dropouts and range
// noise, select returns for the mode, quantise to the wire units.
#include "ogf/sim/lidar_simulator.hpp"

#include <cmath>
#include <numbers>

#include "ogf/sim/beam_echoes.hpp"
#include "ogf/sim/random.hpp"

#include "units.hpp"

namespace ogf::sim {
namespace {

constexpr std::int64_t kMicrosPerHour = 3600LL * 1000000LL;

// A channel's wire values for one echo: 2 mm distance units (0 = no return, as beyond max range) and the
// reflectivity byte (at least 1 so a real return never looks empty).
void store(vlp16::FiringBlock& block, std::size_t channel, const Echo* echo, double max_range) {
  if (echo == nullptr || !(echo->range > 0.0) || echo->range > max_range) {
    block.distance[channel] = 0;
    block.reflectivity[channel] = 0;
    return;
  }
  block.distance[channel] = static_cast<std::uint16_t>(std::lround(echo->range / vlp16::kDistanceUnitM));
  block.reflectivity[channel] = static_cast<std::uint8_t>(std::clamp(std::lround(echo->intensity), 1L, 255L));
}

}  // namespace

LidarSimulator::LidarSimulator(const World& world, const Eigen::Isometry3d& sensor_to_body,
                               const Trajectory& trajectory, const SensorConfig& config, std::int64_t start_utime)
    : world_(world), sensor_to_body_(sensor_to_body), trajectory_(trajectory), config_(config),
      start_utime_(start_utime), model_(lidarModel(config.model)) {
  for (std::size_t i = 0; i < model_.lasers; ++i) {
    cos_elevation_[i] = std::cos(model_.elevation_deg[i] * kRadiansPerDegree);
    sin_elevation_[i] = std::sin(model_.elevation_deg[i] * kRadiansPerDegree);
  }
}

std::uint32_t LidarSimulator::tohAt(std::int64_t t_ns) const {
  const std::int64_t u = utimeAt(t_ns);
  return static_cast<std::uint32_t>(((u % kMicrosPerHour) + kMicrosPerHour) % kMicrosPerHour);
}

double LidarSimulator::azimuthDegAt(std::int64_t t_ns) const {
  // rpm · 360° / 60 s, times the elapsed seconds; ns kept integral until here so long runs stay exact.
  const double turns = config_.rpm / 60.0 * (static_cast<double>(t_ns) * 1e-9);
  const double deg = config_.initial_azimuth_deg + 360.0 * (turns - std::floor(turns));
  return std::fmod(std::fmod(deg, 360.0) + 360.0, 360.0);
}

vlp16::DataPacket LidarSimulator::dataPacket(std::uint64_t index) const {
  using vlp16::ReturnMode;
  const bool dual = config_.mode == ReturnMode::Dual;
  const std::int64_t t0 = packetStartNs(index);
  Random rng(config_.seed, index + 1);
  vlp16::DataPacket packet;
  packet.toh_us = tohAt(t0);
  packet.mode = config_.mode;
  packet.product_id = model_.product_id;
  const int groups = dual ? vlp16::kBlocks / 2 : vlp16::kBlocks;
  const double trace_range = config_.max_range_m + 6.0 * config_.range_noise_m;
  for (int g = 0; g < groups; ++g) {
    vlp16::FiringBlock& first = packet.blocks[static_cast<std::size_t>(dual ? 2 * g : g)];
    vlp16::FiringBlock* second = dual ? &packet.blocks[static_cast<std::size_t>(2 * g + 1)] : nullptr;
    for (int c = 0; c < vlp16::kChannelsPerBlock; ++c) {
      const std::int64_t t = t0 + model_.channelOffsetNs(g, c);
      const double az_deg = azimuthDegAt(t);
      if (c == 0) {
        // The block's azimuth is that of its first firing, 0.01° units (§4.1).
        const auto az = static_cast<std::uint16_t>(std::lround(az_deg * 100.0) % 36000);
        first.azimuth = az;
        if (second) second->azimuth = az;
      }
      const auto laser = static_cast<std::size_t>(c) % model_.lasers;
      const Eigen::Isometry3d sensor = trajectory_.poseAt(static_cast<double>(t) * 1e-9).isometry() * sensor_to_body_;
      const double a = az_deg * kRadiansPerDegree;
      // Sensor frame of §4.3: x forward, y left, azimuth clockwise seen from above.
      const Eigen::Vector3d local{cos_elevation_[laser] * std::cos(a), -cos_elevation_[laser] * std::sin(a),
                                  sin_elevation_[laser]};
      const Ray ray{sensor * Eigen::Vector3d{0.0, 0.0, model_.vertical_offset_m[laser]}, sensor.linear() * local};

      BeamEchoes echoes = traceBeam(world_, ray, trace_range, static_cast<double>(t) * 1e-9);
      const double drop = rng.uniform();
      for (std::size_t i = 0; i < echoes.count; ++i) echoes.echoes[i].range += config_.range_noise_m * rng.normal();
      if (drop < config_.dropout) echoes.count = 0;

      const auto ch = static_cast<std::size_t>(c);
      switch (config_.mode) {
        case ReturnMode::Strongest: store(first, ch, echoes.strongest(), config_.max_range_m); break;
        case ReturnMode::Last: store(first, ch, echoes.last(), config_.max_range_m); break;
        case ReturnMode::Dual: {
          // Even block: last return; odd block: strongest, or the second strongest when the strongest is
          // the last; both the same when there is one return (§4.4).
          const Echo* last = echoes.last();
          const Echo* strong = echoes.strongest();
          if (strong == last && echoes.count > 1) strong = echoes.strongest(true);
          store(first, ch, last, config_.max_range_m);
          store(*second, ch, strong, config_.max_range_m);
          break;
        }
      }
    }
  }
  return packet;
}

}  // namespace ogf::sim
