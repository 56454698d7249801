#include "ogf/map_io/offline_mapping.hpp"

#include <algorithm>

#include "ogf/map_io/odometry_clock.hpp"

namespace ogf::map_io {

Result<OfflineMapping> OfflineMapping::create(const pipeline::MapperConfig& config) {
  auto mapper = pipeline::ScanMapper::create(config);
  if (!mapper) return mapper.error();
  return OfflineMapping(std::move(*mapper), config);
}

OfflineMapping::OfflineMapping(pipeline::ScanMapper mapper, const pipeline::MapperConfig& config)
    : mapper_(std::move(mapper)), config_(config) {}

void OfflineMapping::setOdometry(std::span<const fusion::Pose> poses) {
  // The buffer holds the whole file: offline nothing needs evicting.
  fusion::PoseBufferConfig cfg = config_.fusion.pose_buffer;
  cfg.capacity = std::max<std::size_t>(poses.size(), 2);
  poses_.emplace(cfg);
  for (const fusion::Pose& p : poses) poses_->insert(p);
  counts_.poses_accepted = poses_->counts().accepted;
  counts_.poses_rejected = poses_->counts().rejected();
}

std::optional<std::pair<std::int64_t, std::int64_t>> OfflineMapping::odometrySpan() const {
  if (!poses_ || poses_->empty()) return std::nullopt;
  return std::make_pair(poses_->oldest().utime, poses_->newest().utime);
}

Status OfflineMapping::setPaging(const std::filesystem::path& dir, double distance_m) {
  auto pager = persistence::MapPager::open(dir);
  if (!pager) return pager.error();
  pager_.emplace(std::move(*pager));
  page_out_distance_m_ = distance_m;
  return okStatus();
}

Status OfflineMapping::bringInAll() {
  if (!paging_) return paging_;
  if (!pager_) return okStatus();
  const auto damage = pager_->bringInAll(mapper_.filter());
  if (!damage.empty()) return Error{damage.front().reason};
  pager_->collect({});  // every page is back in memory: the files are of no further use
  return okStatus();
}

ScanOutcome OfflineMapping::fold(std::size_t points) {
  if (mapper_.measurements().empty()) {
    ++counts_.scans_empty;
    return ScanOutcome::kEmpty;
  }
  if (pager_) {
    if (const auto damage = pager_->bringIn(mapper_.filter(), mapper_.measurements()); !damage.empty()) {
      paging_ = Error{damage.front().reason};
    }
  }
  mapper_.apply(mapper_.measurements());
  if (pager_ && paging_) {
    const Eigen::Vector3d at = mapper_.sensorOrigin();
    paging_ = pager_->sendAway(mapper_.filter(), {at.x(), at.y(), at.z()}, page_out_distance_m_);
  }
  ++counts_.scans_mapped;
  counts_.points += static_cast<std::int64_t>(points);
  counts_.measurements += static_cast<std::int64_t>(mapper_.measurements().size());
  return ScanOutcome::kMapped;
}

ScanOutcome OfflineMapping::addScan(const ScanRecord& scan, TimeBase base) {
  ++counts_.scans_in;
  if (!poses_) {
    ++counts_.scans_uncovered;
    return ScanOutcome::kUncovered;
  }
  const fusion::ScanPoints points = scan.points(base);
  correction::ScanCorrection applied;
  const fusion::PoseCoverage coverage = correction_ ? mapper_.measure(points, *poses_, *correction_, &applied)
                                                    : mapper_.measure(points, *poses_);
  if (coverage != fusion::PoseCoverage::kCovered) {
    ++counts_.scans_uncovered;
    if (!clock_mismatch_) clock_mismatch_ = map_io::clockMismatch(scan, base, *poses_);
    return ScanOutcome::kUncovered;
  }
  if (correction_) {
    fusion::Pose p;
    p.utime = mapper_.referencePose().utime;
    p.position = applied.map_from_body.translation();
    p.orientation = Eigen::Quaterniond(applied.map_from_body.linear());
    corrected_.push_back(p);
  }
  return fold(scan.size());
}

ScanOutcome OfflineMapping::addStaticScan(const ScanRecord& scan, const Eigen::Isometry3d& odom_from_body) {
  ++counts_.scans_in;
  mapper_.measureStatic(scan.points(TimeBase::kDevice), odom_from_body * config_.fusion.extrinsic.bodyFromSensor());
  return fold(scan.size());
}

ScanOutcome OfflineMapping::addCloud(const Eigen::Vector3d& origin, std::span<const Eigen::Vector3d> points) {
  // measureStatic places sensor-frame points with one pose; a pure translation to `origin` makes the
  // points (given relative to it) land back where the cloud has them, and the rays start at `origin`.
  ++counts_.scans_in;
  cloud_.x.resize(points.size());
  cloud_.y.resize(points.size());
  cloud_.z.resize(points.size());
  cloud_.time_offset_ns.assign(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d d = points[i] - origin;
    cloud_.x[i] = static_cast<float>(d.x());
    cloud_.y[i] = static_cast<float>(d.y());
    cloud_.z[i] = static_cast<float>(d.z());
  }
  mapper_.measureStatic(cloud_.points(TimeBase::kDevice), Eigen::Isometry3d(Eigen::Translation3d(origin)));
  return fold(points.size());
}

}  // namespace ogf::map_io
