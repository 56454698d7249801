// ogf-mapper's map services: OGF_MAP_QUERY → OGF_MAP_QUERY_REPLY (map_query_answer.hpp) and
// OGF_MAP_COMMAND → OGF_MAP_COMMAND_REPLY (save a snapshot now, reset the map, export it). Requests are
// received on the Asio thread, which refuses at once commands that are disabled, unauthenticated or
// replayed (command_auth.hpp); the rest wait in a queue of at most kMaxWaitingServices and the worker
// serves them between scans, for at most services.budget_ms_per_scan at a time. Every request gets
// exactly one reply, a refusal included; refusals are counted by reason in the status.
#include <ogf/filter/map_file.hpp>
#include <ogf/map_command_reply_t.hpp>
#include <ogf/map_formats/cell_csv.hpp>
#include <ogf/map_formats/cell_pcd.hpp>
#include <ogf/map_formats/cell_ply.hpp>
#include <ogf/map_formats/map_cells.hpp>
#include <ogf/map_formats/octomap_export.hpp>
#include <ogf/messages/limits.hpp>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "map_id.hpp"
#include "ogf/mapper_daemon/log_text.hpp"
#include "ogf/mapper_daemon/map_export.hpp"
#include "ogf/mapper_daemon/map_query_answer.hpp"
#include "ogf/mapper_daemon/mapper_daemon.hpp"

