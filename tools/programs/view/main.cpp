// ogf-view: the map in a browser. Follows OGF_MAP_DELTA as ogf-map-client does (a keyframe at start and
// after every gap, asked for on OGF_MAP_REQUEST), the 2-D navigation grid on OGF_NAV_GRID likewise
// (keyframes asked for on OGF_NAV_REQUEST), the robot's poses (POSE, POSE_CORRECTED) and the two status
// channels, or shows a saved map (--map), and serves one page with a WebSocket feed: the occupied cells and
// the grid's changed tiles as binary frames a few times a second, the figures and the poses as JSON.
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
#include <ogf/nav_grid_t.hpp>

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
#include "ogf/navigation/nav_receiver.hpp"
#include "ogf/navigation/nav_stream.hpp"
#include "ogf/pipeline/published_cells.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/lcm_asio_bridge.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"
#include "ogf/view/access_token.hpp"
#include "ogf/view/feed_state.hpp"
#include "ogf/view/keyframe_retry.hpp"
#include "ogf/view/occupied_slots.hpp"
#include "ogf/view/view_address.hpp"
#include "ogf/view/view_server.hpp"
#include "ogf/view/web_page.hpp"

namespace {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

// A step that cannot go on returns the exit code (after logging why); nullopt goes on.
using Stop = std::optional<int>;

struct Options {
  std::string url;
  std::string map_path;
  std::string bind = "127.0.0.1";
  std::uint16_t port = 8765;
  std::string delta_channel = "OGF_MAP_DELTA";
  std::string request_channel = "OGF_MAP_REQUEST";
  std::string nav_channel = "OGF_NAV_GRID";
  std::string nav_request_channel = "OGF_NAV_REQUEST";
  ogf::navigation::NavBand nav_band;  // --map: the band of the saved map's grid
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

  bool live() const { return map_path.empty(); }
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--lcm-url", o.url, "LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)");
  app.add_option("--map", o.map_path, "Show this map file (ogf-map --out) or daemon snapshot instead of the bus")
      ->check(CLI::ExistingFile);
  app.add_option("--bind", o.bind, "Address to serve on (0.0.0.0: every interface)")->capture_default_str();
  app.add_option("--port", o.port, "TCP port to serve on (0: any free port, printed at start)")->capture_default_str();
  app.add_option("--channel", o.delta_channel, "Delta channel")->capture_default_str();
  app.add_option("--request-channel", o.request_channel, "Keyframe request channel")->capture_default_str();
  app.add_option("--nav-channel", o.nav_channel, "2-D navigation grid channel (ogf.nav_grid_t)")->capture_default_str();
  app.add_option("--nav-request-channel", o.nav_request_channel, "Navigation grid keyframe request channel")
      ->capture_default_str();
  app.add_option("--nav-floor-z", o.nav_band.floor_z,
                 "--map: height of the floor in the map frame, metres (nav.floor_z of the mapper)")
      ->capture_default_str();
  app.add_option("--nav-min-height", o.nav_band.min_height, "--map: the band starts this far above the floor, metres")
      ->capture_default_str();
  app.add_option("--nav-max-height", o.nav_band.max_height, "--map: the band ends this far above the floor, metres")
      ->capture_default_str();
  app.add_option("--nav-min-free-fraction", o.nav_band.min_free_fraction,
                 "--map: fraction of the band's layers seen free that makes a column free")
      ->capture_default_str();
  app.add_option("--pose-channel", o.pose_channel, "Odometry channel (ogf.odometry_t or bot_core.pose_t)")
      ->capture_default_str();
  app.add_option("--corrected-channel", o.corrected_channel, "Corrected pose channel")->capture_default_str();
  app.add_option("--mapper-status-channel", o.mapper_status_channel, "Mapper status channel")->capture_default_str();
  app.add_option("--driver-status-channel", o.driver_status_channel, "Driver status channel")->capture_default_str();
  app.add_option("--rate", o.rate_hz, "Updates sent to the browsers per second")
      ->check(CLI::Range(0.2, 30.0))->capture_default_str();
  app.add_option("--max-boxes", o.max_boxes,
                 "Most boxes drawn: beyond, a box stands for 2x2x2 cells (4x4x4, ...), the level of detail")
      ->check(CLI::Range(std::size_t{1000}, std::size_t{50000000}))->capture_default_str();
  app.add_option("--keyframe-retry", o.keyframe_retry_s,
                 "Seconds between keyframe requests while one is needed (doubling up to 30 s while the stream "
                 "is not heard on the bus)")
      ->check(ogf::cli::positive())->capture_default_str();
  app.add_option("--three-dir", o.three_dir,
                 "Where three.js is installed (Debian's libjs-three): three.min.js and "
                 "examples/js/controls/OrbitControls.js")
      ->capture_default_str();
  app.add_option("--max-clients", o.limits.max_clients,
                 "Browsers served at once (each a WebSocket feed); the rest are refused with 503")
      ->check(CLI::Range(std::size_t{1}, std::size_t{10000}))->capture_default_str();
  app.add_option("--client-timeout", o.client_timeout_s,
                 "Seconds of silence after which a connection is closed: an incomplete or idle HTTP request, a "
                 "feed whose browser answers no ping or takes no data")
      ->check(CLI::Range(1.0, 3600.0))->capture_default_str();
  app.add_option("--memory-budget", o.memory_budget_mib,
                 "MiB of frames kept for browsers that are behind, in all; beyond, the slowest is disconnected")
      ->check(CLI::Range(std::size_t{16}, std::size_t{1} << 20))->capture_default_str();
  app.add_option("--token", o.token_path,
                 "File whose first line is the token every request must carry (?token=...); without it a "
                 "non-loopback --bind makes one and prints it in the address")
      ->check(CLI::ExistingFile);
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error")->capture_default_str();
}

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

