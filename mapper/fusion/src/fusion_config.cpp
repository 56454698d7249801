// Validation of the fusion configuration: every check names its field and the value it saw.
#include <ogf/fusion/fusion_config.hpp>

#include <cmath>
#include <sstream>
#include <string>

namespace ogf::fusion {
namespace {

// Cell coordinates of anything within max range must stay far inside int32 (CellKey).
constexpr double kMaxCellsPerRange = 1 << 20;

Error fieldError(const std::string& field, const std::string& rule, double value) {
  std::ostringstream s;
  s << field << " " << rule << " (got " << value << ")";
  return Error::configuration(s.str());
}

Status prefixed(const char* prefix, Status status) {
  if (status) return status;
  return Error::configuration(std::string(prefix) + status.error().message);
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

Status MeasurementConfig::validate() const {
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m)) {
    return fieldError("resolution_m", "must be a positive number of metres", resolution_m);
  }
  if (!(min_range_m >= 0.0) || !std::isfinite(min_range_m)) {
    return fieldError("min_range_m", "must be >= 0 metres", min_range_m);
  }
  if (!(max_range_m > min_range_m) || !std::isfinite(max_range_m)) {
    return fieldError("max_range_m", "must be finite and > min_range_m", max_range_m);
  }
  if (max_range_m / resolution_m > kMaxCellsPerRange) {
    return fieldError("max_range_m", "must be at most 2^20 cells (resolution_m * 1048576)", max_range_m);
  }
  return okStatus();
}

Status ExtrinsicConfig::validate() const {
  if (!finite(translation_m)) return Error::configuration("translation_m must be finite");
  if (quaternion) {
    const double n = quaternion->coeffs().norm();
    if (!quaternion->coeffs().allFinite() || std::abs(n - 1.0) > 1e-3) {
      return fieldError("quaternion", "must be a unit quaternion (w, x, y, z), norm", n);
    }
  } else if (!finite(rpy_rad)) {
    return Error::configuration("rpy_rad must be finite");
  }
  return okStatus();
}

Eigen::Isometry3d ExtrinsicConfig::bodyFromSensor() const {
  Eigen::Quaterniond q;
  if (quaternion) {
    q = quaternion->normalized();
  } else {
    q = Eigen::AngleAxisd(rpy_rad.z(), Eigen::Vector3d::UnitZ()) *
        Eigen::AngleAxisd(rpy_rad.y(), Eigen::Vector3d::UnitY()) *
        Eigen::AngleAxisd(rpy_rad.x(), Eigen::Vector3d::UnitX());
  }
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = q.toRotationMatrix();
  t.translation() = translation_m;
  return t;
}

Status PoseBufferConfig::validate() const {
  if (capacity < 2) return fieldError("capacity", "must hold at least 2 poses", static_cast<double>(capacity));
  if (!(quaternion_tolerance >= 0.0 && quaternion_tolerance < 0.5)) {
    return fieldError("quaternion_tolerance", "must be in [0, 0.5)", quaternion_tolerance);
  }
  if (!(jump_translation_m > 0.0)) return fieldError("jump_translation_m", "must be > 0 metres", jump_translation_m);
  if (!(jump_rotation_rad > 0.0)) return fieldError("jump_rotation_rad", "must be > 0 radians", jump_rotation_rad);
  if (!(max_abs_position_m > 0.0) || !std::isfinite(max_abs_position_m))
    return fieldError("max_abs_position_m", "must be a positive number of metres", max_abs_position_m);
  return okStatus();
}

Status PendingScansConfig::validate() const {
  if (!(max_pose_wait_s >= 0.0) || !std::isfinite(max_pose_wait_s)) {
    return fieldError("max_pose_wait_s", "must be >= 0 seconds", max_pose_wait_s);
  }
  if (max_pending_scans < 1) return Error::configuration("max_pending_scans must be >= 1 (got 0)");
  if (max_pending_points < 1) return Error::configuration("max_pending_points must be >= 1 (got 0)");
  return okStatus();
}

Status FusionConfig::validate() const {
  if (Status s = prefixed("measurement.", measurement.validate()); !s) return s;
  if (Status s = prefixed("extrinsic.", extrinsic.validate()); !s) return s;
  if (Status s = prefixed("pose_buffer.", pose_buffer.validate()); !s) return s;
  // Every cell a ray from a pose can reach must have an int32 key.
  if ((pose_buffer.max_abs_position_m + measurement.max_range_m) / measurement.resolution_m > 2e9)
    return fieldError("pose_buffer.max_abs_position_m", "plus max_range_m must be below 2e9 cells",
                      pose_buffer.max_abs_position_m);
  if (Status s = prefixed("time_sanity.", time_sanity.validate()); !s) return s;
  return prefixed("pending.", pending.validate());
}

}  // namespace ogf::fusion
