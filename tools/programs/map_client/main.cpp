// ogf-map-client: follows the OGF_MAP_DELTA stream the way a planner or viewer would: rebuilds the map
// from deltas and keyframes, asks for a keyframe (map_request_t on OGF_MAP_REQUEST) at start and after
// any gap, and prints the checksum of the published map it rebuilt (cells as the deltas carry them:
// quantised probability, class, variance), which equals the checksum the mapper stamps on each delta
// when nothing was missed. Neither is the status's filter_checksum (every float the filter stores).
//
// With --nav (or --nav-only, without the 3-D deltas) it follows the 2-D navigation grid on OGF_NAV_GRID the
// same way (navigation::NavReceiver; keyframes asked for on OGF_NAV_REQUEST) and prints the grid's checksum.
//
// Output: a line per second while running (with --progress) and, at the end,
//   map_id <id> seq <n> cells <n> published_checksum <hex> mapper_published_checksum <hex>
//   consistent <yes|no> gaps <n> keyframes <n> malformed <n> messages <n> dropped <n>
// and with --nav or --nav-only (the first line only without --nav-only)
//   nav_map_id <id> nav_seq <n> nav_known_columns <n> nav_checksum <hex> mapper_nav_checksum <hex>
//   nav_consistent <yes|no> nav_gaps <n> nav_keyframes <n> nav_malformed <n> nav_dropped <n>
// dropped: updates and keyframes whose parts, waiting, went over --max-held-mb (anyone on the bus can send
// parts that never complete; what they may hold is bounded, delta/update_sequence.hpp).
#include <CLI/CLI.hpp>
#include <boost/asio/steady_timer.hpp>
#include <lcm/lcm-cpp.hpp>

#include <ogf/map_delta_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/nav_grid_t.hpp>

#include <chrono>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>

#include "ogf/common/command_line.hpp"
#include "ogf/delta/keyframe_request.hpp"
#include "ogf/delta/map_receiver.hpp"
#include "ogf/navigation/nav_receiver.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/lcm_asio_bridge.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

namespace {

constexpr int kExitUsage = 2;  // bad flags, or the bus cannot be joined

const char* const kDescription =
    "Rebuild the ogf map from OGF_MAP_DELTA and print the checksum of that published map.\n\n"
    "Output at the end: map_id, seq, cells, published_checksum (of the map this client rebuilt), "
    "mapper_published_checksum (the one the mapper stamps on its deltas for the same seq), consistent (yes when "
    "the two are equal: nothing was missed), gaps, keyframes, malformed, messages, dropped (updates and keyframes "
    "dropped because the parts waiting went over --max-held-mb).\n"
    "Both checksums cover the published cells (quantised probability, class, variance). The filter_checksum in "
    "OGF_MAPPER_STATUS covers every float the filter stores: a different number, to compare only with another "
    "mapper's filter_checksum or with the checksum ogf-map prints.\n"
    "With --nav (or --nav-only) it also (only) follows the 2-D navigation grid on OGF_NAV_GRID and prints at the "
    "end nav_map_id, nav_seq, nav_known_columns, nav_checksum (of the grid it rebuilt), mapper_nav_checksum (the "
    "mapper's for the same nav_seq), nav_consistent, nav_gaps, nav_keyframes, nav_malformed, nav_dropped.";

struct Options {
  std::string url;
  std::string delta_channel = "OGF_MAP_DELTA";
  std::string request_channel = "OGF_MAP_REQUEST";
  bool nav = false;
  bool nav_only = false;
  std::string nav_channel = "OGF_NAV_GRID";
  std::string nav_request_channel = "OGF_NAV_REQUEST";
  double duration_s = 0;
  std::int64_t until_seq = -1;
  double idle_exit_s = 0;
  double keyframe_retry_s = 1.0;
  bool progress = false;
  std::optional<double> max_held_mb;
  std::string log_level = "info";
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--lcm-url", o.url, "LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)");
  app.add_option("--channel", o.delta_channel, "Delta channel")->capture_default_str();
  app.add_option("--request-channel", o.request_channel, "Keyframe request channel")->capture_default_str();
  app.add_flag("--nav", o.nav, "Also follow the 2-D navigation grid");
  app.add_flag("--nav-only", o.nav_only, "Follow only the 2-D navigation grid, not the 3-D deltas");
  app.add_option("--nav-channel", o.nav_channel, "Navigation grid channel")->capture_default_str();
  app.add_option("--nav-request-channel", o.nav_request_channel, "Navigation grid keyframe request channel")
      ->capture_default_str();
  app.add_option("--duration", o.duration_s, "Stop after this many seconds (0: run until SIGINT/SIGTERM)")
      ->check(ogf::cli::nonNegative());
  app.add_option("--until-seq", o.until_seq,
                 "Stop once the map is consistent at this update sequence or later (with --nav-only: the grid)");
  app.add_option("--idle-exit", o.idle_exit_s,
                 "Stop after this many seconds without a message once the map (and the grid) is consistent (0: never)")
      ->check(ogf::cli::nonNegative());
  app.add_option("--keyframe-retry", o.keyframe_retry_s, "Seconds between keyframe requests while one is needed")
      ->check(ogf::cli::positive())->capture_default_str();
  app.add_flag("--progress", o.progress, "Print a status line every second");
  app.add_option("--max-held-mb", o.max_held_mb,
                 "MB the parts of updates and keyframes waiting to complete may hold besides the map held (default 64 "
                 "for the map, 16 for the grid); past it the oldest is dropped and counted")
      ->check(ogf::cli::positive());
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error")->capture_default_str();
}

