// ogf-mapper's map services: OGF_MAP_QUERY → OGF_MAP_QUERY_REPLY (map_query_answer.hpp) and
// OGF_MAP_COMMAND → OGF_MAP_COMMAND_REPLY (save a snapshot now, reset the map, export it). Requests are
// received on the Asio thread, which refuses at once commands that are disabled, unauthenticated or
// replayed (command_auth.hpp); the rest wait in a queue of at most kMaxWaitingServices and the worker
// serves them between scans, for at most services.budget_ms_per_scan at a time. Every request gets
// exactly one reply, a refusal included; refusals are counted by reason in the status.
#include <ogf/filter/map_file.hpp>
#include <ogf/map_command_reply_t.hpp>
#include <ogf/map_io/cell_csv.hpp>
#include <ogf/map_io/cell_pcd.hpp>
#include <ogf/map_io/cell_ply.hpp>
#include <ogf/map_io/map_cells.hpp>
#include <ogf/map_io/octomap_export.hpp>
#include <ogf/messages/limits.hpp>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/log_text.hpp"
#include "ogf/mapper_daemon/map_export.hpp"
#include "ogf/mapper_daemon/map_query_answer.hpp"
#include "ogf/mapper_daemon/map_services.hpp"

namespace ogf::mapper_daemon {
namespace {

constexpr std::size_t kMaxWaitingServices = 32;

// How far a command's utime may be from the mapper's clock (command_auth.hpp's replay rule): wide enough
// for hosts whose clocks agree to a few seconds (NTP), short enough that a recorded command soon expires.
constexpr std::int64_t kCommandWindowUs = 30'000'000;

std::string replyChannel(const std::string& channel) { return channel + "_REPLY"; }

// Writes `bytes` to `path` (the export's unnamed file).
Status writeBytes(const std::vector<std::uint8_t>& bytes, const std::filesystem::path& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f.get()) != bytes.size() || std::fclose(f.release()) != 0)
    return Error{"write failed"};
  return okStatus();
}

std::string describe(const ogf::map_command_t& c) {
  std::string what = "map command '" + sanitisedForLog(c.command, 16) + "'";
  if (c.command == "export") what += " " + sanitisedForLog(c.format, 8) + " '" + sanitisedForLog(c.path) + "'";
  return what + " from " + sanitisedForLog(c.requester);
}

}  // namespace

MapServices::MapServices(const MapperOptions& options, lcm::LCM& lcm, SharedState& shared,
                         pipeline::ScanMapper& mapper, delta::DeltaStream& deltas, MapPersistence& persistence,
                         std::optional<CommandKey> key, DaemonHooks hooks)
    : options_(options),
      lcm_(lcm),
      shared_(shared),
      mapper_(mapper),
      deltas_(deltas),
      persistence_(persistence),
      command_key_(std::move(key)),
      hooks_(std::move(hooks)),
      replay_guard_(wallUtime(), kCommandWindowUs) {}

void MapServices::onMalformed(const std::string& ch, std::size_t size, std::string_view why) {
  {
    std::lock_guard lk(shared_.mu);
    ++requests_in_;
    ++requests_refused_;
    if (ch == options_.query_channel) ++shared_.stats.queries_refused;
    else ++shared_.stats.commands_refused_unauthenticated;  // nothing in it can be authenticated
  }
  if (auto n = log_.allow()) spdlog::warn("map service request on {} ({} bytes) {} ({} more)", ch, size, why, *n);
}

void MapServices::subscribe() {
  const auto malformed = [this](const std::string& ch, std::size_t size, std::string_view why) {
    onMalformed(ch, size, why);
  };
  query_sub_ = std::make_unique<transport::Subscriber<ogf::map_query_t>>(
      lcm_, options_.query_channel,
      [this](const ogf::map_query_t& q, const lcm::ReceiveBuffer&, const std::string&) { enqueue(q); },
      malformed);
  command_sub_ = std::make_unique<transport::Subscriber<ogf::map_command_t>>(
      lcm_, options_.command_channel,
      [this](const ogf::map_command_t& c, const lcm::ReceiveBuffer&, const std::string&) { enqueue(c); },
      malformed);
}