// The token of --token FILE; an error message when unusable.
ogf::Result<std::string> tokenFromFile(const std::string& path) {
  const auto text = readFile(path);
  if (!text) return ogf::Error{"--token " + path + ": cannot read the file"};
  std::string token = ogf::view::tokenOfFileText(*text);
  if (auto why = ogf::view::tokenProblem(token)) return ogf::Error{"--token " + path + ": " + *why};
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && (st.st_mode & 077) != 0)
    spdlog::warn("--token {}: other users can read the file (chmod 600 it)", path);
  return token;
}

// The server's limits from the flags, with the token: --token's, or one made at start off loopback.
Stop resolveLimits(Options& o) {
  o.limits.client_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(o.client_timeout_s * 1000.0));
  o.limits.memory_budget = o.memory_budget_mib << 20;
  if (!o.token_path.empty()) {
    auto token = tokenFromFile(o.token_path);
    if (!token) {
      spdlog::error("{}", token.error().message);
      return kExitUsage;
    }
    o.limits.token = *token;
  } else if (!ogf::view::isLoopbackAddress(o.bind)) {
    auto token = randomToken();
    if (!token) {
      spdlog::error("cannot make a token (getrandom failed): give --token FILE");
      return kExitFailure;
    }
    o.limits.token = *token;
  }
  return std::nullopt;
}

// The page and three.js, served as they are.
Stop readPages(const Options& o, std::map<std::string, ogf::view::ViewServer::Page>& pages) {
  const std::string three_path = o.three_dir + "/three.min.js";
  const std::string controls_path = o.three_dir + "/examples/js/controls/OrbitControls.js";
  const auto three = readFile(three_path);
  const auto controls = readFile(controls_path);
  if (!three || !controls) {
    spdlog::error("cannot read {}: install libjs-three (apt-get install libjs-three) or give --three-dir",
                  !three ? three_path : controls_path);
    return kExitFailure;
  }
  pages["/"] = {"text/html; charset=utf-8", std::make_shared<const std::string>(ogf::view::indexHtml())};
  pages["/lib/three.min.js"] = {"text/javascript", std::make_shared<const std::string>(*three)};
  pages["/lib/OrbitControls.js"] = {"text/javascript", std::make_shared<const std::string>(*controls)};
  return std::nullopt;
}

