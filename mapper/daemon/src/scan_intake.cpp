// ogf-mapper's intake of scans, poses and keyframe requests (scan_intake.hpp): the sources and robots it
// is made of, the choice of the next scan among them, and their sums in the status.
#include "ogf/mapper_daemon/scan_intake.hpp"

#include <ogf/messages/limits.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/log_text.hpp"

namespace ogf::mapper_daemon {
namespace {

// The worker's time by which one source may be ahead of the least served ready one and still go first by
// age (fusion::FairShare): about one large scan, so sources that take alike keep the order of their clocks.
constexpr std::int64_t kShareSlackUs = 100'000;
// The most a source can bank while it sends nothing.
constexpr std::int64_t kShareWindowUs = 1'000'000;

}  // namespace

Result<ScanIntake::Sources> ScanIntake::prepare(const MapperOptions& options) {
  auto resolved = resolveSources(options);
  if (!resolved) return resolved.error();
  Sources sources;
  for (const ResolvedSource& source : *resolved) {
    auto packets = packetStreamFor(source);
    if (!packets) return packets.error();
    sources.packets.push_back(std::move(*packets));
  }
  sources.resolved = std::move(*resolved);
  return sources;
}

ScanIntake::ScanIntake(const MapperOptions& options, lcm::LCM& lcm, SharedState& shared, Sources sources,
                       boost::asio::io_context& io)
    : options_(options), lcm_(lcm), shared_(shared), share_(sources.resolved.size(), kShareSlackUs, kShareWindowUs) {
  const auto& resolved = sources.resolved;
  // With several sources (or robots) every log line says whose it is; one source logs as it always has.
  const bool several_sources = resolved.size() > 1;
  for (std::size_t i = 0; i < resolved.size(); ++i) {
    const ResolvedSource& source = resolved[i];
    RobotOdometry* robot = nullptr;
    for (const auto& r : robots_)
      if (r->robot() == source.robot) robot = r.get();
    if (robot == nullptr) {
      const bool several_robots = std::any_of(resolved.begin(), resolved.end(),
                                              [&](const ResolvedSource& s) { return s.robot != source.robot; });
      robots_.push_back(std::make_unique<RobotOdometry>(
          source.robot, source.pose_channel, several_robots ? "robot " + source.robot + ": " : "", options, shared));
      robot = robots_.back().get();
    }
    const std::string label = several_sources ? "source " + source.name + ": " : "";
    sources_.push_back(
        std::make_unique<SourceIntake>(source, label, std::move(sources.packets[i]), options, *robot, shared, io));
  }
}

void ScanIntake::subscribe() {
  for (auto& s : sources_) s->subscribe(lcm_);
}

void ScanIntake::subscribeRequests(lcm::LCM& bus) {
  // A request only raises a flag, so LCM need hold few of them.
  constexpr int kRequestQueueCapacity = 16;
  request_sub_ = std::make_unique<transport::Subscriber<ogf::map_request_t>>(
      bus, options_.request_channel,
      [this](const ogf::map_request_t& r, const lcm::ReceiveBuffer&, const std::string&) { onRequest(r); },
      [this](const std::string& ch, std::size_t size, std::string_view why) { onMalformedRequest(ch, size, why); },
      kRequestQueueCapacity, messages::kMaxMapRequestBytes);
}

void ScanIntake::subscribePoses() {
  for (auto& robot : robots_) {
    std::vector<SourceIntake*> mine;
    for (auto& s : sources_)
      if (s->source().robot == robot->robot()) mine.push_back(s.get());
    robot->subscribe(lcm_, [mine](std::int64_t steady) {
      for (SourceIntake* s : mine) s->poseArrived(steady);
    });
  }
}

void ScanIntake::unsubscribe() {
  for (auto& r : robots_) r->unsubscribe();
  for (auto& s : sources_) s->unsubscribe();
  request_sub_.reset();
}

void ScanIntake::restartInputWatch() {
  const std::int64_t now = steadyUtime();
  for (auto& s : sources_) s->restartInputWatch(now);
}

std::optional<ScanIntake::ReadyScan> ScanIntake::nextScan(std::int64_t now) {
  ready_.clear();
  for (std::size_t i = 0; i < sources_.size(); ++i) {
    if (const auto* entry = sources_[i]->readyFront(now)) ready_.push_back({i, entry->span.begin_utime});
  }
  const auto chosen = share_.choose(ready_);
  if (!chosen) return std::nullopt;
  const std::size_t index = ready_[*chosen].source;
  return ReadyScan{sources_[index].get(), index, sources_[index]->popFront()};
}

bool ScanIntake::takeKeyframeRequest() {
  const bool requested = keyframe_requested_;
  keyframe_requested_ = false;
  return requested;
}

void ScanIntake::watchInputs() {
  const std::int64_t now = steadyUtime();
  for (auto& s : sources_) s->watchInputs(now);
}

std::int64_t ScanIntake::scansIn() const {
  std::int64_t n = 0;
  for (const auto& s : sources_) n += s->scansIn();
  return n;
}

fusion::PendingScansCounts ScanIntake::pendingCounts() const {
  fusion::PendingScansCounts sum;
  for (const auto& s : sources_) sum += s->pendingCounts();
  return sum;
}

void ScanIntake::fillStatus(ogf::mapper_status_t& s) const {
  const std::int64_t now = steadyUtime();
  s.sources.clear();
  for (const auto& source : sources_) s.sources.push_back(source->status(now));
  s.num_sources = static_cast<std::int16_t>(s.sources.size());
  fillSums(s);
  fillInputs(s);
  s.requests_in = requests_ + malformed_requests_;
  s.requests_rejected = malformed_requests_;
}

void ScanIntake::fillSums(ogf::mapper_status_t& s) const {
  const auto pc = pendingCounts();
  std::int64_t malformed = 0, refused = 0, scan_jumps = 0, throttled = 0;
  for (const auto& source : sources_) {
    malformed += source->malformedScans();
    throttled += source->throttledScans();
    refused += source->scansRefusedTime();
    scan_jumps += source->clockJumps();
  }
  s.scans_refused_time = refused;
  s.scans_in = pc.scans_in + malformed + refused + throttled;
  s.scans_dropped_behind = pc.scans_dropped_behind;
  s.scans_dropped_no_pose = pc.scans_dropped_no_pose;
  s.scans_late = pc.scans_late;
  s.scans_rejected = pc.scans_rejected + malformed;
  s.scans_dropped_pose_jump = pc.scans_dropped_pose_jump;
  OdometryCounts poses;
  for (const auto& r : robots_) poses += r->counts();
  s.poses_in = poses.poses_in;
  s.poses_rejected = poses.poses_rejected;
  s.poses_refused_time = poses.poses_refused_time;
  s.clock_jumps = scan_jumps + poses.clock_jumps;
  s.pose_jumps = poses.pose_jumps;
  s.poses_ignored = poses.poses_ignored;
}

void ScanIntake::fillInputs(ogf::mapper_status_t& s) const {
  // The whole is OK only when every source is; else it says the first source that is not. The clocks are
  // those of that source (or the first), the ages the freshest of any source.
  const SourceIntake* shown = sources_.front().get();
  for (const auto& source : sources_) {
    if (source->inputState() != fusion::InputState::kOk) {
      shown = source.get();
      break;
    }
  }
  s.inputs = inputsCode(shown->inputState());
  shown->fillClocks(s.clocks, s.scan_clock, s.clock_offset_us);
  const auto freshest = [](float a, float b) { return a < 0 ? b : (b < 0 ? a : std::min(a, b)); };
  s.last_scan_age_s = -1.0f;
  s.last_pose_age_s = -1.0f;
  for (const auto& st : s.sources) {
    s.last_scan_age_s = freshest(s.last_scan_age_s, st.last_scan_age_s);
    s.last_pose_age_s = freshest(s.last_pose_age_s, st.last_pose_age_s);
  }
  s.pose_source = options_.pose_source == PoseSource::kStatic ? ogf::mapper_status_t::POSE_SOURCE_STATIC
                                                              : ogf::mapper_status_t::POSE_SOURCE_ODOMETRY;
}

void ScanIntake::onRequest(const ogf::map_request_t& r) {
  spdlog::debug("keyframe requested by {} (last seq {})", sanitisedForLog(r.requester), r.last_seq);
  std::lock_guard lk(shared_.mu);
  ++requests_;
  keyframe_requested_ = true;
  shared_.wake();
}

void ScanIntake::onMalformedRequest(const std::string& channel, std::size_t size, std::string_view why) {
  {
    std::lock_guard lk(shared_.mu);
    ++malformed_requests_;
  }
  if (auto n = bad_request_log_.allow()) {
    spdlog::warn("map request on {} ({} bytes) {} ({} more)", channel, size, why, *n);
  }
}

}  // namespace ogf::mapper_daemon
