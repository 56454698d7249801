// ogf-mapper's map services: OGF_MAP_QUERY → OGF_MAP_QUERY_REPLY (map_query_answer.hpp) and
// OGF_MAP_COMMAND → OGF_MAP_COMMAND_REPLY (save a snapshot now, reset the map, export it). Requests are
// received on the Asio thread into a queue of at most kMaxWaitingServices and served by the worker between
// scans; every request gets exactly one reply, a refusal included.
#include <ogf/filter/map_file.hpp>
#include <ogf/map_command_reply_t.hpp>
#include <ogf/map_io/cell_csv.hpp>
#include <ogf/map_io/cell_pcd.hpp>
#include <ogf/map_io/cell_ply.hpp>
#include <ogf/map_io/map_cells.hpp>
#include <ogf/map_io/octomap_export.hpp>
#include <ogf/messages/limits.hpp>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "map_id.hpp"
#include "ogf/mapper_daemon/map_query_answer.hpp"
#include "ogf/mapper_daemon/mapper_daemon.hpp"

namespace ogf::mapper_daemon {
namespace {

constexpr std::size_t kMaxWaitingServices = 32;

std::string replyChannel(const std::string& channel) { return channel + "_REPLY"; }

}  // namespace

void MapperDaemon::subscribeServices() {
  const auto malformed = [this](const std::string& ch, std::size_t size, std::string_view why) {
    {
      std::lock_guard lk(mu_);
      ++service_in_;
      ++service_refused_;
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

void MapperDaemon::enqueueService(ServiceRequest request) {
  {
    std::lock_guard lk(mu_);
    ++service_in_;
    if (service_requests_.size() < kMaxWaitingServices) {
      service_requests_.push_back(std::move(request));
      work_ = true;
      cv_.notify_one();
      return;
    }
    ++service_refused_;
  }
  const std::string why = "busy: " + std::to_string(kMaxWaitingServices) + " requests already wait";
  if (const auto* q = std::get_if<ogf::map_query_t>(&request)) {
    const auto reply = refuseQuery(*q, why, wallUtime());
    lcm_.publish(replyChannel(options_.query_channel), &reply);
  } else {
    const auto& c = std::get<ogf::map_command_t>(request);
    ogf::map_command_reply_t reply{};
    reply.utime = wallUtime();
    reply.request_id = c.request_id;
    reply.status = ogf::map_command_reply_t::STATUS_REFUSED;
    reply.message = why;
    lcm_.publish(replyChannel(options_.command_channel), &reply);
  }
}

void MapperDaemon::serve(std::deque<ServiceRequest>& requests) {
  for (const ServiceRequest& request : requests) {
    if (const auto* q = std::get_if<ogf::map_query_t>(&request)) {
      if (pager_) {
        // The regions the query asks about, back from their pages (they go out again as the robot moves).
        const auto& f = *q;
        if (f.kind == ogf::map_query_t::KIND_BOX) {
          reportPageDamage(pager_->bringInBox(mapper_.filter(), {f.box_min[0], f.box_min[1], f.box_min[2]},
                                              {f.box_max[0], f.box_max[1], f.box_max[2]}, &deltas_.map()));
        } else {
          for (const auto& p : f.points)
            reportPageDamage(
                pager_->bringInBox(mapper_.filter(), {p[0], p[1], p[2]}, {p[0], p[1], p[2]}, &deltas_.map()));
        }
      }
      const auto reply = answerQuery(*q, mapper_.filter(), deltas_.mapId(), deltas_.seq(), wallUtime());
      if (reply.status != ogf::map_query_reply_t::STATUS_OK) {
        std::lock_guard lk(mu_);
        ++service_refused_;
      }
      spdlog::debug("map query {} from {}: {}", q->request_id, q->requester,
                    reply.status == ogf::map_query_reply_t::STATUS_OK ? "answered" : reply.message);
      lcm_.publish(replyChannel(options_.query_channel), &reply);
    } else {
      carryOut(std::get<ogf::map_command_t>(request));
    }
  }
  requests.clear();
}

void MapperDaemon::carryOut(const ogf::map_command_t& command) {
  ogf::map_command_reply_t reply{};
  reply.request_id = command.request_id;
  reply.status = ogf::map_command_reply_t::STATUS_OK;
  const auto fail = [&](std::int8_t status, std::string why) {
    reply.status = status;
    reply.message = std::move(why);
  };
  if (command.command == "save") {
    if (!state_) {
      fail(ogf::map_command_reply_t::STATUS_FAILED, "no state directory: the map lives in memory only");
    } else {
      takeSnapshot(true);
      if (state_) reply.message = "snapshot at seq " + std::to_string(deltas_.seq()) + " in " + options_.state_dir.string();
      else fail(ogf::map_command_reply_t::STATUS_FAILED, "the snapshot failed (see the status' persistence_error)");
    }
  } else if (command.command == "reset") {
    resetMap();
    reply.message = "new map " + std::to_string(deltas_.mapId());
  } else if (command.command == "export") {
    const std::filesystem::path path(command.path);
    const std::string& f = command.format;
    if (!path.is_absolute()) {
      fail(ogf::map_command_reply_t::STATUS_REFUSED, "path '" + command.path + "' must be absolute");
    } else if (f != "ogfm" && f != "ply" && f != "pcd" && f != "csv" && f != "bt") {
      fail(ogf::map_command_reply_t::STATUS_REFUSED, "format '" + f + "': ogfm, ply, pcd, csv or bt");
    } else {
      Status st = okStatus();
      // An export holds the whole map.
      if (pager_) reportPageDamage(pager_->bringInAll(mapper_.filter(), &deltas_.map()));
      if (f == "ogfm") {
        st = filter::saveMapFile(mapper_.filter(), path);
      } else {
        const map_io::MapCells cells = map_io::collectCells(mapper_.filter());
        if (f == "ply") st = map_io::writeOccupiedPly(cells, path);
        if (f == "pcd") st = map_io::writeOccupiedPcd(cells, path);
        if (f == "csv") st = map_io::writeCellCsv(cells, path);
        if (f == "bt") {
          auto bt = map_io::writeOctomapBinary(cells, path);
          if (!bt) st = bt.error();
        }
      }
      if (!st) fail(ogf::map_command_reply_t::STATUS_FAILED, st.error().message);
      else reply.message = "wrote " + path.string() + " at seq " + std::to_string(deltas_.seq());
    }
  } else {
    fail(ogf::map_command_reply_t::STATUS_REFUSED, "command '" + command.command + "': save, reset or export");
  }
  if (reply.status != ogf::map_command_reply_t::STATUS_OK) {
    std::lock_guard lk(mu_);
    ++service_refused_;
  }
  spdlog::info("map command '{}' from {}: {}", command.command, command.requester,
               reply.status == ogf::map_command_reply_t::STATUS_OK ? reply.message : "not done: " + reply.message);
  reply.map_id = deltas_.mapId();
  reply.seq = deltas_.seq();
  reply.utime = wallUtime();
  lcm_.publish(replyChannel(options_.command_channel), &reply);
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
