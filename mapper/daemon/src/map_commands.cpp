// ogf-mapper's map commands (map_services.hpp), once authenticated: save (a snapshot now), reset (a new
// map, the old one kept aside) and export (the map copied on the worker, written into the export directory
// on a thread of its own). Each gets exactly one reply; an export's once its file is written.
#include <ogf/filter/map_file.hpp>
#include <ogf/map_command_reply_t.hpp>
#include <ogf/map_formats/cell_csv.hpp>
#include <ogf/map_formats/cell_pcd.hpp>
#include <ogf/map_formats/cell_ply.hpp>
#include <ogf/map_formats/map_cells.hpp>
#include <ogf/map_formats/octomap_export.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/log_text.hpp"
#include "ogf/mapper_daemon/map_export.hpp"
#include "ogf/mapper_daemon/map_services.hpp"

namespace ogf::mapper_daemon {
namespace {

// Writes `bytes` to `path` (the export's unnamed file).
Status writeBytes(const std::vector<std::uint8_t>& bytes, const std::filesystem::path& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f.get()) != bytes.size() || std::fclose(f.release()) != 0)
    return Error{"write failed"};
  return okStatus();
}

}  // namespace

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
  // The free space, from the map's size alone, before anything is copied (its figures brought up to date:
  // they are kept for the status, which may not have asked for them since the last scan).
  hooks_.refresh_figures();
  std::int64_t cells = 0;
  {
    std::lock_guard lk(shared_.mu);
    cells = shared_.stats.cells;
  }
  const auto all_cells = static_cast<std::uint64_t>(std::max<std::int64_t>(cells, 0));
  const std::uint64_t bound =
      exportBytesBound(command.format, all_cells, filter::encodedMapBytes(mapper_.filter(), all_cells));
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
  auto copy = std::make_shared<const map_formats::MapCells>(map_formats::collectCells(mapper_.filter()));
  return [copy, format](const std::filesystem::path& p) -> Status {
    if (format == "ply") return map_formats::writeOccupiedPly(*copy, p);
    if (format == "pcd") return map_formats::writeOccupiedPcd(*copy, p);
    if (format == "csv") return map_formats::writeCellCsv(*copy, p);
    auto bt = map_formats::writeOctomapBinary(*copy, p);
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
