// ogf-mapper's output of the map on LCM (map_publisher.hpp): deltas, corrected poses and keyframes.
#include "ogf/mapper_daemon/map_publisher.hpp"

#include <ogf/odometry_t.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "ogf/mapper_daemon/daemon_time.hpp"

namespace ogf::mapper_daemon {

namespace {

// The most of the channel's rate a keyframe takes while it goes out: the deltas keep the rest.
constexpr double kKeyframeShare = 0.5;

}  // namespace

MapPublisher::MapPublisher(const MapperOptions& options, lcm::LCM& lcm, delta::DeltaStream& deltas,
                           MapPersistence& persistence, SharedState& shared)
    : options_(options),
      lcm_(lcm),
      deltas_(deltas),
      persistence_(persistence),
      shared_(shared),
      drop_rng_(options.test_seed),
      channel_budget_(static_cast<double>(options.deltas.max_bytes_per_s), options.deltas.burst_s, steadyUtime()),
      keyframe_budget_(static_cast<double>(options.deltas.max_bytes_per_s) * kKeyframeShare, options.deltas.burst_s,
                       steadyUtime()) {}

MapPublisher::~MapPublisher() { stop(); }

void MapPublisher::start() {
  grant();
  keyframe_sender_ = std::make_unique<KeyframeSender>(
      [this](const ogf::map_delta_t& m) { publishKeyframePart(m); },
      [this](const KeyframeSender::Report& r) { keyframeSent(r); }, 16, std::chrono::milliseconds(2),
      [this] { return keyframePace(); });
}

void MapPublisher::stop() { keyframe_sender_.reset(); }

void MapPublisher::grant() {
  deltas_.setRule({options_.deltas.probability_step, options_.deltas.variance_step});
  if (options_.deltas.max_bytes_per_s > 0) {
    deltas_.limitWaitingTo(static_cast<double>(options_.deltas.max_bytes_per_s), options_.deltas.max_wait_s);
  }
  std::lock_guard lk(budget_mu_);
  channel_budget_.refill(steadyUtime());
  deltas_.allow(channel_budget_.allowance());
}

void MapPublisher::publishKeyframePart(const ogf::map_delta_t& part) {
  lcm_.publish(options_.delta_channel, &part);
  const std::int64_t bytes = delta::DeltaStream::partBytes(static_cast<std::size_t>(part.num_cells));
  std::lock_guard lk(budget_mu_);
  channel_budget_.spend(bytes);
  keyframe_budget_.spend(bytes);
}

std::chrono::microseconds MapPublisher::keyframePace() {
  std::lock_guard lk(budget_mu_);
  keyframe_budget_.refill(steadyUtime());
  return std::chrono::microseconds(keyframe_budget_.debtUs());
}

void MapPublisher::publishDeltas(const std::vector<ogf::map_delta_t>& deltas) {
  const bool drop = options_.test_drop_delta_fraction > 0 &&
                    std::uniform_real_distribution<double>(0, 1)(drop_rng_) < options_.test_drop_delta_fraction;
  if (!drop) {
    for (const auto& m : deltas) lcm_.publish(options_.delta_channel, &m);
    std::lock_guard lk(budget_mu_);
    channel_budget_.spend(delta::DeltaStream::bytesOf(deltas));
  }
  std::int64_t bytes_sent = 0;
  {
    std::lock_guard lk(budget_mu_);
    bytes_sent = channel_budget_.spent();
  }
  {
    const delta::UpdateFigures& update = deltas_.lastUpdate();
    std::lock_guard lk(shared_.mu);
    auto& stats = shared_.stats;
    stats.delta_bytes_sent = bytes_sent;
    stats.delta_cells_sent += static_cast<std::int64_t>(update.sent);
    stats.delta_cells_waiting = static_cast<std::int64_t>(update.deferred);
    stats.delta_class_changes_waiting = static_cast<std::int64_t>(deltas_.deferred().classChanges());
    stats.delta_cells_overflowed = static_cast<std::int64_t>(deltas_.overflowed());
    stats.delta_slabs_stale = static_cast<std::int64_t>(update.stale);
  }
  grant();
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
  grant();
  keyframe_waiting_ = keyframe_waiting_ || requested;
  if (keyframe_waiting_ || keyframePeriodDue(now)) {
    if (publishKeyframe()) keyframe_waiting_ = false;
  }
}

void MapPublisher::keyframeOfNewMap() {
  grant();  // a new map is a new delta stream
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
  // Requests can ask for keyframes back to back (any host on the bus may): the log says one of them per
  // keyframe_log_ period, and how many others went out meanwhile.
  if (auto more = keyframe_log_.allow()) {
    spdlog::info("keyframe at seq {}: {} cells ({} from pages) in {} parts; cut in {:.0f} ms, sent in {:.0f} ms{}{}",
                 r.seq, r.cells, r.page_cells, r.parts, r.cut_ms, r.send_ms,
                 r.missing + r.surplus == 0
                     ? std::string()
                     : fmt::format(" ({} cells missing, {} beyond the count)", r.missing, r.surplus),
                 *more == 0 ? std::string() : fmt::format(" ({} more keyframes since the last line)", *more));
  }
  std::int64_t bytes_sent = 0;
  {
    std::lock_guard budget(budget_mu_);
    bytes_sent = channel_budget_.spent();
  }
  std::lock_guard lk(shared_.mu);
  ++shared_.stats.keyframes_sent;
  shared_.stats.delta_bytes_sent = bytes_sent;
}

}  // namespace ogf::mapper_daemon