// --map: the saved map's cells and figures, shown as they are.
Stop showSavedMap(const Options& o, ogf::view::FeedState& feed) {
  if (o.live()) {
    feed.stream().source = "live";
    return std::nullopt;
  }
  auto loaded = ogf::map_formats::loadOgfMap(o.map_path);
  if (!loaded) {
    spdlog::error("{}", loaded.error().message);
    return kExitFailure;
  }
  const auto cells = ogf::pipeline::publishedCellsOf(loaded->map);
  auto& slots = feed.slots();
  slots.reset(cells, ogf::view::chooseLod(cells, o.max_boxes));
  auto& stream = feed.stream();
  stream.source = o.map_path;
  stream.seq = loaded->seq;
  stream.cells = cells.size();
  stream.consistent = true;
  stream.resolution = loaded->map.config().resolution;
  spdlog::info("{} ({}): {} cells, {} occupied, drawn as {} boxes of {} cells a side", o.map_path, loaded->kind,
               cells.size(), slots.occupiedCells(), slots.occupied(), slots.lod());
  // The map's 2-D navigation grid, projected as the mapper does and given to the feed as one keyframe.
  auto projection = ogf::navigation::NavProjection::create(stream.resolution, o.nav_band);
  if (!projection) {
    spdlog::error("--nav-*: {}", projection.error().message);
    return kExitUsage;
  }
  for (const auto& c : cells)
    projection->update(
        {c.key, static_cast<double>(c.probability) / ogf::delta::kProbabilityScale, c.cell_class, c.variance});
  projection->refresh();
  for (const auto& m : ogf::navigation::NavStream(0).keyframe(0, *projection)) feed.navReceiver().accept(m);
  spdlog::info("navigation grid of the band {:.2f}..{:.2f} m above z = {:.2f} m: {} known columns",
               o.nav_band.min_height, o.nav_band.max_height, o.nav_band.floor_z, feed.navReceiver().knownColumns());
  return std::nullopt;
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

// The bus: the delta stream into the feed's receiver and the navigation grid into its own (for each, a
// keyframe asked for at start and after every gap, and again every --keyframe-retry while one is needed;
// less often while the stream is not heard, as the grid of a mapper with nav off: KeyframeRetry), the two
// status channels into the figures, the poses into the trails.
class BusFeed {
 public:
  BusFeed(const Options& o, ogf::view::FeedState& feed)
      : o_(o), feed_(feed), raw_poses_{&feed.figures().trail(false)}, corrected_poses_{&feed.figures().trail(true)},
        retry_(retryOf(o)), nav_retry_(retryOf(o)) {}

  Stop join(boost::asio::io_context& io) {
    const std::string resolved = ogf::transport::withReceiveBuffer(ogf::transport::resolveLcmUrl(o_.url));
    lcm_ = std::make_unique<lcm::LCM>(resolved);
    if (!lcm_->good()) {
      spdlog::error("cannot join the LCM bus {}", resolved);
      return kExitFailure;
    }
    if (const auto why = ogf::transport::receiveProblem(*lcm_, resolved)) {
      spdlog::error("{}", *why);
      return kExitFailure;
    }
    feed_.receiver().onDeltaCell([this](const ogf::delta::PublishedCell& c) { feed_.slots().set(c); });
    subscribe();
    bridge_ = std::make_unique<ogf::transport::LcmAsioBridge>(io, *lcm_);
    requestKeyframe();
    requestNavKeyframe();
    return std::nullopt;
  }

  // Every tick: a keyframe asked for again while one is needed, and a coarser level of detail when the
  // map outgrew the box budget.
  void tick() {
    if (!lcm_) return;
    auto& receiver = feed_.receiver();
    const auto now = std::chrono::steady_clock::now();
    if (receiver.needsKeyframe() && retry_.due(now)) requestKeyframe();
    if (feed_.navReceiver().needsKeyframe() && nav_retry_.due(now)) requestNavKeyframe();
    auto& slots = feed_.slots();
    if (slots.occupied() > o_.max_boxes) {
      const auto cells = receiver.map().sortedCells();
      slots.reset(cells, ogf::view::chooseLod(cells, o_.max_boxes));
      spdlog::info("{} occupied cells: drawn as {} boxes of {} cells a side", slots.occupiedCells(), slots.occupied(),
                   slots.lod());
    }
  }

 private:
  static ogf::view::KeyframeRetry retryOf(const Options& o) {
    using Clock = ogf::view::KeyframeRetry::Clock;
    return {std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.keyframe_retry_s)),
            std::chrono::seconds(30)};
  }

  void requestKeyframe() {
    const ogf::map_request_t req = ogf::delta::keyframeRequest(feed_.receiver(), requester_);
    lcm_->publish(o_.request_channel, &req);
    retry_.asked(std::chrono::steady_clock::now());
  }

  void requestNavKeyframe() {
    ogf::map_request_t req{};
    req.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                    std::chrono::system_clock::now().time_since_epoch()).count();
    req.requester = requester_;
    req.last_seq = feed_.navReceiver().appliedSeq();
    lcm_->publish(o_.nav_request_channel, &req);
    nav_retry_.asked(std::chrono::steady_clock::now());
  }

  // A receiver dropped what waited to complete (the parts went over their byte bound): said at most once a
  // second, for both streams together.
  template <class Receiver>
  void warnDropped(const char* stream, const Receiver& receiver) {
    if (auto n = dropped_log_.allow())
      spdlog::warn("the {}'s parts waiting to complete held more than {:.0f} MB: dropped the oldest update or "
                   "keyframe, {} so far ({} more)",
                   stream, static_cast<double>(receiver.heldBytesLimit()) / 1e6, receiver.dropped(), *n);
  }

  void onNavGrid(const ogf::nav_grid_t& m, const std::string& channel, std::size_t size) {
    auto& receiver = feed_.navReceiver();
    feed_.countNavMessage(true);
    const bool needed_before = receiver.needsKeyframe();
    const auto dropped_before = receiver.dropped();
    const auto outcome = receiver.accept(m);
    if (outcome == ogf::navigation::NavReceiver::Outcome::kMalformed) {
      if (auto n = malformed_log_.allow())
        spdlog::warn("message on {} ({} bytes, seq {}, part {} of {}) does not agree with itself: ignored ({} more)",
                     channel, size, m.seq, m.part_index, m.part_count, *n);
    } else if (outcome == ogf::navigation::NavReceiver::Outcome::kGap) {
      spdlog::warn("gap in the navigation grid after seq {}: asking for a keyframe", receiver.appliedSeq());
    }
    if (receiver.dropped() != dropped_before) warnDropped("navigation grid", receiver);
    if (outcome == ogf::navigation::NavReceiver::Outcome::kKeyframeApplied) {
      spdlog::debug("navigation keyframe applied: map {} seq {} known columns {}", receiver.mapId().value_or(-1),
                    receiver.appliedSeq(), receiver.knownColumns());
    }
    nav_retry_.heard();  // the first message makes a request due at the next tick
    if (receiver.needsKeyframe() && !needed_before) requestNavKeyframe();
  }

  void onDelta(const ogf::map_delta_t& m) {
    auto& receiver = feed_.receiver();
    ++feed_.stream().messages;
    const bool needed_before = receiver.needsKeyframe();
    const auto dropped_before = receiver.dropped();
    const auto outcome = receiver.accept(m);
    if (outcome == ogf::delta::MapReceiver::Outcome::kGap)
      spdlog::warn("gap in the delta stream after seq {}: asking for a keyframe", receiver.appliedSeq());
    if (receiver.dropped() != dropped_before) warnDropped("delta stream", receiver);
    if (receiver.keyframesApplied() != keyframes_seen_) {
      keyframes_seen_ = receiver.keyframesApplied();
      const auto cells = receiver.map().sortedCells();
      auto& slots = feed_.slots();
      slots.reset(cells, ogf::view::chooseLod(cells, o_.max_boxes));
      spdlog::info("keyframe applied: map {} seq {} cells {} occupied {} boxes {} of {} cells a side",
                   receiver.mapId().value_or(-1), receiver.appliedSeq(), receiver.map().size(),
                   slots.occupiedCells(), slots.occupied(), slots.lod());
    }
    retry_.heard();  // the first message makes a request due at the next tick
    if (receiver.needsKeyframe() && !needed_before) requestKeyframe();
  }

  void subscribe() {
    const auto on_error = [this](const std::string& channel, std::size_t size, std::string_view why) {
      feed_.countDecodeError();
      if (auto n = malformed_log_.allow()) spdlog::warn("message on {} ({} bytes) {} ({} more)", channel, size, why, *n);
    };
    auto& figures = feed_.figures();
    subscriptions_.push_back(std::make_shared<ogf::transport::Subscriber<ogf::nav_grid_t>>(
        *lcm_, o_.nav_channel,
        [this](const ogf::nav_grid_t& m, const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
          onNavGrid(m, channel, rbuf.data_size);
        },
        [this](const std::string& channel, std::size_t size, std::string_view why) {
          feed_.countNavMessage(false);
          if (auto n = malformed_log_.allow()) spdlog::warn("message on {} ({} bytes) {} ({} more)", channel, size, why, *n);
        }));
    subscriptions_.push_back(std::make_shared<ogf::transport::Subscriber<ogf::map_delta_t>>(
        *lcm_, o_.delta_channel,
        [this](const ogf::map_delta_t& m, const lcm::ReceiveBuffer&, const std::string&) { onDelta(m); }, on_error));
    subscriptions_.push_back(std::make_shared<ogf::transport::Subscriber<ogf::mapper_status_t>>(
        *lcm_, o_.mapper_status_channel,
        [&figures](const ogf::mapper_status_t& m, const lcm::ReceiveBuffer&, const std::string&) { figures.mapperStatus(m); },
        on_error));
    subscriptions_.push_back(std::make_shared<ogf::transport::Subscriber<ogf::driver_status_t>>(
        *lcm_, o_.driver_status_channel,
        [&figures](const ogf::driver_status_t& m, const lcm::ReceiveBuffer&, const std::string&) { figures.driverStatus(m); },
        on_error));
    lcm_->subscribeFunction(o_.pose_channel, &PoseSubscription::handle, &raw_poses_)
        ->setQueueCapacity(ogf::transport::kSubscriptionQueueCapacity);
    lcm_->subscribeFunction(o_.corrected_channel, &PoseSubscription::handle, &corrected_poses_)
        ->setQueueCapacity(ogf::transport::kSubscriptionQueueCapacity);
  }

  const Options& o_;
  ogf::view::FeedState& feed_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::vector<std::shared_ptr<void>> subscriptions_;
  std::unique_ptr<ogf::transport::LcmAsioBridge> bridge_;
  PoseSubscription raw_poses_;
  PoseSubscription corrected_poses_;
  ogf::view::KeyframeRetry retry_;
  ogf::view::KeyframeRetry nav_retry_;
  const std::string requester_ = ogf::delta::requesterName() + ":ogf-view";
  std::uint64_t keyframes_seen_ = 0;
  ogf::transport::LogRateLimiter malformed_log_;
  ogf::transport::LogRateLimiter dropped_log_;
};