// What the followers of the two streams say, each in its own words: the progress line, the line at the end
// (see the top of this file), the size of what a keyframe brought, and the keyframe request.
void printProgress(const ogf::delta::MapReceiver& r, std::uint64_t messages) {
  std::printf("seq %lld cells %zu published_checksum %016llx gaps %llu messages %llu\n",
              static_cast<long long>(r.appliedSeq()), r.map().size(), static_cast<unsigned long long>(r.map().checksum()),
              static_cast<unsigned long long>(r.gaps()), static_cast<unsigned long long>(messages));
}
void printProgress(const ogf::navigation::NavReceiver& r, std::uint64_t messages) {
  std::printf("nav_seq %lld nav_known_columns %zu nav_checksum %016llx nav_gaps %llu nav_messages %llu\n",
              static_cast<long long>(r.appliedSeq()), r.knownColumns(), static_cast<unsigned long long>(r.checksum()),
              static_cast<unsigned long long>(r.gaps()), static_cast<unsigned long long>(messages));
}
void printSummary(const ogf::delta::MapReceiver& r, std::uint64_t malformed, std::uint64_t messages) {
  std::printf("map_id %lld seq %lld cells %zu published_checksum %016llx mapper_published_checksum %016llx "
              "consistent %s gaps %llu keyframes %llu malformed %llu messages %llu dropped %llu\n",
              static_cast<long long>(r.mapId().value_or(-1)), static_cast<long long>(r.appliedSeq()), r.map().size(),
              static_cast<unsigned long long>(r.map().checksum()),
              static_cast<unsigned long long>(r.serverChecksum().value_or(0)), r.consistent() ? "yes" : "no",
              static_cast<unsigned long long>(r.gaps()), static_cast<unsigned long long>(r.keyframesApplied()),
              static_cast<unsigned long long>(malformed), static_cast<unsigned long long>(messages),
              static_cast<unsigned long long>(r.dropped()));
}
void printSummary(const ogf::navigation::NavReceiver& r, std::uint64_t malformed, std::uint64_t) {
  std::printf("nav_map_id %lld nav_seq %lld nav_known_columns %zu nav_checksum %016llx mapper_nav_checksum %016llx "
              "nav_consistent %s nav_gaps %llu nav_keyframes %llu nav_malformed %llu nav_dropped %llu\n",
              static_cast<long long>(r.mapId().value_or(-1)), static_cast<long long>(r.appliedSeq()), r.knownColumns(),
              static_cast<unsigned long long>(r.checksum()), static_cast<unsigned long long>(r.serverChecksum().value_or(0)),
              r.consistent() ? "yes" : "no", static_cast<unsigned long long>(r.gaps()),
              static_cast<unsigned long long>(r.keyframesApplied()), static_cast<unsigned long long>(malformed),
              static_cast<unsigned long long>(r.dropped()));
}
std::string holding(const ogf::delta::MapReceiver& r) { return fmt::format("cells {}", r.map().size()); }
std::string holding(const ogf::navigation::NavReceiver& r) { return fmt::format("known columns {}", r.knownColumns()); }
ogf::map_request_t requestOf(const ogf::delta::MapReceiver& r, const std::string& requester) {
  return ogf::delta::keyframeRequest(r, requester);
}
ogf::map_request_t requestOf(const ogf::navigation::NavReceiver& r, const std::string& requester) {
  ogf::map_request_t req{};
  req.utime = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
                  .count();
  req.requester = requester;
  req.last_seq = r.appliedSeq();
  return req;
}

