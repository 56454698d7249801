// ogf-mapper's map services (map_services.cpp, map_queries.cpp, map_commands.cpp): queries on OGF_MAP_QUERY
// and commands on OGF_MAP_COMMAND (save a snapshot now, reset the map, export it) arrive on the service
// bus's thread, never in the queue of scans and poses; requests longer than their kind's largest are refused
// before decoding, commands that are disabled, unauthenticated or replayed at once; the rest wait in a queue
// bounded by count and bytes and are served by the worker between scans for at most
// services.budget_ms_per_scan each time (a box query in chunks over several turns, an export written on its
// own thread), so they never hold up mapping.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/map_command_reply_t.hpp>
#include <ogf/map_command_t.hpp>
#include <ogf/map_query_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <deque>
#include <filesystem>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "ogf/common/result.hpp"
#include "ogf/delta/delta_stream.hpp"
#include "ogf/mapper_daemon/command_auth.hpp"
#include "ogf/mapper_daemon/map_export.hpp"
#include "ogf/mapper_daemon/map_persistence.hpp"
#include "ogf/mapper_daemon/map_query_answer.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

namespace ogf::mapper_daemon {

class MapServices {
 public:
  // What the services do to the whole daemon: reset the map (`reset`), and bring the status' map figures
  // up to date after regions came back from their pages (`refresh_figures`).
  struct DaemonHooks {
    std::function<void()> reset;
    std::function<void()> refresh_figures;
  };
  // `key`: services.key_file's key, when commands are enabled.
  MapServices(const MapperOptions& options, lcm::LCM& lcm, SharedState& shared, pipeline::ScanMapper& mapper,
              delta::DeltaStream& deltas, MapPersistence& persistence, std::optional<CommandKey> key,
              DaemonHooks hooks);
  MapServices(const MapServices&) = delete;
  MapServices& operator=(const MapServices&) = delete;

  // Receives the requests on `bus` (the service bus, dispatched on its own thread); replies go out on the
  // instance the services were made with.
  void subscribe(lcm::LCM& bus);
  void unsubscribe();

  // The worker's. Whether service work waits (a request, or a box being answered); `Locked`: shared.mu held.
  bool waiting();
  bool waitingLocked() const { return box_job_.has_value() || !requests_.empty(); }
  // Serves waiting requests for at most services.budget_ms_per_scan.
  void serve();
  // Export: checked and copied on the worker, written on its own thread; one at a time.
  bool exportWritten() const;
  void finishExport(bool wait);
  // The requests received and refused (shared.mu held).
  void fillStatus(ogf::mapper_status_t& s) const;

 private:
  using Request = std::variant<ogf::map_query_t, ogf::map_command_t>;
  enum class CommandRefusal { kUnauthenticated, kReplayed, kBadName, kBusy, kDiskSpace, kOther };
  // `bytes`: the request's encoded length, counted against the queue's byte bound.
  void enqueue(Request request, std::size_t bytes);
  void onMalformed(const std::string& channel, std::size_t size, std::string_view why);
  // Why the command may not be carried out (shared.mu held), nullopt when it may.
  std::optional<std::pair<CommandRefusal, std::string>> authenticate(const ogf::map_command_t& command);
  void refuseCommand(const ogf::map_command_t& command, CommandRefusal why, const std::string& message);
  void refuseQuery(const ogf::map_query_t& query, const std::string& message);
  void countRefused();
  static std::string replyChannel(const std::string& channel);
  // The command for the log: its name, an export's format and file, the requester; sanitised.
  static std::string describe(const ogf::map_command_t& command);
  void answer(const ogf::map_query_t& query);
  void stepBox();
  void carryOut(const ogf::map_command_t& command);
  void save(ogf::map_command_reply_t& reply);
  void startExport(const ogf::map_command_t& command, ogf::map_command_reply_t& reply);
  // Where the export goes, once the name, the directory and its free space are checked; nothing when the
  // command is refused (replied to) or failed (`reply` says why).
  std::optional<ExportDirectory> exportDestination(const ogf::map_command_t& command, ogf::map_command_reply_t& reply);
  // The map copied for the export's thread, which writes it as `format` to the path it is given.
  std::function<Status(const std::filesystem::path&)> copyForExport(const std::string& format);

  const MapperOptions& options_;
  lcm::LCM& lcm_;
  SharedState& shared_;
  pipeline::ScanMapper& mapper_;
  delta::DeltaStream& deltas_;
  MapPersistence& persistence_;
  std::optional<CommandKey> command_key_;
  DaemonHooks hooks_;

  // Under shared_.mu:
  struct Waiting {
    Request request;
    std::size_t bytes;
  };
  std::deque<Waiting> requests_;
  std::size_t waiting_bytes_ = 0;
  std::int64_t requests_in_ = 0;       // queries and commands received, malformed ones too
  std::int64_t requests_refused_ = 0;  // malformed, beyond the limits, or refused for a full queue
  ReplayGuard replay_guard_;
  // The worker's: the box query being answered chunk by chunk, and the export being written.
  struct BoxJob {
    ogf::map_query_t query;
    ChunkedBox chunks;
    std::int64_t map_id;
  };
  std::optional<BoxJob> box_job_;
  struct ExportJob {
    ogf::map_command_reply_t reply;
    std::string command_text;  // for the log: command, name and requester, sanitised
    std::future<Status> written;
  };
  std::optional<ExportJob> export_job_;

  std::unique_ptr<transport::Subscriber<ogf::map_query_t>> query_sub_;
  std::unique_ptr<transport::Subscriber<ogf::map_command_t>> command_sub_;
  transport::LogRateLimiter log_;
};

}  // namespace ogf::mapper_daemon
