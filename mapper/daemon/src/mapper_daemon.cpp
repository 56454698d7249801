#include "map_id.hpp"
#include "ogf/mapper_daemon/mapper_daemon.hpp"

#include <ogf/filter/map_file.hpp>
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <system_error>

#include "ogf/adapters/message_adapters.hpp"
#include <ogf/odometry_t.hpp>

namespace ogf::mapper_daemon {

using adapters::decodePose;
using adapters::scanPointsOf;
using adapters::validateScan;

namespace {

using Clock = std::chrono::steady_clock;

// Milliseconds from `since` until now, for the log and the status.
double msSince(Clock::time_point since) {
  return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

// How far a command's utime may be from the mapper's clock (command_auth.hpp's replay rule): wide enough
// for hosts whose clocks agree to a few seconds (NTP), short enough that a recorded command soon expires.
constexpr std::int64_t kCommandWindowUs = 30'000'000;

// A worker that has not come round its loop for this long is stuck (the watchdog stops being fed).
constexpr std::int64_t kWorkerStuckUs = 10'000'000;

// Seconds between two microsecond times, for the log.
double secondsBetween(std::int64_t later, std::int64_t earlier) { return static_cast<double>(later - earlier) * 1e-6; }

// Whether a message whose clock TimeSanity judged (before check() took it in) goes on; logs a refusal
// (rate-limited) with the times it was judged against, or a followed jump.
bool timePlausible(const char* what, fusion::TimeVerdict verdict, const fusion::TimeSanity& clock,
                   std::optional<std::int64_t> expected, std::int64_t utime, std::int64_t wall_utime,
                   transport::LogRateLimiter& log) {
  using fusion::TimeVerdict;
  if (verdict == TimeVerdict::kAccept) return true;
  if (verdict == TimeVerdict::kFollowJump) {
    spdlog::warn("{} clock jumped from {} to {} (host clock {}): followed after consistent messages", what,
                 clock.timeBeforeLastJump() ? std::to_string(*clock.timeBeforeLastJump()) : "none", utime, wall_utime);
    return true;
  }
  const auto n = log.allow();
  if (!n) return false;
  const double max_ahead_s = static_cast<double>(clock.maxAheadUs()) * 1e-6;
  std::string why;
  if (verdict == TimeVerdict::kAheadOfHost) {
    why = fmt::format("{:.3f} s ahead of the host clock {} (at most {} s is plausible)", secondsBetween(utime, wall_utime),
                      wall_utime, max_ahead_s);
  } else if (verdict == TimeVerdict::kAheadOfStream && expected) {
    why = fmt::format("{:.3f} s ahead of the stream, which is expected at {} (its newest time {} plus the host time "
                      "since; at most {} s beyond is plausible)",
                      secondsBetween(utime, *expected), *expected, clock.reference().value_or(0), max_ahead_s);
  } else {
    why = fmt::format("{:.3f} s behind the stream's newest time {} (at most {} s is plausible)",
                      secondsBetween(clock.reference().value_or(utime), utime), clock.reference().value_or(0),
                      static_cast<double>(clock.maxBehindUs()) * 1e-6);
  }
  spdlog::warn("{} at {} refused: {}; host clock {} ({} more)", what, utime, why, wall_utime, *n);
  return false;
}

}  // namespace

std::int64_t MapperDaemon::steadyUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
}

std::int64_t MapperDaemon::wallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

Result<std::unique_ptr<MapperDaemon>> MapperDaemon::create(const MapperOptions& options, lcm::LCM& lcm,
                                                           transport::DaemonLoop& loop) {
  if (auto st = options.validate(); !st) return st.error();
  auto mapper = pipeline::ScanMapper::create(options.map);
  if (!mapper) return mapper.error();
  std::optional<correction::ScanPoseCorrection> correction;
  if (options.pose_correction.corrector.mode != slam::CorrectionMode::kNone) {
    auto c = correction::ScanPoseCorrection::create(options.pose_correction);
    if (!c) return c.error().within("pose_correction");
    correction.emplace(std::move(*c));
  }
  std::optional<CommandKey> key;
  if (options.services.commands_enabled) {
    // Never start accepting commands with a key others could read or that is not ours.
    auto k = loadCommandKey(options.services.key_file);
    if (!k) return k.error().within("services.key_file");
    key = *k;
  }
  std::unique_ptr<MapperDaemon> d(new MapperDaemon(options, lcm, loop, std::move(*mapper), std::move(correction)));
  d->command_key_ = key;
  d->restore();
  return d;
}

MapperDaemon::MapperDaemon(const MapperOptions& options, lcm::LCM& lcm, transport::DaemonLoop& loop,
                           pipeline::ScanMapper mapper, std::optional<correction::ScanPoseCorrection> correction)
    : options_(options),
      lcm_(lcm),
      loop_(loop),
      static_map_from_sensor_(options.static_pose.bodyFromSensor() * options.map.fusion.extrinsic.bodyFromSensor()),
      mapper_(std::move(mapper)),
      correction_(std::move(correction)),
      deltas_({options.map.filter.resolution, newMapId(), ogf::messages::kMaxDeltaCellsPerMessage}),
      drop_rng_(options.test_seed),
      poses_(options.map.fusion.pose_buffer),
      pending_(options.map.fusion.pending),
      pose_clock_(options.map.fusion.time_sanity),
      scan_clock_(options.map.fusion.time_sanity),
      inputs_(inputWatchConfig(), steadyUtime()),
      replay_guard_(wallUtime(), kCommandWindowUs),
      status_timer_(loop.io()) {
  stats_.persistence_ok = true;
}

MapperDaemon::~MapperDaemon() { stop(); }

void MapperDaemon::persistenceFailed(const std::string& what, bool retry) {
  std::lock_guard lk(mu_);
  // Said once per failure, not at every retry that meets the same one.
  if (stats_.persistence_ok || stats_.persistence_error != what)
    spdlog::error("persistence: {}; mapping goes on in memory{}", what,
                  retry ? ", the state directory is tried again at each snapshot" : "");
  stats_.persistence_ok = false;
  stats_.persistence_error = what;
  retry_persistence_ = retry;
}

bool MapperDaemon::applyRecovered(const persistence::RecoveredState& rec, const std::string& snapshot_source) {
  for (const auto& note : rec.notes) spdlog::warn("state directory: {}", note);
  if (!rec.snapshot_map.empty()) {
    if (auto st = mapper_.restoreFilter(rec.snapshot_map, snapshot_source); !st) {
      spdlog::error("state directory: {}; starting a new map", st.error().message);
      return false;
    }
  }
  if (!rec.pages.empty()) {
    openPager(options_.state_dir / "pages", true);
    if (!pager_) {
      // Never write over a saved map whose pages could not even be listed.
      spdlog::error("state directory: the map's pages in {} cannot be read; starting a new map",
                    (options_.state_dir / "pages").string());
      if (auto fresh = pipeline::ScanMapper::create(options_.map)) mapper_ = std::move(*fresh);
      return false;
    }
    reportPageDamage(pager_->adopt(rec.pages, mapper_.filter()));
  }
  for (const auto& r : rec.replay) {
    if (pager_) reportPageDamage(pager_->bringIn(mapper_.filter(), r.measurements));
    mapper_.apply(r.measurements);
  }
  // The published map is built from the filter's cells in memory and the published cells the pages hold
  // (restore()); pages of the first version hold none, so their regions come back for it.
  if (pager_) reportPageDamage(pager_->bringInUnpublished(mapper_.filter()));
  snapshot_seq_ = rec.snapshot_seq;
  // The whole map's cells and checksum, paged-out regions included, as the status reports them.
  const auto& map = mapper_.filter();
  const filter::BlockHashSum held = pager_ ? pager_->heldBlocks() : filter::BlockHashSum{};
  // The map id the delta stream, queries and command replies carry: a restart is a new stream for clients
  // (they take a keyframe), so this run's id, not the one the state directory's files were written under.
  spdlog::info("restored map {} at seq {} (snapshot {} + {} journal records): {} cells, filter checksum {:016x}",
               deltas_.mapId(), rec.last_seq, rec.snapshot_seq, rec.replay.size(),
               map.allocatedCells() + held.blocks * map.cellsPerBlock(), map.checksum(held));
  return true;
}

void MapperDaemon::restore() {
  std::int64_t seq = 0;
  if (!options_.state_dir.empty()) {
    auto dir = persistence::StateDirectory::open(options_.state_dir);
    if (!dir) {
      persistenceFailed(dir.error().message, true);
      // A directory that can be read but not written (read-only): still map on from the saved map, so that
      // once it is writable again the next snapshot holds the saved map and what was mapped since, instead
      // of replacing it with a map that lacks it.
      auto rec = persistence::StateDirectory::read(options_.state_dir, newMapId());
      if (!rec) {
        spdlog::error("state directory: {}; starting a new map in memory and not persisting", rec.error().message);
        retry_persistence_ = false;  // never write over a map that could not be read
      } else if (applyRecovered(*rec, (options_.state_dir / "snapshot.ogfs").string())) {
        seq = rec->last_seq;
      } else {
        retry_persistence_ = false;
      }
    } else {
      auto rec = dir->recover(newMapId(), wallUtime());
      const bool damaged = !rec && rec.error().is(ErrorKind::input_damaged);
      if (damaged) {
        // Never half-load a map, and never overwrite one that could still be rescued: set it aside.
        const auto aside = dir->setAside(wallUtime());
        spdlog::error("state directory: {}; moved to {} and starting a new map", rec.error().message,
                      aside ? aside->string() : aside.error().message);
        rec = dir->recover(newMapId(), wallUtime());
      }
      if (!rec && !damaged) {
        // Not known to be damaged (an I/O or resource error): the files stay as they are and nothing is
        // written over them; the next start reads them again.
        persistenceFailed(rec.error().message + "; the state directory is left as it is and not written", false);
      } else if (!rec) {
        persistenceFailed(rec.error().message, true);
      } else if (applyRecovered(*rec, dir->snapshotPath().string())) {
        seq = rec->last_seq;
        state_.emplace(std::move(*dir));
        if (!pager_) openPager(state_->pagesDir());
        if (!rec->damage.empty()) {
          // Restored around damage: said until the next snapshot holds the map again.
          spdlog::error("state directory: {}", rec->damage);
          std::lock_guard lk(mu_);
          stats_.persistence_ok = false;
          stats_.persistence_error = rec->damage;
        }
      } else {
        persistenceFailed("the saved map cannot be restored (it does not fit the configuration, or its pages cannot be read; see the log); not persisting", false);
      }
    }
  }
  const auto cells = mapper_.publishedCells();
  deltas_.reset(cells, seq);
  if (pager_) pager_->holdPublished(deltas_.map());
  std::lock_guard lk(mu_);
  stats_.delta_seq = seq;
  fillMapStats();
}

void MapperDaemon::openPager(const std::filesystem::path& pages_dir, bool holds_pages) {
  pager_.reset();
  paging_failed_ = false;
  if (!(options_.page_out_distance_m > 0) && !holds_pages) return;
  const double reach =
      persistence::MapPager::churnDistance(options_.map.fusion.measurement.max_range_m, options_.map.filter.resolution);
  if (options_.page_out_distance_m > 0 && options_.page_out_distance_m < reach)
    spdlog::warn("paging: page_out_distance_m {} m is within the scans' reach (max_range plus two regions, {:.1f} m): "
                 "regions will go out and come back scan after scan (the map is the same, the disk busier)",
                 options_.page_out_distance_m, reach);
  auto pager = persistence::MapPager::open(pages_dir);
  if (!pager) {
    spdlog::error("paging: {}; the whole map stays in memory", pager.error().message);
    return;
  }
  pager_.emplace(std::move(*pager));
}

void MapperDaemon::reportPageDamage(const std::vector<persistence::PageDamage>& damage) {
  for (const auto& d : damage) {
    const std::string what = d.reason + "; the cells of its region are lost";
    spdlog::error("paging: {}", what);
    std::lock_guard lk(mu_);
    stats_.persistence_ok = false;
    stats_.persistence_error = what;
  }
}

void MapperDaemon::pageOut() {
  if (!pager_ || paging_failed_ || !(options_.page_out_distance_m > 0)) return;
  const Eigen::Vector3d at = mapper_.sensorOrigin();
  if (auto st = pager_->sendAway(mapper_.filter(), {at.x(), at.y(), at.z()}, options_.page_out_distance_m,
                                 &deltas_.map());
      !st) {
    // The regions not written stay in memory; those already out still come back when needed.
    paging_failed_ = true;
    spdlog::error("paging: {}; the map stays in memory from now on", st.error().message);
  }
}

void MapperDaemon::fillMapStats() {
  const auto& map = mapper_.filter();
  const filter::BlockHashSum held = pager_ ? pager_->heldBlocks() : filter::BlockHashSum{};
  stats_.cells = static_cast<std::int64_t>(map.allocatedCells() + held.blocks * map.cellsPerBlock());
  stats_.memory_bytes = mapMemoryBytes();
  stats_.filter_checksum = static_cast<std::int64_t>(map.checksum(held));
}

void MapperDaemon::start() {
  if (started_) return;
  started_ = true;
  scan_sub_ = std::make_unique<transport::Subscriber<ogf::lidar_scan_t>>(
      lcm_, options_.scan_channel,
      [this](const ogf::lidar_scan_t& s, const lcm::ReceiveBuffer& rb, const std::string&) { onScan(s, rb); },
      [this](const std::string& ch, std::size_t size, std::string_view why) {
        {
          std::lock_guard lk(mu_);
          ++malformed_scans_;
          inputs_.scanArrived(steadyUtime());
        }
        if (auto n = bad_scan_log_.allow()) spdlog::warn("scan on {} ({} bytes) {} ({} more)", ch, size, why, *n);
      });
  request_sub_ = std::make_unique<transport::Subscriber<ogf::map_request_t>>(
      lcm_, options_.request_channel,
      [this](const ogf::map_request_t& r, const lcm::ReceiveBuffer&, const std::string&) {
        spdlog::debug("keyframe requested by {} (last seq {})", r.requester, r.last_seq);
        std::lock_guard lk(mu_);
        ++requests_;
        keyframe_requested_ = true;
        work_ = true;
        cv_.notify_one();
      },
      [this](const std::string& ch, std::size_t size, std::string_view why) {
        {
          std::lock_guard lk(mu_);
          ++malformed_requests_;
        }
        if (auto n = bad_request_log_.allow()) {
          spdlog::warn("map request on {} ({} bytes) {} ({} more)", ch, size, why, *n);
        }
      });
  subscribeServices();
  pose_sub_ = lcm_.subscribeFunction(
      options_.pose_channel,
      +[](const lcm::ReceiveBuffer* rb, const std::string&, MapperDaemon* self) { self->onPose(*rb); }, this);
  if (pose_sub_ != nullptr) pose_sub_->setQueueCapacity(transport::kSubscriptionQueueCapacity);
  {
    std::lock_guard lk(mu_);
    worker_heartbeat_ = steadyUtime();
    // The inputs' silence counts from now, not from before restoring the map (a long journal replay).
    inputs_ = fusion::InputWatch(inputWatchConfig(), steadyUtime());
  }
  keyframe_sender_ = std::make_unique<KeyframeSender>(
      [this](const ogf::map_delta_t& m) { lcm_.publish(options_.delta_channel, &m); },
      [this](const KeyframeSender::Report& r) { keyframeSent(r); });
  worker_ = std::thread([this] { workerLoop(); });
  armStatusTimer();
}

void MapperDaemon::stop() {
  if (!started_ || stopped_) return;
  stopped_ = true;
  {
    std::lock_guard lk(mu_);
    stop_ = true;
    cv_.notify_one();
  }
  if (worker_.joinable()) worker_.join();
  finishExport(true);
  keyframe_sender_.reset();
  {
    std::lock_guard lk(mu_);
    const auto& pc = pending_.counts();
    // The filter checksum is the status's filter_checksum and ogf-map's checksum of the same scans.
    spdlog::info("stopping: {} scans in, {} mapped, {} dropped behind, {} without poses; {} keyframes sent; "
                 "filter checksum {:016x}",
                 pc.scans_in + malformed_scans_, stats_.scans_mapped, pc.scans_dropped_behind,
                 pc.scans_dropped_no_pose, stats_.keyframes_sent,
                 static_cast<std::uint64_t>(stats_.filter_checksum));
  }
  boost::system::error_code ec;
  status_timer_.cancel(ec);
  if (pose_sub_ != nullptr) lcm_.unsubscribe(pose_sub_);
  pose_sub_ = nullptr;
  scan_sub_.reset();
  request_sub_.reset();
  query_sub_.reset();
  command_sub_.reset();
  takeSnapshot(true);
}

bool MapperDaemon::healthy() const {
  std::lock_guard lk(mu_);
  return !stop_ && steadyUtime() - worker_heartbeat_ < kWorkerStuckUs;
}

void MapperDaemon::onScan(const ogf::lidar_scan_t& scan, const lcm::ReceiveBuffer&) {
  if (auto st = validateScan(scan); !st) {
    {
      std::lock_guard lk(mu_);
      ++malformed_scans_;
      inputs_.scanArrived(steadyUtime());
    }
    if (auto n = bad_scan_log_.allow()) spdlog::warn("scan seq {} rejected: {} ({} more)", scan.seq, st.error().message, *n);
    return;
  }
  auto owned = std::make_shared<const ogf::lidar_scan_t>(scan);
  const fusion::ScanTimeSpan span = fusion::timeSpanOf(scanPointsOf(*owned, options_.time_base));
  std::lock_guard lk(mu_);
  const std::int64_t wall = wallUtime(), steady = steadyUtime();
  inputs_.scanArrived(steady);
  watchClocks(scan);  // before the time checks: a scan on another clock than the odometry is told apart
  const auto expected = scan_clock_.expectedAt(steady);
  const auto verdict = scan_clock_.check(span.end_utime, wall, steady);
  if (!timePlausible("scan", verdict, scan_clock_, expected, span.end_utime, wall, bad_time_log_)) return;
  if (verdict == fusion::TimeVerdict::kFollowJump) pending_.restartClock();
  const auto outcome = pending_.push({span.begin_utime, span.end_utime, static_cast<std::size_t>(scan.num_points)},
                                     std::move(owned), poses_, steady);
  if (outcome == fusion::PushOutcome::kLate) {
    if (auto n = bad_scan_log_.allow()) spdlog::warn("scan seq {} arrived after a newer one: dropped ({} more)", scan.seq, *n);
  }
  work_ = true;
  cv_.notify_one();
}

void MapperDaemon::onPose(const lcm::ReceiveBuffer& rb) {
  if (staticPose()) {
    std::lock_guard lk(mu_);
    inputs_.poseArrived(steadyUtime());
    poseIgnored();
    return;
  }
  auto pose = decodePose(rb.data, rb.data_size);
  if (!pose) {
    {
      std::lock_guard lk(mu_);
      ++malformed_poses_;
      inputs_.poseArrived(steadyUtime());
    }
    if (auto n = bad_pose_log_.allow())
      spdlog::warn("message on {} ({} bytes): {} ({} more)", options_.pose_channel, rb.data_size, pose.error().message, *n);
    return;
  }
  fusion::PoseInsertResult r;
  {
    std::lock_guard lk(mu_);
    // A pose refused for its content is counted as such by insert(), whatever its time.
    const std::int64_t wall = wallUtime(), steady = steadyUtime();
    inputs_.poseArrived(steady);
    const auto expected = pose_clock_.expectedAt(steady);
    const auto verdict = poses_.contentRejection(*pose) == fusion::PoseRejection::kNone
                             ? pose_clock_.check(pose->utime, wall, steady)
                             : fusion::TimeVerdict::kAccept;
    if (!timePlausible("pose", verdict, pose_clock_, expected, pose->utime, wall, bad_time_log_)) return;
    if (verdict == fusion::TimeVerdict::kFollowJump) poses_.clear();
    r = poses_.insert(*pose);
    if (r.accepted()) last_pose_steady_ = steadyUtime();
    work_ = true;
    cv_.notify_one();
  }
  if (!r.accepted()) {
    static constexpr const char* kWhy[] = {"",         "out of order",          "at a duplicate time",
                                           "not finite", "not a unit quaternion", "absurdly far from the origin"};
    if (auto n = bad_pose_log_.allow())
      spdlog::warn("pose at {} rejected: {} ({} more)", pose->utime, kWhy[static_cast<int>(r.rejection)], *n);
  } else if (r.jump) {
    if (auto n = jump_log_.allow())
      spdlog::warn("odometry jumped {:.3f} m / {:.3f} rad at {}: beyond max_pose_jump, scans spanning it are dropped ({} more)",
                   r.step_translation_m, r.step_rotation_rad,
                   pose->utime, *n);
  }
}

void MapperDaemon::workerLoop() {
  const auto snapshot_us = static_cast<std::int64_t>(options_.snapshot_interval_s * 1e6);
  const auto keyframe_us = static_cast<std::int64_t>(options_.keyframe_interval_s * 1e6);
  last_snapshot_steady_ = last_keyframe_steady_ = steadyUtime();
  std::unique_lock lk(mu_);
  while (!stop_) {
    cv_.wait_for(lk, std::chrono::milliseconds(20), [this] { return stop_ || work_; });
    work_ = false;
    worker_heartbeat_ = steadyUtime();
    watchInputs();
    // Scans whose poses have arrived (every scan, with a static pose), oldest first; waiting ones expire
    // inside popReady. Keyframes, map services and snapshots come between two scans, also while scans keep
    // arriving faster than they are mapped: the loop leaves for them and comes straight back.
    bool more = false;
    while (!stop_) {
      auto entry = staticPose() ? pending_.popOldest() : pending_.popReady(poses_, steadyUtime());
      if (!entry) break;
      const ScanPtr scan = std::move(entry->payload);
      const auto t0 = Clock::now();
      const fusion::ScanPoints points = scanPointsOf(*scan, options_.time_base);
      // With pose correction only the placing needs the pose buffer's lock; the correction (an RBPF may
      // take a while) runs after it is released, so odometry and scans keep arriving meanwhile.
      fusion::PoseCoverage coverage = fusion::PoseCoverage::kCovered;
      if (!staticPose()) coverage = correction_ ? mapper_.place(points, poses_) : mapper_.measure(points, poses_);
      lk.unlock();
      if (staticPose()) mapper_.measureStatic(points, static_map_from_sensor_);
      if (coverage == fusion::PoseCoverage::kCovered) {
        if (correction_) {
          correction::ScanCorrection applied;
          mapper_.measurePlaced(*correction_, &applied);
          publishCorrectedPose(mapper_.referencePose().utime, applied);
        }
        mapScan(scan);
      }
      const double ms = msSince(t0);
      lk.lock();
      worker_heartbeat_ = steadyUtime();
      if (coverage == fusion::PoseCoverage::kCovered) {
        stats_.update_ms_last = static_cast<float>(ms);
        update_ms_sum_ += ms;
        ++update_count_;
        stats_.lag_ms = static_cast<float>(static_cast<double>(wallUtime() - scan->host_utime_end) / 1000.0);
      }
      const auto now = steadyUtime();
      const bool keyframe_due = (keyframe_requested_ || keyframe_waiting_ || now - last_keyframe_steady_ > keyframe_us) &&
                                !keyframe_sender_->busy();
      if (keyframe_due || !service_requests_.empty() || box_job_ || snapshotWritten() || exportWritten() ||
          ((state_ || retry_persistence_) && now - last_snapshot_steady_ > snapshot_us)) {
        more = true;
        break;
      }
    }
    const bool keyframe = keyframe_requested_;
    keyframe_requested_ = false;
    lk.unlock();
    serve();
    finishExport(false);
    more = more || servicesWaiting();
    const auto now = steadyUtime();
    // A keyframe asked for while one is going out follows it; a periodic one waits for the sender.
    keyframe_waiting_ = keyframe_waiting_ || keyframe;
    if (keyframe_waiting_ || now - last_keyframe_steady_ > keyframe_us) {
      if (publishKeyframe()) keyframe_waiting_ = false;
    }
    finishSnapshotWrite(false);
    if ((state_ || retry_persistence_) && now - last_snapshot_steady_ > snapshot_us) takeSnapshot();
    lk.lock();
    work_ = work_ || more;
  }
}

void MapperDaemon::mapScan(const ScanPtr& scan) {
  const auto measurements = mapper_.measurements();
  const std::int64_t seq = deltas_.seq() + 1;
  // Write-ahead: the journal holds the scan before the map changes, so what a client is told exists on disk.
  if (state_) {
    if (auto st = state_->journal(seq, scan->utime, measurements); !st) {
      state_.reset();
      persistenceFailed(st.error().message, true);
    }
  }
  changes_.clear();
  if (pager_) reportPageDamage(pager_->bringIn(mapper_.filter(), measurements, &deltas_.map()));
  mapper_.apply(measurements, &changes_);
  auto msgs = deltas_.update(scan->utime, changes_);
  pageOut();  // after the delta: the published cells of a region leave with it
  const bool drop = options_.test_drop_delta_fraction > 0 &&
                    std::uniform_real_distribution<double>(0, 1)(drop_rng_) < options_.test_drop_delta_fraction;
  if (!drop) {
    for (const auto& m : msgs) lcm_.publish(options_.delta_channel, &m);
  }
  std::lock_guard lk(mu_);
  ++stats_.scans_mapped;
  stats_.measurements += static_cast<std::int64_t>(measurements.size());
  stats_.delta_seq = deltas_.seq();
  fillMapStats();
}

std::int64_t MapperDaemon::mapMemoryBytes() const {
  return static_cast<std::int64_t>(mapper_.filter().memoryBytes() + deltas_.map().memoryBytes());
}

void MapperDaemon::publishCorrectedPose(std::int64_t utime, const correction::ScanCorrection& applied) {
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

bool MapperDaemon::publishKeyframe() {
  if (keyframe_sender_->busy()) return false;
  last_keyframe_steady_ = steadyUtime();
  // The cells in memory are copied now; the pages holding the rest are read by the sender.
  const auto began = Clock::now();
  KeyframeSender::Job job{delta::KeyframeWriter(deltas_, wallUtime()), deltas_.map().sortedCells(),
                          pager_ ? pager_->heldPublishedPages() : std::vector<std::filesystem::path>{}, 0.0};
  job.cut_ms = msSince(began);
  keyframe_sender_->send(std::move(job));
  return true;
}

void MapperDaemon::keyframeSent(const KeyframeSender::Report& r) {
  reportPageDamage(r.damage);
  spdlog::info("keyframe at seq {}: {} cells ({} from pages) in {} parts; cut in {:.0f} ms, sent in {:.0f} ms{}", r.seq,
               r.cells, r.page_cells, r.parts, r.cut_ms, r.send_ms,
               r.missing + r.surplus == 0 ? std::string()
                                          : fmt::format(" ({} cells missing, {} beyond the count)", r.missing, r.surplus));
  std::lock_guard lk(mu_);
  ++stats_.keyframes_sent;
}

void MapperDaemon::takeSnapshot(bool wait) {
  finishSnapshotWrite(wait);
  if (snapshot_write_) return;  // still being written: the next check between scans puts it in place
  last_snapshot_steady_ = steadyUtime();
  if (!state_ && retry_persistence_) {
    // Persistence failed earlier (no space, read-only, I/O error): try the directory again, starting over
    // with a full snapshot of the map in memory.
    auto dir = persistence::StateDirectory::open(options_.state_dir);
    if (!dir) return persistenceFailed(dir.error().message, true);
    auto rec = dir->recover(deltas_.mapId());
    if (!rec) return persistenceFailed(rec.error().message, true);
    state_.emplace(std::move(*dir));
    snapshot_seq_ = -1;
    if (!pager_) openPager(state_->pagesDir());
  }
  if (!state_ || snapshot_seq_ == deltas_.seq()) return;
  // The map in memory, and the pages holding the rest (a page is written before its region leaves memory;
  // the writer's thread flushes the new ones before the snapshot that names them).
  SnapshotWrite w;
  w.began = Clock::now();
  w.seq = deltas_.seq();
  auto bytes = filter::encodeMap(mapper_.filter());
  w.bytes = bytes.size();
  w.encode_ms = msSince(w.began);
  if (pager_) {
    w.pages = pager_->files();
    w.page_flush = pager_->takeUnsynced();
  }
  if (auto st = state_->beginSnapshot(w.seq); !st) {
    if (pager_) pager_->giveBackUnsynced(w.page_flush);
    state_.reset();
    persistenceFailed(st.error().message, true);
    return;
  }
  auto write = std::make_shared<std::function<SnapshotWritten()>>(
      [path = state_->snapshotPath(), id = state_->mapId(), seq = w.seq, bytes = std::move(bytes),
       pages = w.pages, flush = w.page_flush, retired = state_->retiredJournalPath()] {
        SnapshotWritten done;
        const auto began = Clock::now();
        done.status = persistence::MapPager::flushPages(flush);
        done.flush_ms = msSince(began);
        const auto flushed = Clock::now();
        if (!done.status) return done;
        done.status = persistence::StateDirectory::writeSnapshotFile(path, id, seq, bytes, pages);
        if (done.status) persistence::StateDirectory::retireOldJournal(retired);
        done.write_ms = msSince(flushed);
        return done;
      });
  try {
    w.written = std::async(std::launch::async, [write] { return (*write)(); });
  } catch (const std::system_error& e) {
    // No thread to be had (resource limits): the snapshot is written here, holding up mapping meanwhile.
    spdlog::warn("snapshot: no thread to write it on ({}); written on the worker", e.what());
    std::promise<SnapshotWritten> now;
    now.set_value((*write)());
    w.written = now.get_future();
  }
  w.cut_ms = msSince(w.began);
  snapshot_write_ = std::move(w);
  if (wait) finishSnapshotWrite(true);
}

bool MapperDaemon::snapshotWritten() const {
  return snapshot_write_ && snapshot_write_->written.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

void MapperDaemon::finishSnapshotWrite(bool wait) {
  if (!snapshot_write_ || (!wait && !snapshotWritten())) return;
  SnapshotWrite w = std::move(*snapshot_write_);
  snapshot_write_.reset();
  const SnapshotWritten written = w.written.get();
  Status st = written.status;
  if (!st && pager_) pager_->giveBackUnsynced(w.page_flush);  // flushed by the next snapshot
  // Persistence failed while the file was written (a journal write): the directory is opened anew later.
  if (!state_) return;
  if (st) st = state_->finishSnapshot(w.pages);
  if (!st) {
    state_->abandonSnapshot();
    state_.reset();
    persistenceFailed(st.error().message, true);
    return;
  }
  if (pager_) {
    // The pages a keyframe going out still reads stay too.
    auto keep = state_->referencedPages();
    const auto pinned = keyframe_sender_ ? keyframe_sender_->pinnedPages() : std::vector<std::string>{};
    keep.insert(keep.end(), pinned.begin(), pinned.end());
    pager_->collect(keep);
  }
  snapshot_seq_ = w.seq;
  spdlog::info("snapshot at seq {}: {} bytes and {} pages in {:.0f} ms; the worker {:.0f} ms (encoding {:.0f}), "
               "its own thread flushing {} new pages {:.0f} ms and writing the file {:.0f} ms",
               snapshot_seq_, w.bytes, w.pages.size(), msSince(w.began), w.cut_ms, w.encode_ms,
               w.page_flush.names.size(), written.flush_ms, written.write_ms);
  std::lock_guard lk(mu_);
  if (!stats_.persistence_ok) spdlog::info("persistence: {} is written again; the map is saved at seq {}",
                                           options_.state_dir.string(), snapshot_seq_);
  stats_.persistence_ok = true;
  stats_.persistence_error.clear();
}

void MapperDaemon::armStatusTimer() {
  status_timer_.expires_after(std::chrono::microseconds(static_cast<std::int64_t>(options_.status_interval_s * 1e6)));
  status_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    publishStatus();
    armStatusTimer();
  });
}

void MapperDaemon::publishStatus() {
  ogf::mapper_status_t s;
  {
    std::lock_guard lk(mu_);
    s = stats_;
    const auto& pc = pending_.counts();
    s.scans_in = pc.scans_in + malformed_scans_;
    s.scans_dropped_behind = pc.scans_dropped_behind;
    s.scans_dropped_no_pose = pc.scans_dropped_no_pose;
    s.scans_late = pc.scans_late;
    s.scans_rejected = pc.scans_rejected + malformed_scans_;
    s.poses_in = poses_.counts().accepted + poses_.counts().rejected() + malformed_poses_;
    s.poses_rejected = poses_.counts().rejected() + malformed_poses_;
    s.requests_in = requests_ + malformed_requests_;
    s.requests_rejected = malformed_requests_;
    s.scans_refused_time = scan_clock_.counts().refused();
    s.poses_refused_time = pose_clock_.counts().refused();
    s.clock_jumps = scan_clock_.counts().jumps_followed + pose_clock_.counts().jumps_followed;
    s.pose_jumps = poses_.counts().jumps;
    s.scans_dropped_pose_jump = pc.scans_dropped_pose_jump;
    s.scans_in += s.scans_refused_time;
    s.poses_in += s.poses_refused_time;
    s.service_requests_in = service_in_;
    s.service_requests_refused = service_refused_;
    s.update_ms_mean = update_count_ > 0 ? static_cast<float>(update_ms_sum_ / update_count_) : 0.0f;
    update_ms_sum_ = 0;
    update_count_ = 0;
    fillClockStatus(s);
    fillInputStatus(s);
  }
  s.utime = wallUtime();
  lcm_.publish(options_.status_channel, &s);
}

}  // namespace ogf::mapper_daemon
