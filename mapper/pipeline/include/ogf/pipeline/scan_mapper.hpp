// One scan through the map: placed with the sensor pose at each point's time (Deskew), turned into one
// measurement per cell (MeasurementSet, Sun et al. Sec. VI-B), folded into the banded OGF (eq. 5), and the
// cells whose published state changed collected for the delta stream. measure() and apply() are separate
// so the daemon can journal a scan's measurements before the filter sees them (write-ahead): replaying the
// journal through apply() gives back the same map, bit for bit.
#pragma once

#include <ogf/filter/banded_ogf.hpp>
#include <ogf/fusion/deskew.hpp>
#include <ogf/fusion/measurement_set.hpp>
#include <ogf/fusion/pose_buffer.hpp>

#include <Eigen/Geometry>

#include <span>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/correction/scan_pose_correction.hpp"
#include "ogf/core/huge_pages.hpp"
#include "ogf/core/measurement.hpp"
#include "ogf/delta/published_cell.hpp"
#include "ogf/pipeline/mapper_config.hpp"

namespace ogf::pipeline {

// The cells one scan changed, as delta candidates: a fresh map's first 0.1 m street scan changes 3.4 M
// cells, 68 MB, in huge pages where the kernel has them (a 4 KB page's first write is a slow fault).
using ChangedCells = std::vector<delta::PublishedCell, HugePageAllocator<delta::PublishedCell>>;

class ScanMapper {
 public:
  static Result<ScanMapper> create(const MapperConfig& config);

  // Where the sensor of the scans measured next sits on the body (the configuration's extrinsic until
  // set): a mapper fed by several lidars sets it for each scan.
  void setBodyFromSensor(const Eigen::Isometry3d& body_from_sensor) { deskew_ = fusion::Deskew(body_from_sensor); }

  // Places the scan with the poses and builds its measurement set. On kCovered, measurements() holds it
  // until the next measure call; otherwise it is empty and the coverage says wait (kNotYet) or drop
  // (kTooOld).
  fusion::PoseCoverage measure(const fusion::ScanPoints& scan, const fusion::PoseBuffer& poses);
  // The same with a pose-correction stage between odometry and the map: the placed scan goes to
  // `correction` with the body's odometry pose at the middle of the scan, and is measured where the
  // corrected pose puts it. `applied` (when given) receives the correction on kCovered.
  fusion::PoseCoverage measure(const fusion::ScanPoints& scan, const fusion::PoseBuffer& poses,
                               correction::ScanPoseCorrection& correction,
                               correction::ScanCorrection* applied = nullptr);
  // That call in two steps, so a daemon can hold the pose buffer's lock only for the first: place()
  // deskews the scan and looks up its reference pose; measurePlaced() corrects (which may take a while
  // for an RBPF) and builds the measurement set.
  fusion::PoseCoverage place(const fusion::ScanPoints& scan, const fusion::PoseBuffer& poses);
  void measurePlaced(correction::ScanPoseCorrection& correction, correction::ScanCorrection* applied = nullptr);
  // The body's odometry pose at the middle of the last scan place() covered: the instant a correction
  // refers to (its utime stamps the corrected pose).
  const fusion::Pose& referencePose() const { return reference_; }

  // The same for a sensor that does not move (a tripod): every point from one sensor pose.
  void measureStatic(const fusion::ScanPoints& scan, const Eigen::Isometry3d& odom_from_sensor);
  std::span<const Measurement> measurements() const { return measurements_; }
  // Where the sensor was in the middle of the last scan measured (map frame; the origin before the first).
  Eigen::Vector3d sensorOrigin() const {
    return origins_.empty() ? Eigen::Vector3d::Zero() : origins_[origins_.size() / 2];
  }
  const fusion::RayCounts& rayCounts() const { return set_.counts(); }

  // Folds measurements into the filter in the filter's deterministic order. When `changes` is given,
  // the cells whose class or quantised probability changed are appended to it as delta candidates.
  filter::UpdateStats apply(std::span<const Measurement> measurements,
                            ChangedCells* changes = nullptr);

  // Replaces the filter with a saved map (the filter's map file bytes). Refused, naming the field, when the
  // saved map was made with another resolution, kernel or stencil than this configuration; a map saved in
  // the other covariance storage is converted to the configured one.
  Status restoreFilter(std::span<const std::uint8_t> map_bytes, const std::string& source);

  filter::BandedOgf& filter() { return filter_; }
  const filter::BandedOgf& filter() const { return filter_; }
  const MapperConfig& config() const { return config_; }

  // Every allocated cell as the delta stream would publish it, in the filter's cell order (for the
  // first keyframe after a restart and for exports).
  std::vector<delta::PublishedCell> publishedCells() const;

 private:
  ScanMapper(const MapperConfig& config, filter::BandedOgf filter);

  MapperConfig config_;
  fusion::Deskew deskew_;
  fusion::MeasurementSet set_;
  filter::BandedOgf filter_;
  std::vector<Eigen::Vector3d> origins_;
  std::vector<Eigen::Vector3d> endpoints_;
  fusion::Pose reference_;  // set by place()
  std::span<const Measurement> measurements_;
};

}  // namespace ogf::pipeline
