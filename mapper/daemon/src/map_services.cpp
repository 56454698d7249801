// ogf-mapper's map services (map_services.hpp), their wiring: OGF_MAP_QUERY → OGF_MAP_QUERY_REPLY
// (answered in map_queries.cpp) and OGF_MAP_COMMAND → OGF_MAP_COMMAND_REPLY (carried out in
// map_commands.cpp: save a snapshot now, reset the map, export it). Requests are received on the service
// bus's own thread (transport/dispatch_thread.hpp), apart from scans and poses; one longer than the largest
// request of its kind is refused from its length before it is decoded, and commands that are disabled,
// unauthenticated or replayed are refused at once. The rest wait in a queue of at most kMaxWaitingServices
// requests and kMaxWaitingServiceBytes bytes, and the worker serves them between scans, for at most
// services.budget_ms_per_scan at a time. Every request that decodes gets exactly one reply, a refusal
// included; refusals are counted by reason in the status.
#include "ogf/mapper_daemon/map_services.hpp"

#include <ogf/map_command_reply_t.hpp>
#include <ogf/messages/limits.hpp>
#include <spdlog/spdlog.h>

#include <chrono>

#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/log_text.hpp"
#include "ogf/mapper_daemon/map_query_answer.hpp"

namespace ogf::mapper_daemon {
namespace {

constexpr std::size_t kMaxWaitingServices = 32;
// Eight of the largest queries (10 000 points, 120 kB): what waits is bounded by bytes as well as by count.
constexpr std::size_t kMaxWaitingServiceBytes = 8 * messages::maxQueryBytes(kMaxQueryPoints);
// What LCM may hold of a service channel before the service thread takes it: that thread only checks a
// request's length, decodes and queues it, so a few suffice, and a flood is dropped by LCM, not held.
constexpr int kServiceQueueCapacity = 16;

// How far a command's utime may be from the mapper's clock (command_auth.hpp's replay rule): wide enough
// for hosts whose clocks agree to a few seconds (NTP), short enough that a recorded command soon expires.
constexpr std::int64_t kCommandWindowUs = 30'000'000;

}  // namespace

std::string MapServices::replyChannel(const std::string& channel) { return channel + "_REPLY"; }

std::string MapServices::describe(const ogf::map_command_t& c) {
  std::string what = "map command '" + sanitisedForLog(c.command, 16) + "'";
  if (c.command == "export") what += " " + sanitisedForLog(c.format, 8) + " '" + sanitisedForLog(c.path) + "'";
  return what + " from " + sanitisedForLog(c.requester);
}

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

void MapServices::subscribe(lcm::LCM& bus) {
  const auto malformed = [this](const std::string& ch, std::size_t size, std::string_view why) {
    onMalformed(ch, size, why);
  };
  query_sub_ = std::make_unique<transport::Subscriber<ogf::map_query_t>>(
      bus, options_.query_channel,
      [this](const ogf::map_query_t& q, const lcm::ReceiveBuffer& rbuf, const std::string&) {
        enqueue(q, rbuf.data_size);
      },
      malformed, kServiceQueueCapacity, messages::maxQueryBytes(kMaxQueryPoints));
  command_sub_ = std::make_unique<transport::Subscriber<ogf::map_command_t>>(
      bus, options_.command_channel,
      [this](const ogf::map_command_t& c, const lcm::ReceiveBuffer& rbuf, const std::string&) {
        enqueue(c, rbuf.data_size);
      },
      malformed, kServiceQueueCapacity, messages::kMaxCommandBytes);
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

void MapServices::enqueue(Request request, std::size_t bytes) {
  std::optional<std::pair<CommandRefusal, std::string>> refusal;
  {
    std::lock_guard lk(shared_.mu);
    ++requests_in_;
    const auto* c = std::get_if<ogf::map_command_t>(&request);
    shared_.stats.last_requester =
        sanitisedForLog(c ? c->requester : std::get<ogf::map_query_t>(request).requester);
    if (c) refusal = authenticate(*c);
    if (!refusal) {
      if (requests_.size() < kMaxWaitingServices && waiting_bytes_ + bytes <= kMaxWaitingServiceBytes) {
        requests_.push_back({std::move(request), bytes});
        waiting_bytes_ += bytes;
        shared_.wake();
        return;
      }
      refusal = std::pair{CommandRefusal::kBusy, "busy: " + std::to_string(requests_.size()) + " requests of " +
                                                     std::to_string(waiting_bytes_) + " bytes already wait"};
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
      request = std::move(requests_.front().request);
      waiting_bytes_ -= requests_.front().bytes;
      requests_.pop_front();
    }
    if (const auto* q = std::get_if<ogf::map_query_t>(&*request)) answer(*q);
    else carryOut(std::get<ogf::map_command_t>(*request));
  } while (std::chrono::steady_clock::now() - began < budget);
}

}  // namespace ogf::mapper_daemon
