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
#include <string>

#include "ogf/common/command_line.hpp"
#include "ogf/delta/keyframe_request.hpp"
#include "ogf/delta/map_receiver.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/lcm_asio_bridge.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Rebuild the ogf map from OGF_MAP_DELTA and print the checksum of that published map.\n\n"
      "Output at the end: map_id, seq, cells, published_checksum (of the map this client rebuilt), "
      "mapper_published_checksum (the one the mapper stamps on its deltas for the same seq), consistent (yes when "
      "the two are equal: nothing was missed), gaps, keyframes, malformed, messages.\n"
      "Both checksums cover the published cells (quantised probability, class, variance). The filter_checksum in "
      "OGF_MAPPER_STATUS covers every float the filter stores: a different number, to compare only with another "
      "mapper's filter_checksum or with the checksum ogf-map prints."};
  std::string url;
  std::string delta_channel = "OGF_MAP_DELTA";
  std::string request_channel = "OGF_MAP_REQUEST";
  double duration_s = 0;
  std::int64_t until_seq = -1;
  double idle_exit_s = 0;
  double keyframe_retry_s = 1.0;
  bool progress = false;
  std::string log_level = "info";
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)");
  app.add_option("--channel", delta_channel, "Delta channel")->capture_default_str();
  app.add_option("--request-channel", request_channel, "Keyframe request channel")->capture_default_str();
  app.add_option("--duration", duration_s, "Stop after this many seconds (0: run until SIGINT/SIGTERM)")
      ->check(ogf::cli::nonNegative());
  app.add_option("--until-seq", until_seq, "Stop once the map is consistent at this update sequence or later");
  app.add_option("--idle-exit", idle_exit_s,
                 "Stop after this many seconds without a delta once the map is consistent (0: never)")
      ->check(ogf::cli::nonNegative());
  app.add_option("--keyframe-retry", keyframe_retry_s, "Seconds between keyframe requests while one is needed")
      ->check(ogf::cli::positive())->capture_default_str();
  app.add_flag("--progress", progress, "Print a status line every second");
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")->capture_default_str();
  OGF_PARSE_COMMAND_LINE(app, argc, argv);

  if (!ogf::transport::setupLoggingAt("ogf-map-client", "--log-level", log_level)) return 2;
  const std::string resolved = ogf::transport::withReceiveBuffer(ogf::transport::resolveLcmUrl(url));
  lcm::LCM lcm(resolved);
  if (!lcm.good()) {
    spdlog::error("cannot join the LCM bus {}", resolved);
    return 2;
  }

  ogf::transport::DaemonLoop loop;
  ogf::delta::MapReceiver receiver;
  std::uint64_t messages = 0;
  std::uint64_t decode_errors = 0;
  auto last_delta = std::chrono::steady_clock::now();
  auto last_request = std::chrono::steady_clock::time_point{};
  const std::string requester = ogf::delta::requesterName();

  const auto requestKeyframe = [&] {
    const ogf::map_request_t req = ogf::delta::keyframeRequest(receiver, requester);
    lcm.publish(request_channel, &req);
    last_request = std::chrono::steady_clock::now();
    spdlog::debug("asked for a keyframe (last applied seq {})", req.last_seq);
  };

  ogf::transport::LogRateLimiter malformed_log;
  ogf::transport::Subscriber<ogf::map_delta_t> sub(
      lcm, delta_channel,
      [&](const ogf::map_delta_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        ++messages;
        last_delta = std::chrono::steady_clock::now();
        const bool needed_before = receiver.needsKeyframe();
        const auto outcome = receiver.accept(m);
        if (outcome == ogf::delta::MapReceiver::Outcome::kGap) {
          spdlog::warn("gap in the delta stream after seq {}: asking for a keyframe", receiver.appliedSeq());
        } else if (outcome == ogf::delta::MapReceiver::Outcome::kMalformed) {
          if (auto n = malformed_log.allow()) spdlog::warn("malformed delta seq {} part {}/{} ignored ({} more)", m.seq, m.part_index, m.part_count, *n);
        } else if (outcome == ogf::delta::MapReceiver::Outcome::kKeyframeApplied) {
          spdlog::info("keyframe applied: map {} seq {} cells {}", m.map_id, receiver.appliedSeq(), receiver.map().size());
        }
        if (receiver.needsKeyframe() && !needed_before) requestKeyframe();
        if (until_seq >= 0 && !receiver.needsKeyframe() && receiver.appliedSeq() >= until_seq && receiver.consistent())
          loop.requestStop(0);
      },
      [&](const std::string& channel, std::size_t size, std::string_view why) {
        ++decode_errors;
        if (auto n = malformed_log.allow()) spdlog::warn("message on {} ({} bytes) {} ({} more)", channel, size, why, *n);
      });
  ogf::transport::LcmAsioBridge bridge(loop.io(), lcm);

  // Housekeeping every 100 ms: keyframe requests while needed, progress, idle exit.
  boost::asio::steady_timer tick(loop.io());
  auto last_progress = std::chrono::steady_clock::now();
  std::function<void()> housekeeping = [&] {
    const auto now = std::chrono::steady_clock::now();
    if (receiver.needsKeyframe() && now - last_request > std::chrono::duration<double>(keyframe_retry_s)) requestKeyframe();
    if (progress && now - last_progress >= std::chrono::seconds(1)) {
      last_progress = now;
      std::printf("seq %lld cells %zu published_checksum %016llx gaps %llu messages %llu\n",
                  static_cast<long long>(receiver.appliedSeq()), receiver.map().size(),
                  static_cast<unsigned long long>(receiver.map().checksum()),
                  static_cast<unsigned long long>(receiver.gaps()), static_cast<unsigned long long>(messages));
      std::fflush(stdout);
    }
    if (idle_exit_s > 0 && receiver.consistent() && now - last_delta > std::chrono::duration<double>(idle_exit_s)) {
      loop.requestStop(0);
      return;
    }
    tick.expires_after(std::chrono::milliseconds(100));
    tick.async_wait([&](const boost::system::error_code& ec) { if (!ec) housekeeping(); });
  };
  housekeeping();

  boost::asio::steady_timer stop_timer(loop.io());
  if (duration_s > 0) {
    stop_timer.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(duration_s)));
    stop_timer.async_wait([&](const boost::system::error_code& ec) { if (!ec) loop.requestStop(0); });
  }
  loop.ready("following " + delta_channel);
  const int rc = loop.run();

  const auto server = receiver.serverChecksum();
  std::printf("map_id %lld seq %lld cells %zu published_checksum %016llx mapper_published_checksum %016llx "
              "consistent %s gaps %llu keyframes %llu malformed %llu messages %llu\n",
              static_cast<long long>(receiver.mapId().value_or(-1)), static_cast<long long>(receiver.appliedSeq()),
              receiver.map().size(), static_cast<unsigned long long>(receiver.map().checksum()),
              static_cast<unsigned long long>(server.value_or(0)), receiver.consistent() ? "yes" : "no",
              static_cast<unsigned long long>(receiver.gaps()),
              static_cast<unsigned long long>(receiver.keyframesApplied()),
              static_cast<unsigned long long>(receiver.malformed() + decode_errors),
              static_cast<unsigned long long>(messages));
  return rc;
}