void MapServices::unsubscribe() {
  query_sub_.reset();
  command_sub_.reset();
}

void MapServices::fillStatus(ogf::mapper_status_t& s) const {
  s.service_requests_in = requests_in_;
  s.service_requests_refused = requests_refused_;
}

void MapServices::countRefused() {
  std::lock_guard lk(shared_.mu);
  ++requests_refused_;
}

std::optional<std::pair<MapServices::CommandRefusal, std::string>> MapServices::authenticate(
    const ogf::map_command_t& c) {
  if (!options_.services.commands_enabled || !command_key_)
    return std::pair{CommandRefusal::kUnauthenticated,
                     std::string("commands are disabled (services.commands_enabled is false)")};
  if (!commandMacValid(c, *command_key_))
    return std::pair{CommandRefusal::kUnauthenticated, std::string("not authenticated: the mac does not match the key")};
  switch (replay_guard_.admit(c, wallUtime())) {
    case ReplayGuard::Verdict::kFresh:
      return std::nullopt;
    case ReplayGuard::Verdict::kOutsideWindow:
      return std::pair{CommandRefusal::kReplayed,
                       std::string("utime more than 30 s from the mapper's clock (replayed, or the clocks disagree)")};
    case ReplayGuard::Verdict::kBeforeStart:
      return std::pair{CommandRefusal::kReplayed, std::string("issued before the mapper started (replayed)")};
    case ReplayGuard::Verdict::kReplayed:
      break;
  }
  return std::pair{CommandRefusal::kReplayed, std::string("already received (replayed)")};
}

void MapServices::refuseCommand(const ogf::map_command_t& command, CommandRefusal why, const std::string& message) {
  {
    std::lock_guard lk(shared_.mu);
    ++requests_refused_;
    switch (why) {
      case CommandRefusal::kUnauthenticated: ++shared_.stats.commands_refused_unauthenticated; break;
      case CommandRefusal::kReplayed: ++shared_.stats.commands_refused_replayed; break;
      case CommandRefusal::kBadName: ++shared_.stats.commands_refused_bad_name; break;
      case CommandRefusal::kBusy: ++shared_.stats.commands_refused_busy; break;
      case CommandRefusal::kDiskSpace: ++shared_.stats.commands_refused_disk_space; break;
      case CommandRefusal::kOther: break;
    }
  }
  if (auto n = log_.allow()) spdlog::warn("{} refused: {} ({} more)", describe(command), message, *n);
  ogf::map_command_reply_t reply{};
  reply.utime = wallUtime();
  reply.request_id = command.request_id;
  reply.status = ogf::map_command_reply_t::STATUS_REFUSED;
  reply.message = message;
  lcm_.publish(replyChannel(options_.command_channel), &reply);
}

void MapServices::refuseQuery(const ogf::map_query_t& query, const std::string& message) {
  {
    std::lock_guard lk(shared_.mu);
    ++requests_refused_;
    ++shared_.stats.queries_refused;
  }
  spdlog::debug("map query {} from {} refused: {}", query.request_id, sanitisedForLog(query.requester), message);
  const auto reply = mapper_daemon::refuseQuery(query, message, wallUtime());
  lcm_.publish(replyChannel(options_.query_channel), &reply);
}

void MapServices::enqueue(Request request) {
  std::optional<std::pair<CommandRefusal, std::string>> refusal;
  {
    std::lock_guard lk(shared_.mu);
    ++requests_in_;
    const auto* c = std::get_if<ogf::map_command_t>(&request);
    shared_.stats.last_requester =
        sanitisedForLog(c ? c->requester : std::get<ogf::map_query_t>(request).requester);
    if (c) refusal = authenticate(*c);
    if (!refusal) {
      if (requests_.size() < kMaxWaitingServices) {
        requests_.push_back(std::move(request));
        shared_.wake();
        return;
      }
      refusal = std::pair{CommandRefusal::kBusy,
                          "busy: " + std::to_string(kMaxWaitingServices) + " requests already wait"};
    }
  }
  if (const auto* q = std::get_if<ogf::map_query_t>(&request)) refuseQuery(*q, refusal->second);
  else refuseCommand(std::get<ogf::map_command_t>(request), refusal->first, refusal->second);
}

