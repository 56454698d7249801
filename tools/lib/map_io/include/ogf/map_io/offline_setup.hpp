// One ogf-map run made ready from its request and the --config file: the mapper's configuration (the
// file's, or the defaults, with the flags the command line gave over it), the clock the odometry is on,
// whether the sensor stands still, and the pose correction. The rules:
//   - --time, else the file's time_base, else auto; host for a ROS 2 bag, whose packet stamps and pose
//     header stamps are both on the ROS (host) clock;
//   - pose_source: static in the file is --static, unless the command line names the odometry (--odometry,
//     --pose-topic) or maps PCD files;
//   - --resolution, --max-range, --min-range apply when given or when there is no file; --threads when given;
//   - a pose correction needs a moving sensor with odometry; --corrected-out needs a pose correction.
#pragma once

#include <Eigen/Geometry>
#include <ogf/common/result.hpp>
#include <string>

#include "ogf/map_io/map_config_file.hpp"
#include "ogf/map_io/map_request.hpp"
#include "ogf/map_io/offline_mapping.hpp"
#include "ogf/map_io/scan_record.hpp"

namespace ogf::map_io {

struct OfflineSetup {
  OfflineMapping mapping;  // the filter, with the pose correction when one is asked for
  TimeBase time_base = TimeBase::kAuto;
  bool is_static = false;  // the body held at static_pose
  Eigen::Isometry3d static_pose = Eigen::Isometry3d::Identity();
  std::string pose_correction;  // the correction mode's name: none, scan-match or rbpf
};

// The clock of the odometry by the rules above.
TimeBase chooseTimeBase(const MapRequest& request, const OfflineConfig* file);

// The run, or the usage error that stops it ("--pcap needs --odometry FILE or --static", "configuration:
// ...", "--pose-correction: ..."). `file` is the --config file's content, nullptr without one.
Result<OfflineSetup> prepareOfflineMapping(const MapRequest& request, const OfflineConfig* file);

}  // namespace ogf::map_io
