// ogf-mapper's coordinator (mapper_daemon.hpp): builds the parts, starts and stops them, and runs the
// worker's loop: the scans that are ready, then keyframes, map services and snapshots between two scans.
#include "ogf/mapper_daemon/mapper_daemon.hpp"

#include <ogf/messages/limits.hpp>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>

#include "map_id.hpp"
#include "ogf/adapters/message_adapters.hpp"
#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/pipeline/published_cells.hpp"

namespace ogf::mapper_daemon {

namespace {

// A worker that has not come round its loop for this long is stuck (the watchdog stops being fed).
constexpr std::int64_t kWorkerStuckUs = 10'000'000;

// The occupied-priority rule holds a cell's hit through free_release_scans free scans in a row
// (filter/filter_config.hpp): a window of time at one sensor's rate. With several sources a cell hears from
// each of them in that time, so the window counts that many scans per source (at most the 127 a cell's mark
// holds); otherwise a second robot's grazing rays release the floor the first one hits, and cells both
// maps alone call occupied turn unknown in the shared one.
MapperOptions withSourceWindow(MapperOptions options, std::size_t sources) {
  int& release = options.map.filter.freeReleaseCount;
  if (release > 0 && sources > 1) {
    const int scaled = std::min<int>(release * static_cast<int>(sources), filter::kMaxFreeRelease);
    spdlog::info("occupied priority: a hit is held through {} free scans in a row (free_release_scans {} for each of "
                 "{} sources)", scaled, release, sources);
    release = scaled;
  }
  return options;
}

}  // namespace

Result<std::unique_ptr<MapperDaemon>> MapperDaemon::create(const MapperOptions& configured, lcm::LCM& lcm,
                                                           lcm::LCM* service_bus, transport::DaemonLoop& loop) {
  if (auto st = configured.validate(); !st) return st.error();
  auto sources = ScanIntake::prepare(configured);
  if (!sources) return sources.error();
  const MapperOptions options = withSourceWindow(configured, sources->resolved.size());
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
  std::unique_ptr<MapperDaemon> d(new MapperDaemon(options, lcm, service_bus, loop, std::move(*mapper),
                                                   std::move(correction), std::move(key), std::move(*sources)));
  d->restore();
  return d;
}

MapperDaemon::MapperDaemon(const MapperOptions& options, lcm::LCM& lcm, lcm::LCM* service_bus,
                           transport::DaemonLoop& loop, pipeline::ScanMapper mapper,
                           std::optional<correction::ScanPoseCorrection> correction, std::optional<CommandKey> key,
                           ScanIntake::Sources sources)
    : options_(options),
      lcm_(lcm),
      service_bus_(service_bus),
      mapper_(std::move(mapper)),
      correction_(std::move(correction)),
      deltas_({options.map.filter.resolution, newMapId(), ogf::messages::kMaxDeltaCellsPerMessage}),
      intake_(options_, lcm, shared_, std::move(sources), loop.io()),
      persistence_(options_, mapper_, deltas_, shared_),
      services_(options_, lcm, shared_, mapper_, deltas_, persistence_, std::move(key),
                {[this] { resetMap(); }, [this] { refreshMapFigures(); }}),
      status_(options_, lcm, loop, shared_, intake_, services_),
      publisher_(options_, lcm, deltas_, persistence_, shared_),
      nav_(options_, lcm, shared_, deltas_.mapId()) {
  shared_.stats.persistence_ok = true;
  persistence_.setPinnedPages([this] { return publisher_.pinnedPages(); });
}

MapperDaemon::~MapperDaemon() { stop(); }

void MapperDaemon::restore() {
  const std::int64_t seq = persistence_.restore();
  const auto cells = mapper_.publishedCells();
  deltas_.reset(cells, seq);
  persistence_.holdPublished();
  const persistence::MapPager* pager = persistence_.pager();
  nav_.restored(cells, pager ? pager->heldPublishedPages() : std::vector<std::filesystem::path>{});
  refreshMapFigures();
}

void MapperDaemon::start() {
  if (started_) return;
  started_ = true;
  // Service traffic on its own bus and thread when there is one (udpm), else beside the scans.
  lcm::LCM& services_on = service_bus_ != nullptr ? *service_bus_ : lcm_;
  intake_.subscribe();
  services_.subscribe(services_on);
  nav_.subscribe(services_on);
  intake_.subscribeRequests(services_on);
  intake_.subscribePoses();
  if (service_bus_ != nullptr) service_dispatch_ = std::make_unique<transport::DispatchThread>(*service_bus_);
  {
    std::lock_guard lk(shared_.mu);
    shared_.worker_heartbeat = steadyUtime();
    intake_.restartInputWatch();
  }
  publisher_.start();
  worker_ = std::thread([this] { workerLoop(); });
  status_.start();
}

void MapperDaemon::stop() {
  if (!started_ || stopped_) return;
  stopped_ = true;
  {
    std::lock_guard lk(shared_.mu);
    shared_.stop = true;
    shared_.cv.notify_one();
  }
  if (worker_.joinable()) worker_.join();
  service_dispatch_.reset();  // no service handler runs from here on
  services_.finishExport(true);
  publisher_.stop();
  refreshMapFigures();
  {
    std::lock_guard lk(shared_.mu);
    const auto& pc = intake_.pendingCounts();
    // The filter checksum is the status's filter_checksum and ogf-map's checksum of the same scans.
    spdlog::info("stopping: {} scans in, {} mapped, {} dropped behind, {} without poses; {} keyframes sent; "
                 "filter checksum {:016x}",
                 intake_.scansIn(), shared_.stats.scans_mapped, pc.scans_dropped_behind, pc.scans_dropped_no_pose,
                 shared_.stats.keyframes_sent, static_cast<std::uint64_t>(shared_.stats.filter_checksum));
  }
  status_.stop();
  intake_.unsubscribe();
  services_.unsubscribe();
  nav_.unsubscribe();
  persistence_.takeSnapshot(true);
}

bool MapperDaemon::healthy() const {
  std::lock_guard lk(shared_.mu);
  return !shared_.stop && steadyUtime() - shared_.worker_heartbeat < kWorkerStuckUs;
}

void MapperDaemon::workerLoop() {
  const std::int64_t began = steadyUtime();
  persistence_.startClock(began);
  publisher_.startClock(began);
  std::unique_lock lk(shared_.mu);
  while (!shared_.stop) {
    shared_.cv.wait_for(lk, std::chrono::milliseconds(20), [this] { return shared_.stop || shared_.work; });
    shared_.work = false;
    shared_.worker_heartbeat = steadyUtime();
    intake_.watchInputs();
    // Keyframes, map services and snapshots come between two scans, also while scans keep arriving faster
    // than they are mapped: mapReadyScans leaves for them and the loop comes straight back.
    bool more = mapReadyScans(lk);
    const bool keyframe = intake_.takeKeyframeRequest();
    lk.unlock();
    more = betweenScans(keyframe) || more;
    lk.lock();
    shared_.work = shared_.work || more;
  }
}

bool MapperDaemon::mapReadyScans(std::unique_lock<std::mutex>& lk) {
  while (!shared_.stop) {
    // Scans whose poses have arrived (every scan, with a static pose), oldest first; waiting ones expire
    // on the way.
    auto entry = intake_.nextScan(steadyUtime());
    if (!entry) return false;
    SourceIntake& source = *entry->source;
    const ScanPtr scan = std::move(entry->entry.payload);
    const auto t0 = std::chrono::steady_clock::now();
    const fusion::ScanPoints points = adapters::scanPointsOf(*scan, source.source().time_base);
    mapper_.setBodyFromSensor(source.source().body_from_sensor);
    // With pose correction only the placing needs the pose buffer's lock; the correction (an RBPF may
    // take a while) runs after it is released, so odometry and scans keep arriving meanwhile.
    fusion::PoseCoverage coverage = fusion::PoseCoverage::kCovered;
    if (!staticPose())
      coverage = correction_ ? mapper_.place(points, source.poses()) : mapper_.measure(points, source.poses());
    lk.unlock();
    const bool covered = coverage == fusion::PoseCoverage::kCovered;
    if (covered) mapPlaced(points, scan, source);
    const double ms = msSince(t0);
    lk.lock();
    shared_.worker_heartbeat = steadyUtime();
    intake_.served(entry->index, std::llround(ms * 1e3));
    if (covered) status_.scanMapped(ms, scan->host_utime_end);
    if (dueBetweenScans()) return true;
  }
  return false;
}

void MapperDaemon::mapPlaced(const fusion::ScanPoints& points, const ScanPtr& scan, SourceIntake& source) {
  // With a static pose, the sensor in the map frame is static_pose after the source's extrinsic.
  if (staticPose()) mapper_.measureStatic(points, options_.static_pose.bodyFromSensor() * source.source().body_from_sensor);
  if (correction_) {
    correction::ScanCorrection applied;
    mapper_.measurePlaced(*correction_, &applied);
    publisher_.publishCorrectedPose(mapper_.referencePose().utime, applied);
  }
  mapScan(scan, source);
}

bool MapperDaemon::dueBetweenScans() {
  const auto now = steadyUtime();
  return shared_.status_waiting || publisher_.keyframeDue(intake_.keyframeRequested(), now) || services_.waitingLocked() ||
         persistence_.snapshotWritten() || services_.exportWritten() || persistence_.snapshotDue(now);
}

bool MapperDaemon::betweenScans(bool keyframe_requested) {
  services_.serve();
  services_.finishExport(false);
  const bool services_waiting = services_.waiting();
  const auto now = steadyUtime();
  publisher_.keyframeTurn(keyframe_requested, now);
  nav_.turn(now);
  persistence_.finishSnapshotWrite(false);
  if (persistence_.snapshotDue(now)) persistence_.takeSnapshot();
  answerStatus();
  return services_waiting;
}

void MapperDaemon::answerStatus() {
  {
    std::lock_guard lk(shared_.mu);
    if (!shared_.status_waiting) return;
  }
  refreshMapFigures();
  {
    std::lock_guard lk(shared_.mu);
    shared_.status_waiting = false;
  }
  status_.figuresReady();
}

void MapperDaemon::mapScan(const ScanPtr& scan, SourceIntake& source) {
  const auto measurements = mapper_.measurements();
  // Write-ahead: the journal holds the scan before the map changes, so what a client is told exists on disk.
  persistence_.journal(deltas_.seq() + 1, scan->utime, measurements);
  changes_.clear();
  persistence_.bringIn(measurements);
  mapper_.apply(measurements, &changes_);
  pipeline::refreshStaleSlabs(mapper_.filter(), deltas_);
  const auto deltas = deltas_.update(scan->utime, changes_);
  persistence_.pageOut();  // after the delta: the published cells of a region leave with it
  publisher_.publishDeltas(deltas);
  nav_.scanMapped(scan->utime, changes_, steadyUtime());
  std::lock_guard lk(shared_.mu);
  source.scanMapped(static_cast<std::int64_t>(measurements.size()), mapper_.sensorOrigin());
  shared_.figures_stale = true;  // the counts of this scan go into the status with the map's figures
}

void MapperDaemon::resetMap() {
  auto fresh = pipeline::ScanMapper::create(options_.map);
  if (!fresh) {
    spdlog::error("reset: {}", fresh.error().message);  // cannot happen: the same configuration built the map
    return;
  }
  // A keyframe of the old map going out would read pages about to be moved aside; a snapshot being
  // written goes into place first, so the old map is kept whole.
  publisher_.cancelKeyframe();
  persistence_.finishSnapshotWrite(true);
  mapper_ = std::move(*fresh);
  const std::int64_t id = newMapId();
  deltas_ = delta::DeltaStream({options_.map.filter.resolution, id, ogf::messages::kMaxDeltaCellsPerMessage});
  deltas_.reset(mapper_.publishedCells(), 0);
  persistence_.beginNewMap(id);
  persistence_.takeSnapshot();
  publisher_.keyframeOfNewMap();
  nav_.newMap(id, steadyUtime());
  refreshMapFigures();
}

void MapperDaemon::refreshMapFigures() {
  const MapFigures figures = mapFiguresOf(mapper_, deltas_, persistence_.heldBlocks());
  std::lock_guard lk(shared_.mu);
  // The map's scans and measurements are its sources'.
  shared_.stats.scans_mapped = 0;
  shared_.stats.measurements = 0;
  for (const auto& source : intake_.sources()) {
    source->reportMapped();
    shared_.stats.scans_mapped += source->scansReported();
    shared_.stats.measurements += source->measurementsReported();
  }
  shared_.stats.delta_seq = deltas_.seq();
  mapper_daemon::fillMapFigures(shared_.stats, figures);
  shared_.figures_stale = false;
}

}  // namespace ogf::mapper_daemon
