// The sources of ogf-mapper's scans: each a lidar on a robot, with its own channel, clock and place on the
// body. A robot is the body one odometry stream moves: the sources of one robot share its pose channel, and
// the poses of several robots are all in the one map frame (a localisation system's shared world frame), so
// their scans fold into one map. A configuration that names no source maps one, from channels.scan,
// channels.pose, time_base and map.extrinsic.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/common/result.hpp"
#include "ogf/fusion/fusion_config.hpp"

namespace ogf::mapper_daemon {

struct MapperOptions;

// One entry of the configuration's `sources:` list; what it leaves out comes from the top-level keys.
struct SourceOptions {
  std::string name;                   // 1 to 32 of [A-Za-z0-9_-], unique
  std::string robot = "robot";        // the same characters
  std::string scan_channel;           // ogf.lidar_scan_t ...
  std::string packet_channel;         // ... or ogf.velodyne_packets_t, decoded by the mapper (one of the two)
  std::filesystem::path calibration;  // with packet_channel: VeloView XML or ROS YAML; "" = the model's table
  std::string pose_channel;           // "" = channels.pose
  std::optional<adapters::ScanTimeBase> time_base;  // unset = time_base
  std::optional<fusion::ExtrinsicConfig> extrinsic;  // unset = map.extrinsic
};

// A source with nothing left to the top-level keys, as the daemon maps it.
struct ResolvedSource {
  std::string name;
  std::string robot;
  std::string channel;  // its scans' or its packets' channel
  bool packets = false;  // channel carries ogf.velodyne_packets_t
  std::filesystem::path calibration;
  std::string pose_channel;
  adapters::ScanTimeBase time_base = adapters::ScanTimeBase::kAuto;
  Eigen::Isometry3d body_from_sensor = Eigen::Isometry3d::Identity();
};

// The sources `options` configures, in the file's order (one when it names none). Fails naming the entry
// and the field: a bad name, a name used twice, neither or both channels, a calibration without packets,
// two robots on one pose channel or one robot on two, two sources on one channel, a bad extrinsic.
Result<std::vector<ResolvedSource>> resolveSources(const MapperOptions& options);

// The name of the source a configuration without `sources:` maps, and its robot.
inline constexpr const char* kDefaultSourceName = "lidar";
inline constexpr const char* kDefaultRobotName = "robot";

}  // namespace ogf::mapper_daemon
