// ogf-view: the map in a browser. Follows OGF_MAP_DELTA as ogf-map-client does (a keyframe at start and
// after every gap, asked for on OGF_MAP_REQUEST), the robot's poses (POSE, POSE_CORRECTED) and the two
// status channels, or shows a saved map (--map), and serves one page with a WebSocket feed: the occupied
// cells as binary frames a few times a second, the figures and the poses as JSON.
//
// Who can connect and what each connection may cost is bounded (view_server.hpp); on an address other
// than loopback every request needs a token (access_token.hpp), read from --token FILE or made at start
// and printed in the address.
//
// Exit codes: 0 stopped by SIGINT/SIGTERM, 1 runtime failure (the bus, the port, the map file, three.js),
// 2 usage (the token file included).
#include <CLI/CLI.hpp>
#include <boost/asio/steady_timer.hpp>
#include <lcm/lcm-cpp.hpp>
#include <sys/random.h>
#include <sys/stat.h>

#include <ogf/driver_status_t.hpp>
#include <ogf/map_delta_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <optional>
#include <string>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/common/command_line.hpp"
#include "ogf/delta/keyframe_request.hpp"
#include "ogf/delta/map_receiver.hpp"
#include "ogf/map_formats/map_loader.hpp"
#include "ogf/pipeline/published_cells.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/lcm_asio_bridge.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"
#include "ogf/view/access_token.hpp"
#include "ogf/view/cell_frame.hpp"
#include "ogf/view/live_figures.hpp"
#include "ogf/view/occupied_slots.hpp"
#include "ogf/view/view_server.hpp"
#include "ogf/view/web_page.hpp"

namespace {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

std::optional<std::string> readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// 128 random bits as 32 hex digits.
std::optional<std::string> randomToken() {
  unsigned char bytes[16];
  if (::getrandom(bytes, sizeof bytes, 0) != static_cast<ssize_t>(sizeof bytes)) return std::nullopt;
  std::string out;
  for (const unsigned char b : bytes) out += fmt::format("{:02x}", b);
  return out;
}

// The token of --token FILE: its first line without surrounding blanks; an error message when unusable.
ogf::Result<std::string> tokenFromFile(const std::string& path) {
  const auto text = readFile(path);
  if (!text) return ogf::Error{"--token " + path + ": cannot read the file"};
  std::string token = text->substr(0, text->find('\n'));
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!token.empty() && blank(token.back())) token.pop_back();
  while (!token.empty() && blank(token.front())) token.erase(token.begin());
  if (auto why = ogf::view::tokenProblem(token)) return ogf::Error{"--token " + path + ": " + *why};
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && (st.st_mode & 077) != 0)
    spdlog::warn("--token {}: other users can read the file (chmod 600 it)", path);
  return token;
}