// One stream rebuilt by its receiver (the 3-D map from OGF_MAP_DELTA, or the navigation grid from
// OGF_NAV_GRID): a keyframe asked for at start, after every gap and every --keyframe-retry while one is
// needed, and the stop --until-seq asks for (`until_seq`: whether it applies to this stream).
template <class Receiver, class Message>
class StreamFollower {
 public:
  struct Stream {
    std::string channel, request_channel;
    std::string name;  // in the log: "delta stream", "navigation grid"
    bool until_seq = false;
  };

  StreamFollower(const Options& o, Stream stream, lcm::LCM& lcm, ogf::transport::DaemonLoop& loop)
      : o_(o), stream_(std::move(stream)), lcm_(lcm), loop_(loop),
        receiver_(Receiver::kDefaultBufferedUpdates,
                  o.max_held_mb ? static_cast<std::size_t>(*o.max_held_mb * 1e6) : Receiver::kDefaultMinHeldBytes),
        sub_(lcm, stream_.channel,
             [this](const Message& m, const lcm::ReceiveBuffer&, const std::string&) { onMessage(m); },
             [this](const std::string& channel, std::size_t size, std::string_view why) {
               ++decode_errors_;
               if (auto n = malformed_log_.allow())
                 spdlog::warn("message on {} ({} bytes) {} ({} more)", channel, size, why, *n);
             }) {}

  // Housekeeping every 100 ms: keyframe requests while needed, progress.
  void housekeeping(std::chrono::steady_clock::time_point now) {
    if (receiver_.needsKeyframe() && now - last_request_ > std::chrono::duration<double>(o_.keyframe_retry_s))
      requestKeyframe();
    if (o_.progress && now - last_progress_ >= std::chrono::seconds(1)) {
      last_progress_ = now;
      printProgress(receiver_, messages_);
      std::fflush(stdout);
    }
  }
  // Consistent, and no message for `idle`.
  bool quiet(std::chrono::steady_clock::time_point now, std::chrono::duration<double> idle) const {
    return receiver_.consistent() && now - last_message_ > idle;
  }
  void printSummary() const { ::printSummary(receiver_, receiver_.malformed() + decode_errors_, messages_); }

 private:
  void requestKeyframe() {
    const ogf::map_request_t req = requestOf(receiver_, requester_);
    lcm_.publish(stream_.request_channel, &req);
    last_request_ = std::chrono::steady_clock::now();
    spdlog::debug("asked for a keyframe of the {} (last applied seq {})", stream_.name, req.last_seq);
  }

  void onMessage(const Message& m) {
    ++messages_;
    last_message_ = std::chrono::steady_clock::now();
    const bool needed_before = receiver_.needsKeyframe();
    const auto dropped_before = receiver_.dropped();
    const auto outcome = receiver_.accept(m);
    using Outcome = typename Receiver::Outcome;
    if (outcome == Outcome::kGap) {
      spdlog::warn("gap in the {} after seq {}: asking for a keyframe", stream_.name, receiver_.appliedSeq());
    } else if (outcome == Outcome::kMalformed) {
      if (auto n = malformed_log_.allow())
        spdlog::warn("malformed {} message seq {} part {}/{} ignored ({} more)", stream_.name, m.seq, m.part_index,
                     m.part_count, *n);
    }
    if (receiver_.dropped() != dropped_before) {
      if (auto n = dropped_log_.allow())
        spdlog::warn("the parts of the {} waiting to complete held more than {:.0f} MB besides what is applied "
                     "(--max-held-mb): dropped the oldest update or keyframe, {} so far ({} more)",
                     stream_.name, static_cast<double>(receiver_.heldBytesLimit()) / 1e6, receiver_.dropped(), *n);
    }
    if (outcome == Outcome::kKeyframeApplied) {
      spdlog::info("{} keyframe applied: map {} seq {} {}", stream_.name, m.map_id, receiver_.appliedSeq(),
                   holding(receiver_));
    }
    if (receiver_.needsKeyframe() && !needed_before) requestKeyframe();
    if (stream_.until_seq && o_.until_seq >= 0 && !receiver_.needsKeyframe() && receiver_.appliedSeq() >= o_.until_seq &&
        receiver_.consistent())
      loop_.requestStop(0);
  }

