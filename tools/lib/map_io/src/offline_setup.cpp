#include "ogf/map_io/offline_setup.hpp"

#include <ogf/slam/pose_corrector.hpp>
#include <utility>

namespace ogf::map_io {
namespace {

TimeBase parseTimeBase(const std::string& name) {
  return name == "host" ? TimeBase::kHost : name == "device" ? TimeBase::kDevice : TimeBase::kAuto;
}

bool staticSensor(const MapRequest& r, const mapper_daemon::MapperOptions& options) {
  return r.is_static || (options.pose_source == mapper_daemon::PoseSource::kStatic && !r.given.odometry &&
                         !r.given.pose_topic && r.pcd.empty());
}

pipeline::MapperConfig mapperConfig(const MapRequest& r, const mapper_daemon::MapperOptions& options,
                                    bool from_file) {
  pipeline::MapperConfig config = options.map;
  if (!from_file || r.given.resolution) config.setResolution(r.resolution);
  if (!from_file || r.given.max_range) config.fusion.measurement.max_range_m = r.max_range;
  if (!from_file || r.given.min_range) config.fusion.measurement.min_range_m = r.min_range;
  if (r.given.threads) config.filter.threads = r.threads;
  return config;
}

Result<correction::ScanPoseCorrectionConfig> correctionConfig(const MapRequest& r,
                                                              const mapper_daemon::MapperOptions& options) {
  correction::ScanPoseCorrectionConfig cc = options.pose_correction;
  if (r.given.pose_correction) {
    const auto mode = slam::parseCorrectionMode(r.pose_correction);
    if (!mode) return Error{"--pose-correction: " + mode.error().message};
    cc.corrector.mode = *mode;
  }
  if (r.given.particles) cc.corrector.slam.particles = r.particles;
  return cc;
}

// Gives `mapping` the pose correction `cc` asks for; the usage error when the request cannot have it.
Status addPoseCorrection(const MapRequest& r, const correction::ScanPoseCorrectionConfig& cc, bool is_static,
                         OfflineMapping& mapping) {
  if (cc.corrector.mode == slam::CorrectionMode::kNone) {
    if (!r.corrected_out.empty()) return Error{"--corrected-out needs --pose-correction scan-match or rbpf"};
    return okStatus();
  }
  if (is_static || !r.pcd.empty())
    return Error{
        "--pose-correction needs a moving sensor with odometry (--pcap with --odometry, --lcm-log or "
        "--rosbag2)"};
  auto correction = correction::ScanPoseCorrection::create(cc);
  if (!correction) return Error{"--pose-correction: " + correction.error().message};
  mapping.setPoseCorrection(std::move(*correction));
  return okStatus();
}

}  // namespace

TimeBase chooseTimeBase(const MapRequest& r, const OfflineConfig* file) {
  if (r.given.time_base) return parseTimeBase(r.time_base);
  if (file != nullptr && file->sets("time_base")) return file->options.time_base;
  return r.rosbag2.empty() ? parseTimeBase(r.time_base) : TimeBase::kHost;
}

Result<OfflineSetup> prepareOfflineMapping(const MapRequest& r, const OfflineConfig* file) {
  const mapper_daemon::MapperOptions options =
      file != nullptr ? file->options : mapper_daemon::MapperOptions{};
  const bool is_static = staticSensor(r, options);
  if (!r.pcap.empty() && r.odometry.empty() && !is_static)
    return Error{"--pcap needs --odometry FILE or --static"};
  auto created = OfflineMapping::create(mapperConfig(r, options, file != nullptr));
  if (!created) return Error{"configuration: " + created.error().message};
  const auto cc = correctionConfig(r, options);
  if (!cc) return cc.error();
  if (auto st = addPoseCorrection(r, *cc, is_static, *created); !st) return st.error();
  return OfflineSetup{std::move(*created), chooseTimeBase(r, file), is_static,
                      options.static_pose.bodyFromSensor(), std::string(slam::toString(cc->corrector.mode))};
}

}  // namespace ogf::map_io
