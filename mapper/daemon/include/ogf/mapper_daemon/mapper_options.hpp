// Everything ogf-mapper is configured with: the bus and channels, the map (through MapperConfig), the
// state directory and the timers. Read from a YAML file (unknown keys are refused, so a typo never
// silently falls back to a default), then overridden by flags, then validated as a whole.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/common/result.hpp"
#include "ogf/correction/scan_pose_correction.hpp"
#include "ogf/pipeline/mapper_config.hpp"

namespace ogf::mapper_daemon {

using adapters::ScanTimeBase;

struct MapperOptions {
  // Where each scan's body pose comes from: the odometry on the pose channel (interpolated at every
  // point's time), or one fixed pose (static_pose) for a sensor that does not move, with no odometry.
  enum class PoseSource { kOdometry, kStatic };

  std::string lcm_url;  // "" = $LCM_DEFAULT_URL, else LCM's default
  std::string scan_channel = "VELODYNE_SCAN";
  std::string pose_channel = "POSE";
  std::string delta_channel = "OGF_MAP_DELTA";
  std::string request_channel = "OGF_MAP_REQUEST";
  std::string status_channel = "OGF_MAPPER_STATUS";
  std::string corrected_pose_channel = "POSE_CORRECTED";  // published only when pose correction is on
  // Map services; each answers on its channel + "_REPLY".
  std::string query_channel = "OGF_MAP_QUERY";
  std::string command_channel = "OGF_MAP_COMMAND";
  // Which scan clock the odometry's utime shares: the sensor's device time (GPS/PPS or top-of-hour +
  // host hour) or the driver host's receive time.
  ScanTimeBase time_base = ScanTimeBase::kAuto;
  PoseSource pose_source = PoseSource::kOdometry;
  // With pose_source kStatic: the body in the map frame (the extrinsic still places the sensor on the
  // body); identity by default.
  fusion::ExtrinsicConfig static_pose;

  pipeline::MapperConfig map;
  // The optional stage between odometry and the OGF: none, scan-match or rbpf.
  correction::ScanPoseCorrectionConfig pose_correction;

  // Where snapshots and the journal live; empty = map in memory only.
  std::filesystem::path state_dir;
  // A restart replays the journal since the last snapshot (about 50 ms a scan at 0.2 m): 20 s of scans at
  // 10 Hz restart in about 10 s (docs/performance.md, "Restart after a crash").
  double snapshot_interval_s = 20.0;
  // Regions of the map farther than this from the sensor move to <state_dir>/pages and come back when a
  // scan reaches them again (0 = keep the whole map in memory). Needs a state directory.
  double page_out_distance_m = 60.0;
  double keyframe_interval_s = 30.0;
  double status_interval_s = 1.0;

  // Fault injection for tests: drop this fraction of delta updates before publishing (0 = never).
  double test_drop_delta_fraction = 0.0;
  std::uint32_t test_seed = 1;

  Status validate() const;
};

// Reads a YAML file into `options` (fields not in the file keep their values). Errors name the file,
// the line and the key.
Status loadMapperOptions(const std::filesystem::path& path, MapperOptions& options);

// The same from YAML text; `path` only names the source in errors.
Status parseMapperOptions(const std::string& yaml, const std::filesystem::path& path, MapperOptions& options);

// The keys a file may hold, as a YAML example with the defaults (printed by --print-config).
std::string exampleMapperConfig();

}  // namespace ogf::mapper_daemon