  const Options& o_;
  const Stream stream_;
  lcm::LCM& lcm_;
  ogf::transport::DaemonLoop& loop_;
  Receiver receiver_;
  std::uint64_t messages_ = 0;
  std::uint64_t decode_errors_ = 0;
  std::chrono::steady_clock::time_point last_message_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_request_{};
  std::chrono::steady_clock::time_point last_progress_ = std::chrono::steady_clock::now();
  const std::string requester_ = ogf::delta::requesterName();
  ogf::transport::LogRateLimiter malformed_log_;
  ogf::transport::LogRateLimiter dropped_log_;
  ogf::transport::Subscriber<Message> sub_;
};

using DeltaFollower = StreamFollower<ogf::delta::MapReceiver, ogf::map_delta_t>;
using NavFollower = StreamFollower<ogf::navigation::NavReceiver, ogf::nav_grid_t>;

// Every 100 ms: each follower's housekeeping, and the stop --idle-exit asks for once every stream followed is
// consistent and quiet.
class Housekeeping {
 public:
  Housekeeping(const Options& o, ogf::transport::DaemonLoop& loop, DeltaFollower* deltas, NavFollower* nav)
      : o_(o), loop_(loop), deltas_(deltas), nav_(nav), tick_(loop.io()) {}

  void run() {
    const auto now = std::chrono::steady_clock::now();
    if (deltas_ != nullptr) deltas_->housekeeping(now);
    if (nav_ != nullptr) nav_->housekeeping(now);
    const std::chrono::duration<double> idle(o_.idle_exit_s);
    if (o_.idle_exit_s > 0 && (deltas_ == nullptr || deltas_->quiet(now, idle)) && (nav_ == nullptr || nav_->quiet(now, idle))) {
      loop_.requestStop(0);
      return;
    }
    tick_.expires_after(std::chrono::milliseconds(100));
    tick_.async_wait([this](const boost::system::error_code& ec) { if (!ec) run(); });
  }

 private:
  const Options& o_;
  ogf::transport::DaemonLoop& loop_;
  DeltaFollower* deltas_;
  NavFollower* nav_;
  boost::asio::steady_timer tick_;
};

// --duration: a stop after that many seconds.
void stopAfter(double seconds, boost::asio::steady_timer& timer, ogf::transport::DaemonLoop& loop) {
  if (seconds <= 0) return;
  timer.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds)));
  timer.async_wait([&loop](const boost::system::error_code& ec) { if (!ec) loop.requestStop(0); });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{kDescription};
  Options o;
  addOptions(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (!ogf::transport::setupLoggingAt("ogf-map-client", "--log-level", o.log_level)) return kExitUsage;
  const std::string resolved = ogf::transport::withReceiveBuffer(ogf::transport::resolveLcmUrl(o.url));
  lcm::LCM lcm(resolved);
  if (!lcm.good()) {
    spdlog::error("cannot join the LCM bus {}", resolved);
    return kExitUsage;
  }
  if (const auto why = ogf::transport::receiveProblem(lcm, resolved)) {
    spdlog::error("{}", *why);
    return kExitUsage;
  }

  ogf::transport::DaemonLoop loop;
  std::optional<DeltaFollower> deltas;
  std::optional<NavFollower> nav;
  if (!o.nav_only)
    deltas.emplace(o, DeltaFollower::Stream{o.delta_channel, o.request_channel, "delta stream", true}, lcm, loop);
  if (o.nav || o.nav_only)
    nav.emplace(o, NavFollower::Stream{o.nav_channel, o.nav_request_channel, "navigation grid", o.nav_only}, lcm, loop);
  ogf::transport::LcmAsioBridge bridge(loop.io(), lcm);
  Housekeeping housekeeping(o, loop, deltas ? &*deltas : nullptr, nav ? &*nav : nullptr);
  housekeeping.run();
  boost::asio::steady_timer stop_timer(loop.io());
  stopAfter(o.duration_s, stop_timer, loop);
  loop.ready("following " + (o.nav_only ? o.nav_channel : o.delta_channel + (nav ? " and " + o.nav_channel : "")));
  const int rc = loop.run();
  if (deltas) deltas->printSummary();
  if (nav) nav->printSummary();
  return rc;
}