// A POSE channel carries ogf.odometry_t or bot_core.pose_t: decoded from the raw bytes.
struct PoseSubscription {
  ogf::view::PoseTrail* trail = nullptr;
  std::uint64_t rejected = 0;
  static void handle(const lcm::ReceiveBuffer* rbuf, const std::string&, PoseSubscription* self) {
    auto pose = ogf::adapters::decodePose(rbuf->data, rbuf->data_size);
    if (pose) {
      self->trail->add(*pose);
    } else {
      ++self->rejected;
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Show the ogf map in a browser: follows OGF_MAP_DELTA (or shows a saved map) and serves a 3-D "
               "page with a live WebSocket feed."};
  std::string url;
  std::string map_path;
  std::string bind = "127.0.0.1";
  std::uint16_t port = 8765;
  std::string delta_channel = "OGF_MAP_DELTA";
  std::string request_channel = "OGF_MAP_REQUEST";
  std::string pose_channel = "POSE";
  std::string corrected_channel = "POSE_CORRECTED";
  std::string mapper_status_channel = "OGF_MAPPER_STATUS";
  std::string driver_status_channel = "VELODYNE_STATUS";
  double rate_hz = 4.0;
  std::size_t max_boxes = 300000;
  double keyframe_retry_s = 1.0;
  std::string three_dir = "/usr/share/javascript/three";
  std::string log_level = "info";
  ogf::view::ServerLimits limits;
  double client_timeout_s = 30.0;
  std::size_t memory_budget_mib = limits.memory_budget >> 20;
  std::string token_path;
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)");
  app.add_option("--map", map_path, "Show this map file (ogf-map --out) or daemon snapshot instead of the bus")
      ->check(CLI::ExistingFile);
  app.add_option("--bind", bind, "Address to serve on (0.0.0.0: every interface)")->capture_default_str();
  app.add_option("--port", port, "TCP port to serve on (0: any free port, printed at start)")->capture_default_str();
  app.add_option("--channel", delta_channel, "Delta channel")->capture_default_str();
  app.add_option("--request-channel", request_channel, "Keyframe request channel")->capture_default_str();
  app.add_option("--pose-channel", pose_channel, "Odometry channel (ogf.odometry_t or bot_core.pose_t)")
      ->capture_default_str();
  app.add_option("--corrected-channel", corrected_channel, "Corrected pose channel")->capture_default_str();
  app.add_option("--mapper-status-channel", mapper_status_channel, "Mapper status channel")->capture_default_str();
  app.add_option("--driver-status-channel", driver_status_channel, "Driver status channel")->capture_default_str();
  app.add_option("--rate", rate_hz, "Updates sent to the browsers per second")
      ->check(CLI::Range(0.2, 30.0))->capture_default_str();
  app.add_option("--max-boxes", max_boxes,
                 "Most boxes drawn: beyond, a box stands for 2x2x2 cells (4x4x4, ...), the level of detail")
      ->check(CLI::Range(std::size_t{1000}, std::size_t{50000000}))->capture_default_str();
  app.add_option("--keyframe-retry", keyframe_retry_s, "Seconds between keyframe requests while one is needed")
      ->check(ogf::cli::positive())->capture_default_str();
  app.add_option("--three-dir", three_dir,
                 "Where three.js is installed (Debian's libjs-three): three.min.js and "
                 "examples/js/controls/OrbitControls.js")
      ->capture_default_str();
  app.add_option("--max-clients", limits.max_clients,
                 "Browsers served at once (each a WebSocket feed); the rest are refused with 503")
      ->check(CLI::Range(std::size_t{1}, std::size_t{10000}))->capture_default_str();
  app.add_option("--client-timeout", client_timeout_s,
                 "Seconds of silence after which a connection is closed: an incomplete or idle HTTP request, a "
                 "feed whose browser answers no ping or takes no data")
      ->check(CLI::Range(1.0, 3600.0))->capture_default_str();
  app.add_option("--memory-budget", memory_budget_mib,
                 "MiB of frames kept for browsers that are behind, in all; beyond, the slowest is disconnected")
      ->check(CLI::Range(std::size_t{16}, std::size_t{1} << 20))->capture_default_str();
  app.add_option("--token", token_path,
                 "File whose first line is the token every request must carry (?token=...); without it a "
                 "non-loopback --bind makes one and prints it in the address")
      ->check(CLI::ExistingFile);
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")->capture_default_str();
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (!map_path.empty() && !url.empty()) {
    std::fprintf(stderr, "--map shows a file and joins no bus: drop --lcm-url\n");
    return kExitUsage;
  }
  if (!ogf::transport::setupLoggingAt("ogf-view", "--log-level", log_level)) return kExitUsage;
  limits.client_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(client_timeout_s * 1000.0));
  limits.memory_budget = memory_budget_mib << 20;
  if (!token_path.empty()) {
    auto token = tokenFromFile(token_path);
    if (!token) {
      spdlog::error("{}", token.error().message);
      return kExitUsage;
    }
    limits.token = *token;
  } else if (!ogf::view::isLoopbackAddress(bind)) {
    auto token = randomToken();
    if (!token) {
      spdlog::error("cannot make a token (getrandom failed): give --token FILE");
      return kExitFailure;
    }
    limits.token = *token;
  }

  const std::string three_path = three_dir + "/three.min.js";
  const std::string controls_path = three_dir + "/examples/js/controls/OrbitControls.js";
  const auto three = readFile(three_path);
  const auto controls = readFile(controls_path);
  if (!three || !controls) {
    spdlog::error("cannot read {}: install libjs-three (apt-get install libjs-three) or give --three-dir",
                  !three ? three_path : controls_path);
    return kExitFailure;
  }

  ogf::transport::DaemonLoop loop;
  ogf::view::OccupiedSlots slots;
  ogf::view::LiveFigures figures;
  ogf::view::StreamFigures stream;
  ogf::delta::MapReceiver receiver;
  std::uint64_t decode_errors = 0;  // messages on the subscribed channels that did not decode

  if (!map_path.empty()) {
    auto loaded = ogf::map_formats::loadOgfMap(map_path);
    if (!loaded) {
      spdlog::error("{}", loaded.error().message);
      return kExitFailure;
    }
    const auto cells = ogf::pipeline::publishedCellsOf(loaded->map);
    slots.reset(cells, ogf::view::chooseLod(cells, max_boxes));
    stream.source = map_path;
    stream.seq = loaded->seq;
    stream.cells = cells.size();
    stream.consistent = true;
    stream.resolution = loaded->map.config().resolution;
    spdlog::info("{} ({}): {} cells, {} occupied, drawn as {} boxes of {} cells a side", map_path, loaded->kind,
                 cells.size(), slots.occupiedCells(), slots.occupied(), slots.lod());
  } else {
    stream.source = "live";
  }

  using ogf::view::Frame;
  const auto textFrame = [](std::string s) { return Frame{std::make_shared<const std::string>(std::move(s)), false}; };
  const auto cellFrames = [&](std::span<const std::uint32_t> which, bool full) {
    std::vector<Frame> out;
    for (auto& bytes : ogf::view::encodeCellFrames(slots, which, full, stream.resolution * slots.lod()))
      out.push_back(Frame{std::make_shared<const std::string>(bytes.begin(), bytes.end()), true});
    return out;
  };
  const auto refreshStream = [&] {
    stream.occupied = slots.occupiedCells();
    stream.boxes = slots.occupied();
    stream.lod = slots.lod();
    if (map_path.empty()) {
      stream.seq = receiver.appliedSeq();
      stream.cells = receiver.map().size();
      stream.gaps = receiver.gaps();
      stream.keyframes = receiver.keyframesApplied();
      stream.malformed = receiver.malformed() + decode_errors;
      stream.consistent = receiver.consistent();
      stream.waiting_for_keyframe = receiver.needsKeyframe();
      stream.resolution = receiver.resolution();
    }
  };

  std::map<std::string, ogf::view::ViewServer::Page> pages;
  pages["/"] = {"text/html; charset=utf-8", std::make_shared<const std::string>(ogf::view::indexHtml())};
  pages["/lib/three.min.js"] = {"text/javascript", std::make_shared<const std::string>(*three)};
  pages["/lib/OrbitControls.js"] = {"text/javascript", std::make_shared<const std::string>(*controls)};
  // The whole state, made once and shared by every browser that joins or catches up: the cells until
  // they change, the figures (with the whole trails) until the next tick.
  std::vector<Frame> whole_cells;
  std::optional<Frame> whole_figures;
  const auto wholeState = [&] {
    if (whole_cells.empty()) whole_cells = cellFrames(slots.filledSlots(), true);
    if (!whole_figures) {
      refreshStream();
      whole_figures = textFrame(figures.json(stream, 0, 0));
    }
    std::vector<Frame> out = whole_cells;
    out.push_back(*whole_figures);
    return out;
  };
  auto server = ogf::view::ViewServer::start(loop.io(), bind, port, std::move(pages), wholeState, limits);
  if (!server) {
    spdlog::error("{}", server.error().message);
    return kExitFailure;
  }
  auto& srv = **server;

  // The bus, unless a file is shown.
  std::unique_ptr<lcm::LCM> lcm;
  std::vector<std::shared_ptr<void>> subscriptions;
  std::unique_ptr<ogf::transport::LcmAsioBridge> bridge;
  PoseSubscription raw_poses{&figures.trail(false)};
  PoseSubscription corrected_poses{&figures.trail(true)};
  auto last_request = std::chrono::steady_clock::time_point{};
  const std::string requester = ogf::delta::requesterName() + ":ogf-view";
  const auto requestKeyframe = [&] {
    const ogf::map_request_t req = ogf::delta::keyframeRequest(receiver, requester);
    lcm->publish(request_channel, &req);
    last_request = std::chrono::steady_clock::now();
  };
  if (map_path.empty()) {
    const std::string resolved = ogf::transport::withReceiveBuffer(ogf::transport::resolveLcmUrl(url));
    lcm = std::make_unique<lcm::LCM>(resolved);
    if (!lcm->good()) {
      spdlog::error("cannot join the LCM bus {}", resolved);
      return kExitFailure;
    }
    receiver.onDeltaCell([&](const ogf::delta::PublishedCell& c) { slots.set(c); });
    std::uint64_t keyframes_seen = 0;
    ogf::transport::LogRateLimiter malformed_log;
    const auto on_error = [&](const std::string& channel, std::size_t size, std::string_view why) {
      ++decode_errors;
      if (auto n = malformed_log.allow()) spdlog::warn("message on {} ({} bytes) {} ({} more)", channel, size, why, *n);
    };
    subscriptions.push_back(std::make_shared<ogf::transport::Subscriber<ogf::map_delta_t>>(
        *lcm, delta_channel,
        [&, keyframes_seen](const ogf::map_delta_t& m, const lcm::ReceiveBuffer&, const std::string&) mutable {
          ++stream.messages;
          const bool needed_before = receiver.needsKeyframe();
          const auto outcome = receiver.accept(m);
          if (outcome == ogf::delta::MapReceiver::Outcome::kGap)
            spdlog::warn("gap in the delta stream after seq {}: asking for a keyframe", receiver.appliedSeq());
          if (receiver.keyframesApplied() != keyframes_seen) {
            keyframes_seen = receiver.keyframesApplied();
            const auto cells = receiver.map().sortedCells();
            slots.reset(cells, ogf::view::chooseLod(cells, max_boxes));
            spdlog::info("keyframe applied: map {} seq {} cells {} occupied {} boxes {} of {} cells a side",
                         receiver.mapId().value_or(-1), receiver.appliedSeq(), receiver.map().size(),
                         slots.occupiedCells(), slots.occupied(), slots.lod());
          }
          if (receiver.needsKeyframe() && !needed_before) requestKeyframe();
        },
        on_error));
    subscriptions.push_back(std::make_shared<ogf::transport::Subscriber<ogf::mapper_status_t>>(
        *lcm, mapper_status_channel,
        [&](const ogf::mapper_status_t& m, const lcm::ReceiveBuffer&, const std::string&) { figures.mapperStatus(m); },
        on_error));
    subscriptions.push_back(std::make_shared<ogf::transport::Subscriber<ogf::driver_status_t>>(
        *lcm, driver_status_channel,
        [&](const ogf::driver_status_t& m, const lcm::ReceiveBuffer&, const std::string&) { figures.driverStatus(m); },
        on_error));
    lcm->subscribeFunction(pose_channel, &PoseSubscription::handle, &raw_poses)
        ->setQueueCapacity(ogf::transport::kSubscriptionQueueCapacity);
    lcm->subscribeFunction(corrected_channel, &PoseSubscription::handle, &corrected_poses)
        ->setQueueCapacity(ogf::transport::kSubscriptionQueueCapacity);
    bridge = std::make_unique<ogf::transport::LcmAsioBridge>(loop.io(), *lcm);
    requestKeyframe();
  }

  // Every 1/rate s: what changed goes to the browsers, then the figures.
  boost::asio::steady_timer tick(loop.io());
  std::size_t raw_sent = 0;
  std::size_t corrected_sent = 0;
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
  auto last_server_log = std::chrono::steady_clock::now();
  std::string last_server_status;
  std::function<void()> flush = [&] {
    if (lcm && receiver.needsKeyframe() &&
        std::chrono::steady_clock::now() - last_request > std::chrono::duration<double>(keyframe_retry_s))
      requestKeyframe();
    if (lcm && slots.occupied() > max_boxes) {  // the map outgrew the box budget: a coarser level of detail
      const auto cells = receiver.map().sortedCells();
      slots.reset(cells, ogf::view::chooseLod(cells, max_boxes));
      spdlog::info("{} occupied cells: drawn as {} boxes of {} cells a side", slots.occupiedCells(), slots.occupied(),
                   slots.lod());
    }
    refreshStream();
    const bool full = slots.takeFullPending();
    const auto changed = slots.takeChanged();
    std::vector<Frame> update;
    if (full) {
      whole_cells = cellFrames(slots.filledSlots(), true);
      update = whole_cells;
    } else if (!changed.empty()) {
      whole_cells.clear();
      update = cellFrames(changed, false);
    }
    whole_figures.reset();
    update.push_back(textFrame(figures.json(stream, raw_sent, corrected_sent)));
    srv.broadcast(update);
    raw_sent = figures.trail(false).points().size();
    corrected_sent = figures.trail(true).points().size();
    srv.maintain();
    if (const auto now = std::chrono::steady_clock::now(); now - last_server_log > std::chrono::minutes(1)) {
      if (auto json = srv.statusJson(); json != last_server_status) {
        spdlog::info("server: {}", json.substr(0, json.size() - 1));
        last_server_status = std::move(json);
      }
      last_server_log = now;
    }
    tick.expires_after(period);
    tick.async_wait([&](const boost::system::error_code& ec) { if (!ec) flush(); });
  };
  flush();

  const std::string host = bind == "0.0.0.0" ? "127.0.0.1" : bind.find(':') != std::string::npos ? "[" + bind + "]" : bind;
  if (limits.token.empty()) {
    std::printf("ogf-view: http://%s:%u/\n", host.c_str(), static_cast<unsigned>(srv.port()));
  } else if (token_path.empty()) {
    std::printf("ogf-view: http://%s:%u/?token=%s\n", host.c_str(), static_cast<unsigned>(srv.port()),
                limits.token.c_str());
  } else {
    std::printf("ogf-view: http://%s:%u/ (add ?token= and the token in %s)\n", host.c_str(),
                static_cast<unsigned>(srv.port()), token_path.c_str());
  }
  std::fflush(stdout);
  loop.ready(map_path.empty() ? "following " + delta_channel : "showing " + map_path);
  const int rc = loop.run();
  const auto json = srv.statusJson();
  spdlog::info("stopped: {}", json.substr(0, json.size() - 1));
  return rc;
}
