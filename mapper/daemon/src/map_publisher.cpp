// ogf-mapper's output of the map on LCM (map_publisher.hpp): deltas, corrected poses and keyframes.
#include "ogf/mapper_daemon/map_publisher.hpp"

#include <ogf/odometry_t.hpp>
#include <spdlog/spdlog.h>

#include <chrono>

#include "ogf/mapper_daemon/daemon_time.hpp"

namespace ogf::mapper_daemon {

MapPublisher::MapPublisher(const MapperOptions& options, lcm::LCM& lcm, const delta::DeltaStream& deltas,
                           MapPersistence& persistence, SharedState& shared)
    : options_(options),
      lcm_(lcm),
      deltas_(deltas),
      persistence_(persistence),
      shared_(shared),
      drop_rng_(options.test_seed) {}

MapPublisher::~MapPublisher() { stop(); }

void MapPublisher::start() {
  keyframe_sender_ = std::make_unique<KeyframeSender>(
      [this](const ogf::map_delta_t& m) { lcm_.publish(options_.delta_channel, &m); },
      [this](const KeyframeSender::Report& r) { keyframeSent(r); });
}

void MapPublisher::stop() { keyframe_sender_.reset(); }

void MapPublisher::publishDeltas(const std::vector<ogf::map_delta_t>& deltas) {
  const bool drop = options_.test_drop_delta_fraction > 0 &&
                    std::uniform_real_distribution<double>(0, 1)(drop_rng_) < options_.test_drop_delta_fraction;
  if (drop) return;
  for (const auto& m : deltas) lcm_.publish(options_.delta_channel, &m);
}

void MapPublisher::publishCorrectedPose(std::int64_t utime, const correction::ScanCorrection& applied) {
  ogf::odometry_t m{};
  m.utime = utime;  // the scan's middle, on the clock the odometry shares with the scans
  m.frame_id = "map";
  m.child_frame_id = "body";
  const Eigen::Vector3d t = applied.map_from_body.translation();
  const Eigen::Quaterniond q(applied.map_from_body.linear());
  for (int i = 0; i < 3; ++i) m.position[i] = t[i];
  m.orientation[0] = q.w();
  m.orientation[1] = q.x();
  m.orientation[2] = q.y();
  m.orientation[3] = q.z();
  m.num_covariance = 0;
  lcm_.publish(options_.corrected_pose_channel, &m);
}

bool MapPublisher::keyframePeriodDue(std::int64_t now) const {
  const auto keyframe_us = static_cast<std::int64_t>(options_.keyframe_interval_s * 1e6);
  return now - last_keyframe_steady_ > keyframe_us;
}

bool MapPublisher::keyframeDue(bool requested, std::int64_t now) const {
  return (requested || keyframe_waiting_ || keyframePeriodDue(now)) && !keyframe_sender_->busy();
}

void MapPublisher::keyframeTurn(bool requested, std::int64_t now) {
  keyframe_waiting_ = keyframe_waiting_ || requested;
  if (keyframe_waiting_ || keyframePeriodDue(now)) {
    if (publishKeyframe()) keyframe_waiting_ = false;
  }
}

void MapPublisher::keyframeOfNewMap() {
  if (!publishKeyframe()) keyframe_waiting_ = true;
}

void MapPublisher::cancelKeyframe() { keyframe_sender_->cancel(); }

std::vector<std::string> MapPublisher::pinnedPages() const {
  return keyframe_sender_ ? keyframe_sender_->pinnedPages() : std::vector<std::string>{};
}

bool MapPublisher::publishKeyframe() {
  if (keyframe_sender_->busy()) return false;
  last_keyframe_steady_ = steadyUtime();
  // The cells in memory are copied now; the pages holding the rest are read by the sender.
  const auto began = std::chrono::steady_clock::now();
  const persistence::MapPager* pager = persistence_.pager();
  KeyframeSender::Job job{delta::KeyframeWriter(deltas_, wallUtime()), deltas_.map().sortedCells(),
                          pager ? pager->heldPublishedPages() : std::vector<std::filesystem::path>{}, 0.0};
  job.cut_ms = msSince(began);
  keyframe_sender_->send(std::move(job));
  return true;
}

void MapPublisher::keyframeSent(const KeyframeSender::Report& r) {
  persistence_.reportPageDamage(r.damage);
  spdlog::info("keyframe at seq {}: {} cells ({} from pages) in {} parts; cut in {:.0f} ms, sent in {:.0f} ms{}", r.seq,
               r.cells, r.page_cells, r.parts, r.cut_ms, r.send_ms,
               r.missing + r.surplus == 0 ? std::string()
                                          : fmt::format(" ({} cells missing, {} beyond the count)", r.missing, r.surplus));
  std::lock_guard lk(shared_.mu);
  ++shared_.stats.keyframes_sent;
}

}  // namespace ogf::mapper_daemon