namespace ogf::mapper_daemon {
namespace {

constexpr std::size_t kMaxWaitingServices = 32;

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

void MapperDaemon::subscribeServices() {
  const auto malformed = [this](const std::string& ch, std::size_t size, std::string_view why) {
    {
      std::lock_guard lk(mu_);
      ++service_in_;
      ++service_refused_;
      if (ch == options_.query_channel) ++stats_.queries_refused;
      else ++stats_.commands_refused_unauthenticated;  // nothing in it can be authenticated
    }
    if (auto n = service_log_.allow()) spdlog::warn("map service request on {} ({} bytes) {} ({} more)", ch, size, why, *n);
  };
  query_sub_ = std::make_unique<transport::Subscriber<ogf::map_query_t>>(
      lcm_, options_.query_channel,
      [this](const ogf::map_query_t& q, const lcm::ReceiveBuffer&, const std::string&) { enqueueService(q); },
      malformed);
  command_sub_ = std::make_unique<transport::Subscriber<ogf::map_command_t>>(
      lcm_, options_.command_channel,
      [this](const ogf::map_command_t& c, const lcm::ReceiveBuffer&, const std::string&) { enqueueService(c); },
      malformed);
}

std::optional<std::pair<MapperDaemon::CommandRefusal, std::string>> MapperDaemon::authenticate(
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

void MapperDaemon::refuseCommand(const ogf::map_command_t& command, CommandRefusal why, const std::string& message) {
  {
    std::lock_guard lk(mu_);
    ++service_refused_;
    switch (why) {
      case CommandRefusal::kUnauthenticated: ++stats_.commands_refused_unauthenticated; break;
      case CommandRefusal::kReplayed: ++stats_.commands_refused_replayed; break;
      case CommandRefusal::kBadName: ++stats_.commands_refused_bad_name; break;
      case CommandRefusal::kBusy: ++stats_.commands_refused_busy; break;
      case CommandRefusal::kDiskSpace: ++stats_.commands_refused_disk_space; break;
      case CommandRefusal::kOther: break;
    }
  }
  if (auto n = service_log_.allow()) spdlog::warn("{} refused: {} ({} more)", describe(command), message, *n);
  ogf::map_command_reply_t reply{};
  reply.utime = wallUtime();
  reply.request_id = command.request_id;
  reply.status = ogf::map_command_reply_t::STATUS_REFUSED;
  reply.message = message;
  lcm_.publish(replyChannel(options_.command_channel), &reply);
}

void MapperDaemon::refuseQuery(const ogf::map_query_t& query, const std::string& message) {
  {
    std::lock_guard lk(mu_);
    ++service_refused_;
    ++stats_.queries_refused;
  }
  spdlog::debug("map query {} from {} refused: {}", query.request_id, sanitisedForLog(query.requester), message);
  const auto reply = mapper_daemon::refuseQuery(query, message, wallUtime());
  lcm_.publish(replyChannel(options_.query_channel), &reply);
}

void MapperDaemon::enqueueService(ServiceRequest request) {
  std::optional<std::pair<CommandRefusal, std::string>> refusal;
  {
    std::lock_guard lk(mu_);
    ++service_in_;
    const auto* c = std::get_if<ogf::map_command_t>(&request);
    stats_.last_requester =
        sanitisedForLog(c ? c->requester : std::get<ogf::map_query_t>(request).requester);
    if (c) refusal = authenticate(*c);
    if (!refusal) {
      if (service_requests_.size() < kMaxWaitingServices) {
        service_requests_.push_back(std::move(request));
        work_ = true;
        cv_.notify_one();
        return;
      }
      refusal = std::pair{CommandRefusal::kBusy,
                          "busy: " + std::to_string(kMaxWaitingServices) + " requests already wait"};
    }
  }
  if (const auto* q = std::get_if<ogf::map_query_t>(&request)) refuseQuery(*q, refusal->second);
  else refuseCommand(std::get<ogf::map_command_t>(request), refusal->first, refusal->second);
}

bool MapperDaemon::servicesWaiting() {
  if (box_job_) return true;
  std::lock_guard lk(mu_);
  return !service_requests_.empty();
}

void MapperDaemon::serve() {
  // Regions brought back for a query count in the status' memory and cells at once, not at the next scan.
  const std::size_t cells_before = mapper_.filter().allocatedCells();
  struct Refresh {
    MapperDaemon* self;
    std::size_t before;
    ~Refresh() {
      if (self->mapper_.filter().allocatedCells() != before) self->refreshMapStats();
    }
  } refresh{this, cells_before};
  const auto began = std::chrono::steady_clock::now();
  const auto budget = std::chrono::duration<double, std::milli>(options_.services.budget_ms_per_scan);
  do {
    if (box_job_) {
      stepBox();
      continue;
    }
    std::optional<ServiceRequest> request;
    {
      std::lock_guard lk(mu_);
      if (service_requests_.empty()) return;
      request = std::move(service_requests_.front());
      service_requests_.pop_front();
    }
    if (const auto* q = std::get_if<ogf::map_query_t>(&*request)) answer(*q);
    else carryOut(std::get<ogf::map_command_t>(*request));
  } while (std::chrono::steady_clock::now() - began < budget);
}

void MapperDaemon::answer(const ogf::map_query_t& q) {
  const double res = options_.map.filter.resolution;
  if (q.kind == ogf::map_query_t::KIND_BOX) {
    // The limit from the corners alone: nothing of the map is read or paged in for a refused box.
    auto box = boxKeysOf(q, res, mapper_.filter().config().dimensions, options_.services.max_query_cells);
    if (!box) return refuseQuery(q, box.error().message);
    box_job_.emplace(BoxJob{q, ChunkedBox(*box, options_.services.box_chunk_cells), deltas_.mapId()});
    return;
  }
  if (pager_ && q.kind == ogf::map_query_t::KIND_CELLS && q.num_points >= 1 && q.num_points <= kMaxQueryPoints &&
      q.points.size() == static_cast<std::size_t>(q.num_points)) {
    // The regions holding the points, back from their pages (they go out again as the robot moves).
    for (const auto& p : q.points) {
      if (p.size() == 3 && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
        reportPageDamage(pager_->bringInBox(mapper_.filter(), {p[0], p[1], p[2]}, {p[0], p[1], p[2]}, &deltas_.map()));
    }
  }
  const auto reply = answerQuery(q, mapper_.filter(), deltas_.mapId(), deltas_.seq(), wallUtime());
  if (reply.status != ogf::map_query_reply_t::STATUS_OK) return refuseQuery(q, reply.message);
  spdlog::debug("map query {} from {}: answered", q.request_id, sanitisedForLog(q.requester));
  lcm_.publish(replyChannel(options_.query_channel), &reply);
}

void MapperDaemon::stepBox() {
  BoxJob& job = *box_job_;
  if (job.map_id != deltas_.mapId()) {
    const ogf::map_query_t q = job.query;
    box_job_.reset();
    return refuseQuery(q, "the map was reset while the box was being answered; ask again");
  }
  const auto chunk = job.chunks.next();
  if (chunk) {
    const double res = options_.map.filter.resolution;
    if (pager_) {
      // Only this chunk's regions come back from their pages.
      const auto corner = [res](const CellKey& k) {
        return Eigen::Vector3d((k.x + 0.5) * res, (k.y + 0.5) * res, (k.z + 0.5) * res);
      };
      const Eigen::Vector3d lo = corner(chunk->lo), hi = corner(chunk->hi);
      reportPageDamage(pager_->bringInBox(mapper_.filter(), {lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()},
                                          &deltas_.map()));
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

void MapperDaemon::carryOut(const ogf::map_command_t& command) {
  ogf::map_command_reply_t reply{};
  reply.request_id = command.request_id;
  reply.status = ogf::map_command_reply_t::STATUS_OK;
  if (command.command == "save") {
    if (!state_) {
      reply.status = ogf::map_command_reply_t::STATUS_FAILED;
      reply.message = "no state directory: the map lives in memory only";
    } else {
      takeSnapshot(true);
      if (state_) {
        reply.message = "snapshot at seq " + std::to_string(deltas_.seq()) + " in " + options_.state_dir.string();
      } else {
        reply.status = ogf::map_command_reply_t::STATUS_FAILED;
        reply.message = "the snapshot failed (see the status' persistence_error)";
      }
    }
  } else if (command.command == "reset") {
    resetMap();
    {
      std::lock_guard lk(mu_);
      ++stats_.map_resets;
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
  if (reply.status != ogf::map_command_reply_t::STATUS_OK) {
    std::lock_guard lk(mu_);
    ++service_refused_;
  }
  spdlog::info("{}: {}", describe(command),
               reply.status == ogf::map_command_reply_t::STATUS_OK ? reply.message : "not done: " + reply.message);
  reply.map_id = deltas_.mapId();
  reply.seq = deltas_.seq();
  reply.utime = wallUtime();
  lcm_.publish(replyChannel(options_.command_channel), &reply);
}

void MapperDaemon::startExport(const ogf::map_command_t& command, ogf::map_command_reply_t& reply) {
  const auto refuse = [&](CommandRefusal why, const std::string& message) {
    reply.status = ogf::map_command_reply_t::STATUS_REFUSED;
    refuseCommand(command, why, message);
  };
  if (export_job_) return refuse(CommandRefusal::kBusy, "busy: an export is being written; try again when it is done");
  const std::string& format = command.format;
  if (auto st = checkExportName(command.path, format); !st) return refuse(CommandRefusal::kBadName, st.error().message);
  const auto dir_path = options_.services.exportDirFor(options_.state_dir);
  if (dir_path.empty()) {
    reply.status = ogf::map_command_reply_t::STATUS_FAILED;
    reply.message = "no export directory: set services.export_dir or a state directory";
    return;
  }
  auto dir = ExportDirectory::open(dir_path);
  if (!dir) {
    reply.status = ogf::map_command_reply_t::STATUS_FAILED;
    reply.message = dir.error().message;
    return;
  }
  if (dir->holds(command.path))
    return refuse(CommandRefusal::kBadName, "export name '" + command.path + "' exists; an export never replaces a file");
  // The free space, from the map's size alone, before anything is copied.
  std::int64_t cells = 0;
  {
    std::lock_guard lk(mu_);
    cells = stats_.cells;
  }
  const std::uint64_t bound = exportBytesBound(format, static_cast<std::uint64_t>(std::max<std::int64_t>(cells, 0)));
  auto free = dir->freeBytes();
  if (!free) {
    reply.status = ogf::map_command_reply_t::STATUS_FAILED;
    reply.message = free.error().message;
    return;
  }
  if (*free < bound || *free - bound < options_.services.export_min_free_bytes) {
    return refuse(CommandRefusal::kDiskSpace,
                  "disk space: the export may take " + std::to_string(bound) + " bytes and " +
                      std::to_string(*free) + " are free; services.export_min_free_bytes keeps " +
                      std::to_string(options_.services.export_min_free_bytes));
  }
  // The map copied here (an export holds the whole map, paged-out regions too); the file written on its
  // own thread while mapping goes on.
  if (pager_) reportPageDamage(pager_->bringInAll(mapper_.filter(), &deltas_.map()));
  std::function<Status(const std::filesystem::path&)> write;
  if (format == "ogfm") {
    auto bytes = std::make_shared<const std::vector<std::uint8_t>>(filter::encodeMap(mapper_.filter()));
    write = [bytes](const std::filesystem::path& p) { return writeBytes(*bytes, p); };
  } else {
    auto copy = std::make_shared<const map_formats::MapCells>(map_formats::collectCells(mapper_.filter()));
    write = [copy, format](const std::filesystem::path& p) -> Status {
      if (format == "ply") return map_formats::writeOccupiedPly(*copy, p);
      if (format == "pcd") return map_formats::writeOccupiedPcd(*copy, p);
      if (format == "csv") return map_formats::writeCellCsv(*copy, p);
      auto bt = map_formats::writeOctomapBinary(*copy, p);
      return bt ? okStatus() : Status(bt.error());
    };
  }
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

bool MapperDaemon::exportWritten() const {
  return export_job_ && export_job_->written.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

void MapperDaemon::finishExport(bool wait) {
  if (!export_job_ || (!wait && !exportWritten())) return;
  ExportJob job = std::move(*export_job_);
  export_job_.reset();
  const Status st = job.written.get();
  if (!st) {
    job.reply.status = ogf::map_command_reply_t::STATUS_FAILED;
    job.reply.message = st.error().message;
    std::lock_guard lk(mu_);
    ++service_refused_;
  }
  spdlog::info("{}: {}", job.command_text,
               st ? job.reply.message : "not done: " + job.reply.message);
  job.reply.utime = wallUtime();
  lcm_.publish(replyChannel(options_.command_channel), &job.reply);
}

void MapperDaemon::resetMap() {
  auto fresh = pipeline::ScanMapper::create(options_.map);
  if (!fresh) {
    spdlog::error("reset: {}", fresh.error().message);  // cannot happen: the same configuration built the map
    return;
  }
  // A keyframe of the old map going out would read pages about to be moved aside; a snapshot being
  // written goes into place first, so the old map is kept whole.
  keyframe_sender_->cancel();
  finishSnapshotWrite(true);
  mapper_ = std::move(*fresh);
  const std::int64_t id = newMapId();
  deltas_ = delta::DeltaStream({options_.map.filter.resolution, id, ogf::messages::kMaxDeltaCellsPerMessage});
  deltas_.reset(mapper_.publishedCells(), 0);
  if (state_) {
    // The old map is kept beside the new one, never deleted.
    const auto aside = options_.state_dir / ("reset-" + std::to_string(wallUtime()));
    std::error_code ec;
    std::filesystem::create_directories(aside, ec);
    const std::filesystem::path files[] = {state_->snapshotPath(), state_->journalPath(),
                                           state_->previousSnapshotPath(), state_->previousJournalPath(),
                                           state_->pagesDir()};
    pager_.reset();
    state_.reset();
    for (const auto& f : files) {
      if (std::filesystem::exists(f, ec)) std::filesystem::rename(f, aside / f.filename(), ec);
    }
    auto dir = persistence::StateDirectory::open(options_.state_dir);
    if (!dir) {
      persistenceFailed(dir.error().message, true);
    } else if (auto rec = dir->recover(id); !rec) {
      persistenceFailed(rec.error().message, true);
    } else {
      state_.emplace(std::move(*dir));
      openPager(state_->pagesDir());
    }
    spdlog::info("reset: the previous map is kept in {}", aside.string());
  }
  snapshot_seq_ = -1;
  takeSnapshot();
  if (!publishKeyframe()) keyframe_waiting_ = true;
  refreshMapStats();
}

void MapperDaemon::refreshMapStats() {
  std::lock_guard lk(mu_);
  stats_.delta_seq = deltas_.seq();
  fillMapStats();
}

}  // namespace ogf::mapper_daemon
