// ogf-map-client: follows the OGF_MAP_DELTA stream the way a planner or viewer would: rebuilds the map
// from deltas and keyframes, asks for a keyframe (map_request_t on OGF_MAP_REQUEST) at start and after
// any gap, and prints the checksum of the published map it rebuilt (cells as the deltas carry them:
// quantised probability, class, variance), which equals the checksum the mapper stamps on each delta
// when nothing was missed. Neither is the status's filter_checksum (every float the filter stores).
//
// Output: a line per second while running (with --progress) and, at the end,
//   map_id <id> seq <n> cells <n> published_checksum <hex> mapper_published_checksum <hex>
//   consistent <yes|no> gaps <n> keyframes <n> malformed <n> messages <n>
#include <CLI/CLI.hpp>
#include <boost/asio/steady_timer.hpp>
#include <lcm/lcm-cpp.hpp>

#include <ogf/map_delta_t.hpp>
#include <ogf/map_request_t.hpp>

#include <chrono>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>

#include "ogf/common/command_line.hpp"
#include "ogf/delta/keyframe_request.hpp"
#include "ogf/delta/map_receiver.hpp"
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
    "the two are equal: nothing was missed), gaps, keyframes, malformed, messages.\n"
    "Both checksums cover the published cells (quantised probability, class, variance). The filter_checksum in "
    "OGF_MAPPER_STATUS covers every float the filter stores: a different number, to compare only with another "
    "mapper's filter_checksum or with the checksum ogf-map prints.";

struct Options {
  std::string url;
  std::string delta_channel = "OGF_MAP_DELTA";
  std::string request_channel = "OGF_MAP_REQUEST";
  double duration_s = 0;
  std::int64_t until_seq = -1;
  double idle_exit_s = 0;
  double keyframe_retry_s = 1.0;
  bool progress = false;
  std::string log_level = "info";
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--lcm-url", o.url, "LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)");
  app.add_option("--channel", o.delta_channel, "Delta channel")->capture_default_str();
  app.add_option("--request-channel", o.request_channel, "Keyframe request channel")->capture_default_str();
  app.add_option("--duration", o.duration_s, "Stop after this many seconds (0: run until SIGINT/SIGTERM)")
      ->check(ogf::cli::nonNegative());
  app.add_option("--until-seq", o.until_seq, "Stop once the map is consistent at this update sequence or later");
  app.add_option("--idle-exit", o.idle_exit_s,
                 "Stop after this many seconds without a delta once the map is consistent (0: never)")
      ->check(ogf::cli::nonNegative());
  app.add_option("--keyframe-retry", o.keyframe_retry_s, "Seconds between keyframe requests while one is needed")
      ->check(ogf::cli::positive())->capture_default_str();
  app.add_flag("--progress", o.progress, "Print a status line every second");
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error")->capture_default_str();
}

// The delta stream rebuilt into a map: a keyframe asked for at start and after every gap, and the stops
// --until-seq and --idle-exit ask for.
class DeltaFollower {
 public:
  DeltaFollower(const Options& o, lcm::LCM& lcm, ogf::transport::DaemonLoop& loop)
      : o_(o), lcm_(lcm), loop_(loop), tick_(loop.io()),
        sub_(lcm, o.delta_channel,
             [this](const ogf::map_delta_t& m, const lcm::ReceiveBuffer&, const std::string&) { onDelta(m); },
             [this](const std::string& channel, std::size_t size, std::string_view why) {
               ++decode_errors_;
               if (auto n = malformed_log_.allow())
                 spdlog::warn("message on {} ({} bytes) {} ({} more)", channel, size, why, *n);
             }) {}

