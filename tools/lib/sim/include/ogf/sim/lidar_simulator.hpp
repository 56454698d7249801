// The simulated Velodyne (a VLP-16, or an HDL-32E): spins at the configured rpm on the moving body and
// fills data packets. Every channel of every block is fired at its own time (docs/wire-format.md §4.1 for
// the VLP-16; lidar_model.hpp) from the pose the body has at that
// instant, so the capture carries the motion distortion a real one does. A packet is a function of its
// index alone (the noise stream is seeded per packet), so captures are reproducible for a --seed.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstdint>

#include "ogf/sim/lidar_model.hpp"
#include "ogf/sim/trajectory.hpp"
#include "ogf/sim/vlp16_packet.hpp"
#include "ogf/sim/world.hpp"

namespace ogf::sim {

struct SensorConfig {
  LidarModelId model = LidarModelId::Vlp16;
  double rpm = 600.0;  // the VLP-16 spins at 300..1200 rpm (manual §8.1)
  vlp16::ReturnMode mode = vlp16::ReturnMode::Strongest;
  double range_noise_m = 0.01;  // σ of the Gaussian added to every range
  double dropout = 0.0;         // probability that a firing returns nothing at all
  double max_range_m = vlp16::kMaxRangeM;
  double initial_azimuth_deg = 0.0;  // azimuth at the first firing of packet 0
  std::uint64_t seed = 1;
};

class LidarSimulator {
 public:
  // `world` and `trajectory` must outlive the simulator. `start_utime` is the time of packet 0's first
  // firing, µs since the epoch.
  LidarSimulator(const World& world, const Eigen::Isometry3d& sensor_to_body, const Trajectory& trajectory,
                 const SensorConfig& config, std::int64_t start_utime);

  std::int64_t packetPeriodNs() const { return model_.packetPeriodNs(config_.mode); }
  // Time of packet `index`'s first firing after the start, ns.
  std::int64_t packetStartNs(std::uint64_t index) const {
    return static_cast<std::int64_t>(index) * packetPeriodNs();
  }
  // Absolute time, µs since the epoch (floored), of an instant `t_ns` after the start.
  std::int64_t utimeAt(std::int64_t t_ns) const { return start_utime_ + t_ns / 1000; }
  // The sensor's top-of-hour counter at that instant: µs since the start of the UTC hour.
  std::uint32_t tohAt(std::int64_t t_ns) const;
  // Where the head points at `t_ns` after the start, degrees in [0, 360), clockwise seen from above.
  double azimuthDegAt(std::int64_t t_ns) const;

  vlp16::DataPacket dataPacket(std::uint64_t index) const;

  const SensorConfig& config() const { return config_; }
  std::int64_t startUtime() const { return start_utime_; }

 private:
  const World& world_;
  Eigen::Isometry3d sensor_to_body_;
  const Trajectory& trajectory_;
  SensorConfig config_;
  std::int64_t start_utime_;
  const LidarModel& model_;
  std::array<double, 32> cos_elevation_{};
  std::array<double, 32> sin_elevation_{};
};

}  // namespace ogf::sim