bool MapServices::waiting() {
  if (box_job_) return true;
  std::lock_guard lk(shared_.mu);
  return !requests_.empty();
}

void MapServices::serve() {
  // Regions brought back for a query count in the status' memory and cells at once, not at the next scan.
  const std::size_t cells_before = mapper_.filter().allocatedCells();
  struct Refresh {
    MapServices* self;
    std::size_t before;
    ~Refresh() {
      if (self->mapper_.filter().allocatedCells() != before) self->hooks_.refresh_figures();
    }
  } refresh{this, cells_before};
  const auto began = std::chrono::steady_clock::now();
  const auto budget = std::chrono::duration<double, std::milli>(options_.services.budget_ms_per_scan);
  do {
    if (box_job_) {
      stepBox();
      continue;
    }
    std::optional<Request> request;
    {
      std::lock_guard lk(shared_.mu);
      if (requests_.empty()) return;
      request = std::move(requests_.front());
      requests_.pop_front();
    }
    if (const auto* q = std::get_if<ogf::map_query_t>(&*request)) answer(*q);
    else carryOut(std::get<ogf::map_command_t>(*request));
  } while (std::chrono::steady_clock::now() - began < budget);
}

void MapServices::answer(const ogf::map_query_t& q) {
  const double res = options_.map.filter.resolution;
  if (q.kind == ogf::map_query_t::KIND_BOX) {
    // The limit from the corners alone: nothing of the map is read or paged in for a refused box.
    auto box = boxKeysOf(q, res, mapper_.filter().config().dimensions, options_.services.max_query_cells);
    if (!box) return refuseQuery(q, box.error().message);
    box_job_.emplace(BoxJob{q, ChunkedBox(*box, options_.services.box_chunk_cells), deltas_.mapId()});
    return;
  }
  persistence::MapPager* pager = persistence_.pager();
  if (pager && q.kind == ogf::map_query_t::KIND_CELLS && q.num_points >= 1 && q.num_points <= kMaxQueryPoints &&
      q.points.size() == static_cast<std::size_t>(q.num_points)) {
    // The regions holding the points, back from their pages (they go out again as the robot moves).
    for (const auto& p : q.points) {
      if (p.size() == 3 && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
        persistence_.reportPageDamage(
            pager->bringInBox(mapper_.filter(), {p[0], p[1], p[2]}, {p[0], p[1], p[2]}, &deltas_.map()));
    }
  }
  const auto reply = answerQuery(q, mapper_.filter(), deltas_.mapId(), deltas_.seq(), wallUtime());
  if (reply.status != ogf::map_query_reply_t::STATUS_OK) return refuseQuery(q, reply.message);
  spdlog::debug("map query {} from {}: answered", q.request_id, sanitisedForLog(q.requester));
  lcm_.publish(replyChannel(options_.query_channel), &reply);
}

void MapServices::stepBox() {
  BoxJob& job = *box_job_;
  if (job.map_id != deltas_.mapId()) {
    const ogf::map_query_t q = job.query;
    box_job_.reset();
    return refuseQuery(q, "the map was reset while the box was being answered; ask again");
  }
  const auto chunk = job.chunks.next();
  if (chunk) {
    const double res = options_.map.filter.resolution;
    if (persistence::MapPager* pager = persistence_.pager()) {
      // Only this chunk's regions come back from their pages.
      const auto corner = [res](const CellKey& k) {
        return Eigen::Vector3d((k.x + 0.5) * res, (k.y + 0.5) * res, (k.z + 0.5) * res);
      };
      const Eigen::Vector3d lo = corner(chunk->lo), hi = corner(chunk->hi);
      persistence_.reportPageDamage(pager->bringInBox(mapper_.filter(), {lo.x(), lo.y(), lo.z()},
                                                      {hi.x(), hi.y(), hi.z()}, &deltas_.map()));
    }
    auto part = filter::summariseBox(mapper_.filter(), chunk->lo, chunk->hi);
    if (!part) {
      const ogf::map_query_t q = job.query;
      box_job_.reset();
      return refuseQuery(q, part.error().message);
    }
    job.chunks.add(*part);
    return;
  }
  ogf::map_query_reply_t r{};
  r.utime = wallUtime();
  r.request_id = job.query.request_id;
  r.map_id = deltas_.mapId();
  r.seq = deltas_.seq();
  r.resolution = static_cast<float>(options_.map.filter.resolution);
  job.chunks.fill(r, options_.map.filter.resolution);
  spdlog::debug("map query {} from {}: answered", job.query.request_id, sanitisedForLog(job.query.requester));
  box_job_.reset();
  lcm_.publish(replyChannel(options_.query_channel), &r);
}

void MapServices::carryOut(const ogf::map_command_t& command) {
  ogf::map_command_reply_t reply{};
  reply.request_id = command.request_id;
  reply.status = ogf::map_command_reply_t::STATUS_OK;
  if (command.command == "save") {
    save(reply);
  } else if (command.command == "reset") {
    hooks_.reset();
    {
      std::lock_guard lk(shared_.mu);
      ++shared_.stats.map_resets;
    }
    reply.message = "new map " + std::to_string(deltas_.mapId());
  } else if (command.command == "export") {
    startExport(command, reply);
    if (export_job_ && reply.status == ogf::map_command_reply_t::STATUS_OK) return;  // replied once written
    if (reply.status == ogf::map_command_reply_t::STATUS_REFUSED) return;  // refuseCommand replied
  } else {
    return refuseCommand(command, CommandRefusal::kOther,
                         "command '" + sanitisedForLog(command.command, 16) + "': save, reset or export");
  }
  if (reply.status != ogf::map_command_reply_t::STATUS_OK) countRefused();
  spdlog::info("{}: {}", describe(command),
               reply.status == ogf::map_command_reply_t::STATUS_OK ? reply.message : "not done: " + reply.message);
  reply.map_id = deltas_.mapId();
  reply.seq = deltas_.seq();
  reply.utime = wallUtime();
  lcm_.publish(replyChannel(options_.command_channel), &reply);
}

void MapServices::save(ogf::map_command_reply_t& reply) {
  if (!persistence_.hasStateDirectory()) {
    reply.status = ogf::map_command_reply_t::STATUS_FAILED;
    reply.message = "no state directory: the map lives in memory only";
    return;
  }
  persistence_.takeSnapshot(true);
  if (persistence_.hasStateDirectory()) {
    reply.message = "snapshot at seq " + std::to_string(deltas_.seq()) + " in " + options_.state_dir.string();
  } else {
    reply.status = ogf::map_command_reply_t::STATUS_FAILED;
    reply.message = "the snapshot failed (see the status' persistence_error)";
  }
}

std::optional<ExportDirectory> MapServices::exportDestination(const ogf::map_command_t& command,
                                                              ogf::map_command_reply_t& reply) {
  const auto refuse = [&](CommandRefusal why, const std::string& message) {
    reply.status = ogf::map_command_reply_t::STATUS_REFUSED;
    refuseCommand(command, why, message);
  };
  const auto fail = [&](const std::string& message) {
    reply.status = ogf::map_command_reply_t::STATUS_FAILED;
    reply.message = message;
  };
  if (export_job_) {
    refuse(CommandRefusal::kBusy, "busy: an export is being written; try again when it is done");
    return std::nullopt;
  }
  if (auto st = checkExportName(command.path, command.format); !st) {
    refuse(CommandRefusal::kBadName, st.error().message);
    return std::nullopt;
  }
  const auto dir_path = options_.services.exportDirFor(options_.state_dir);
  if (dir_path.empty()) {
    fail("no export directory: set services.export_dir or a state directory");
    return std::nullopt;
  }
  auto dir = ExportDirectory::open(dir_path);
  if (!dir) {
    fail(dir.error().message);
    return std::nullopt;
  }
  if (dir->holds(command.path)) {
    refuse(CommandRefusal::kBadName, "export name '" + command.path + "' exists; an export never replaces a file");
    return std::nullopt;
  }
  // The free space, from the map's size alone, before anything is copied.
  std::int64_t cells = 0;
  {
    std::lock_guard lk(shared_.mu);
    cells = shared_.stats.cells;
  }
  const std::uint64_t bound =
      exportBytesBound(command.format, static_cast<std::uint64_t>(std::max<std::int64_t>(cells, 0)));
  auto free = dir->freeBytes();
  if (!free) {
    fail(free.error().message);
    return std::nullopt;
  }
  if (*free < bound || *free - bound < options_.services.export_min_free_bytes) {
    refuse(CommandRefusal::kDiskSpace,
           "disk space: the export may take " + std::to_string(bound) + " bytes and " + std::to_string(*free) +
               " are free; services.export_min_free_bytes keeps " +
               std::to_string(options_.services.export_min_free_bytes));
    return std::nullopt;
  }
  return std::move(*dir);
}

std::function<Status(const std::filesystem::path&)> MapServices::copyForExport(const std::string& format) {
  // An export holds the whole map, paged-out regions too.
  if (persistence::MapPager* pager = persistence_.pager())
    persistence_.reportPageDamage(pager->bringInAll(mapper_.filter(), &deltas_.map()));
  if (format == "ogfm") {
    auto bytes = std::make_shared<const std::vector<std::uint8_t>>(filter::encodeMap(mapper_.filter()));
    return [bytes](const std::filesystem::path& p) { return writeBytes(*bytes, p); };
  }
  auto copy = std::make_shared<const map_io::MapCells>(map_io::collectCells(mapper_.filter()));
  return [copy, format](const std::filesystem::path& p) -> Status {
    if (format == "ply") return map_io::writeOccupiedPly(*copy, p);
    if (format == "pcd") return map_io::writeOccupiedPcd(*copy, p);
    if (format == "csv") return map_io::writeCellCsv(*copy, p);
    auto bt = map_io::writeOctomapBinary(*copy, p);
    return bt ? okStatus() : Status(bt.error());
  };
}

void MapServices::startExport(const ogf::map_command_t& command, ogf::map_command_reply_t& reply) {
  auto dir = exportDestination(command, reply);
  if (!dir) return;
  // The map copied here; the file written on its own thread while mapping goes on.
  auto write = copyForExport(command.format);
  reply.map_id = deltas_.mapId();
  reply.seq = deltas_.seq();
  reply.message = "wrote " + (dir->path() / command.path).string() + " at seq " + std::to_string(deltas_.seq());
  ExportJob job{reply, describe(command), {}};
  auto shared_dir = std::make_shared<ExportDirectory>(std::move(*dir));
  const std::string name = command.path;
  try {
    job.written = std::async(std::launch::async, [shared_dir, name, write] { return shared_dir->writeNew(name, write); });
  } catch (const std::system_error& e) {
    reply.status = ogf::map_command_reply_t::STATUS_FAILED;
    reply.message = std::string("no thread to write the export on: ") + e.what();
    return;
  }
  export_job_ = std::move(job);
}

bool MapServices::exportWritten() const {
  return export_job_ && export_job_->written.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

void MapServices::finishExport(bool wait) {
  if (!export_job_ || (!wait && !exportWritten())) return;
  ExportJob job = std::move(*export_job_);
  export_job_.reset();
  const Status st = job.written.get();
  if (!st) {
    job.reply.status = ogf::map_command_reply_t::STATUS_FAILED;
    job.reply.message = st.error().message;
    countRefused();
  }
  spdlog::info("{}: {}", job.command_text,
               st ? job.reply.message : "not done: " + job.reply.message);
  job.reply.utime = wallUtime();
  lcm_.publish(replyChannel(options_.command_channel), &job.reply);
}

}  // namespace ogf::mapper_daemon