  // Housekeeping every 100 ms: keyframe requests while needed, progress, idle exit.
  void housekeeping() {
    const auto now = std::chrono::steady_clock::now();
    if (receiver_.needsKeyframe() && now - last_request_ > std::chrono::duration<double>(o_.keyframe_retry_s))
      requestKeyframe();
    if (o_.progress && now - last_progress_ >= std::chrono::seconds(1)) {
      last_progress_ = now;
      std::printf("seq %lld cells %zu published_checksum %016llx gaps %llu messages %llu\n",
                  static_cast<long long>(receiver_.appliedSeq()), receiver_.map().size(),
                  static_cast<unsigned long long>(receiver_.map().checksum()),
                  static_cast<unsigned long long>(receiver_.gaps()), static_cast<unsigned long long>(messages_));
      std::fflush(stdout);
    }
    if (o_.idle_exit_s > 0 && receiver_.consistent() && now - last_delta_ > std::chrono::duration<double>(o_.idle_exit_s)) {
      loop_.requestStop(0);
      return;
    }
    tick_.expires_after(std::chrono::milliseconds(100));
    tick_.async_wait([this](const boost::system::error_code& ec) { if (!ec) housekeeping(); });
  }

  // The line printed at the end (see the top of this file).
  void printSummary() const {
    const auto server = receiver_.serverChecksum();
    std::printf("map_id %lld seq %lld cells %zu published_checksum %016llx mapper_published_checksum %016llx "
                "consistent %s gaps %llu keyframes %llu malformed %llu messages %llu\n",
                static_cast<long long>(receiver_.mapId().value_or(-1)), static_cast<long long>(receiver_.appliedSeq()),
                receiver_.map().size(), static_cast<unsigned long long>(receiver_.map().checksum()),
                static_cast<unsigned long long>(server.value_or(0)), receiver_.consistent() ? "yes" : "no",
                static_cast<unsigned long long>(receiver_.gaps()),
                static_cast<unsigned long long>(receiver_.keyframesApplied()),
                static_cast<unsigned long long>(receiver_.malformed() + decode_errors_),
                static_cast<unsigned long long>(messages_));
  }

 private:
  void requestKeyframe() {
    const ogf::map_request_t req = ogf::delta::keyframeRequest(receiver_, requester_);
    lcm_.publish(o_.request_channel, &req);
    last_request_ = std::chrono::steady_clock::now();
    spdlog::debug("asked for a keyframe (last applied seq {})", req.last_seq);
  }

  void onDelta(const ogf::map_delta_t& m) {
    ++messages_;
    last_delta_ = std::chrono::steady_clock::now();
    const bool needed_before = receiver_.needsKeyframe();
    const auto outcome = receiver_.accept(m);
    if (outcome == ogf::delta::MapReceiver::Outcome::kGap) {
      spdlog::warn("gap in the delta stream after seq {}: asking for a keyframe", receiver_.appliedSeq());
    } else if (outcome == ogf::delta::MapReceiver::Outcome::kMalformed) {
      if (auto n = malformed_log_.allow()) spdlog::warn("malformed delta seq {} part {}/{} ignored ({} more)", m.seq, m.part_index, m.part_count, *n);
    } else if (outcome == ogf::delta::MapReceiver::Outcome::kKeyframeApplied) {
      spdlog::info("keyframe applied: map {} seq {} cells {}", m.map_id, receiver_.appliedSeq(), receiver_.map().size());
    }
    if (receiver_.needsKeyframe() && !needed_before) requestKeyframe();
    if (o_.until_seq >= 0 && !receiver_.needsKeyframe() && receiver_.appliedSeq() >= o_.until_seq && receiver_.consistent())
      loop_.requestStop(0);
  }

  const Options& o_;
  lcm::LCM& lcm_;
  ogf::transport::DaemonLoop& loop_;
  ogf::delta::MapReceiver receiver_;
  std::uint64_t messages_ = 0;
  std::uint64_t decode_errors_ = 0;
  std::chrono::steady_clock::time_point last_delta_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_request_{};
  std::chrono::steady_clock::time_point last_progress_ = std::chrono::steady_clock::now();
  const std::string requester_ = ogf::delta::requesterName();
  ogf::transport::LogRateLimiter malformed_log_;
  boost::asio::steady_timer tick_;
  ogf::transport::Subscriber<ogf::map_delta_t> sub_;
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

  ogf::transport::DaemonLoop loop;
  DeltaFollower follower(o, lcm, loop);
  ogf::transport::LcmAsioBridge bridge(loop.io(), lcm);
  follower.housekeeping();
  boost::asio::steady_timer stop_timer(loop.io());
  stopAfter(o.duration_s, stop_timer, loop);
  loop.ready("following " + o.delta_channel);
  const int rc = loop.run();
  follower.printSummary();
  return rc;
}