// Every 1/rate s: what changed goes to the browsers, then the figures; the server's figures in the log
// once a minute when they changed.
class Ticker {
 public:
  Ticker(const Options& o, boost::asio::io_context& io, ogf::view::FeedState& feed, BusFeed* bus,
         ogf::view::ViewServer& server)
      : feed_(feed), bus_(bus), server_(server), timer_(io),
        period_(std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / o.rate_hz))) {}

  void tick() {
    if (bus_) bus_->tick();
    server_.broadcast(feed_.takeUpdate());
    server_.maintain();
    if (const auto now = std::chrono::steady_clock::now(); now - last_server_log_ > std::chrono::minutes(1)) {
      if (auto json = server_.statusJson(); json != last_server_status_) {
        spdlog::info("server: {}", json.substr(0, json.size() - 1));
        last_server_status_ = std::move(json);
      }
      last_server_log_ = now;
    }
    timer_.expires_after(period_);
    timer_.async_wait([this](const boost::system::error_code& ec) { if (!ec) tick(); });
  }

 private:
  ogf::view::FeedState& feed_;
  BusFeed* bus_;
  ogf::view::ViewServer& server_;
  boost::asio::steady_timer timer_;
  std::chrono::steady_clock::duration period_;
  std::chrono::steady_clock::time_point last_server_log_ = std::chrono::steady_clock::now();
  std::string last_server_status_;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Show the ogf map in a browser: follows OGF_MAP_DELTA and the 2-D navigation grid OGF_NAV_GRID (or "
               "shows a saved map) and serves a 3-D page with a live WebSocket feed."};
  Options o;
  addOptions(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (!o.map_path.empty() && !o.url.empty()) {
    std::fprintf(stderr, "--map shows a file and joins no bus: drop --lcm-url\n");
    return kExitUsage;
  }
  if (!ogf::transport::setupLoggingAt("ogf-view", "--log-level", o.log_level)) return kExitUsage;
  if (auto stop = resolveLimits(o)) return *stop;
  std::map<std::string, ogf::view::ViewServer::Page> pages;
  if (auto stop = readPages(o, pages)) return *stop;

  ogf::transport::DaemonLoop loop;
  ogf::view::FeedState feed(o.live());
  if (auto stop = showSavedMap(o, feed)) return *stop;
  auto server = ogf::view::ViewServer::start(loop.io(), o.bind, o.port, std::move(pages),
                                             [&feed] { return feed.wholeState(); }, o.limits);
  if (!server) {
    spdlog::error("{}", server.error().message);
    return kExitFailure;
  }
  std::optional<BusFeed> bus;  // the bus, unless a file is shown
  if (o.live()) {
    bus.emplace(o, feed);
    if (auto stop = bus->join(loop.io())) return *stop;
  }
  Ticker ticker(o, loop.io(), feed, bus ? &*bus : nullptr, **server);
  ticker.tick();

  std::fputs(ogf::view::addressLine(o.bind, (*server)->port(), o.limits.token, o.token_path).c_str(), stdout);
  std::fflush(stdout);
  loop.ready(o.live() ? "following " + o.delta_channel : "showing " + o.map_path);
  const int rc = loop.run();
  const auto json = (*server)->statusJson();
  spdlog::info("stopped: {}", json.substr(0, json.size() - 1));
  return rc;
}
