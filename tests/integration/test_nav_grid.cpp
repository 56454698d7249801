// The live 2-D navigation grid (OGF_NAV_GRID) of ogf-mapper as a real process on real LCM (udpm on
// loopback), fed the scans of a robot driving round a walled room (scan_feeder.hpp: walls at x = ±5 m and
// y = ±4 m, 2 m high, floor at z = 0, the sensor 0.5 m above it):
// - ogf-map-client --nav follows the grid to the mapper's checksum while the mapper drops a share of its grid
//   updates (gap injection): it sees the gaps and recovers by keyframe; the 3-D deltas beside it stay
//   consistent too;
// - the grid is the room's: known columns only inside it, occupied ones along the walls, free ones in the
//   middle;
// - after a restart from the state directory (with regions paged out or not) the grid has the same columns
//   from the first status on, and a client following only the grid gets them;
// - keyframe requests on OGF_NAV_REQUEST, well-formed or not, are counted.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/nav_grid_t.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ogf/navigation/nav_receiver.hpp"
#include "scan_feeder.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/lcm_thread.hpp"
#include "support/multicast.hpp"
#include "support/output_field.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using ogf::testing::outputField;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;
using ogf::testing::kMapperStatusChannel;

const std::string kBin = OGF_BIN_DIR;
constexpr double kRes = 0.2;  // the mapper's default resolution

// The last line of `text` that starts with `prefix`.
std::string lineStarting(const std::string& text, const std::string& prefix) {
  std::string found, line;
  std::istringstream in(text);
  while (std::getline(in, line))
    if (line.rfind(prefix, 0) == 0) found = line;
  return found;
}

std::string hex(std::int64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// A grid client inside the test: the grid as OGF_NAV_GRID carries it (keyframes asked for by others).
class GridListener {
 public:
  explicit GridListener(const std::string& url) : bus_(url) {
    bus_.lcm().subscribe("OGF_NAV_GRID", &GridListener::onGrid, this)->setQueueCapacity(10000);
    bus_.start(20ms);
  }
  ogf::navigation::NavGrid grid() const {
    std::lock_guard lk(mu_);
    auto grid = receiver_.grid();
    EXPECT_TRUE(grid) << grid.error().message;
    return grid ? std::move(*grid) : ogf::navigation::NavGrid{};
  }
  bool consistentAt(std::int64_t seq) const {
    std::lock_guard lk(mu_);
    return !receiver_.needsKeyframe() && receiver_.appliedSeq() == seq && receiver_.consistent();
  }

 private:
  void onGrid(const lcm::ReceiveBuffer*, const std::string&, const ogf::nav_grid_t* m) {
    std::lock_guard lk(mu_);
    receiver_.accept(*m);
  }
  mutable std::mutex mu_;
  ogf::navigation::NavReceiver receiver_;
  ogf::testing::LcmThread bus_;
};

void askForGridKeyframe(lcm::LCM& lcm) {
  ogf::map_request_t req{};
  req.requester = "nav-grid-test";
  req.last_seq = -1;
  lcm.publish("OGF_NAV_REQUEST", &req);
}

// Feeds scans [from, to) of the room, waiting whenever the mapper has 3 or more in hand; then waits until
// every one is accounted for and returns that status.
std::optional<ogf::mapper_status_t> feedRoom(lcm::LCM& lcm, Mapper& mapper, int from, int to, int points,
                                             std::chrono::milliseconds pace) {
  for (int i = from; i < to; ++i) {
    const auto step = ogf::testing::feedStep(i, points);
    for (const auto& p : step.poses) lcm.publish("POSE", &p);
    lcm.publish("VELODYNE_SCAN", &step.scan);
    std::this_thread::sleep_for(pace);
    for (int w = 0; w < 200; ++w) {
      const auto s = mapper.latestStatus();
      if (!s || s->scans_in - s->scans_mapped - s->scans_dropped_behind - s->scans_dropped_no_pose < 3) break;
      std::this_thread::sleep_for(5ms);
    }
  }
  const std::int64_t n = to - from;
  return mapper.waitForStatus(
      [&](const ogf::mapper_status_t& s) {
        return s.scans_in == n && s.scans_mapped + s.scans_dropped_behind + s.scans_dropped_no_pose == n;
      },
      60s);
}

class NavGridTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    dir_ = ogf::testing::emptyTestDirectory("ogf-nav-grid-it");
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

TEST_F(NavGridTest, ClientFollowsTheLiveGridToTheMappersChecksumThroughDroppedUpdatesAndTheGridIsTheRooms) {
  // Updates every 0.2 s, a fifth of them dropped; no periodic keyframe: every gap is mended by a keyframe
  // the client asks for.
  std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.1\nnav:\n  update_interval_s: 0.2\n"
                                         "  keyframe_interval_s: 1000\n";
  const std::string url = ogf::testing::loopbackUdpmUrl(47);
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir_ / "mapper.yaml").string(), "--in-memory",
                 "--test-drop-nav", "0.2", "--keyframe-interval", "1000", "--log-level", "warn"},
                (dir_ / "mapper.log").string(), url, kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(10s));
  GridListener listener(url);
  ChildProcess client({kBin + "/ogf-map-client", "--lcm-url", url, "--nav", "--idle-exit", "3", "--duration", "300",
                       "--log-level", "warn"},
                      (dir_ / "client.log").string());
  std::this_thread::sleep_for(300ms);

  lcm::LCM lcm(url);
  const auto done = feedRoom(lcm, mapper, 0, 400, 1500, 30ms);
  ASSERT_TRUE(done) << mapper.log();
  // A last update dropped is invisible until something follows it: ask for a keyframe, as a client that
  // just started would (and for the 3-D map, whose last delta may be older than the client's last request).
  askForGridKeyframe(lcm);
  const auto settled = mapper.waitForStatus(
      [&](const ogf::mapper_status_t& s) { return s.nav_seq == done->nav_seq && s.nav_requests_in > 0; }, 10s);
  ASSERT_TRUE(settled) << mapper.log();
  EXPECT_GT(settled->nav_seq, 10) << "the grid changed in few updates: the gap injection is not exercised";
  EXPECT_GT(settled->nav_bytes_sent, 0);

  const auto rc = client.wait(120s);
  ASSERT_TRUE(rc.has_value()) << client.log();
  EXPECT_EQ(*rc, 0) << client.log();
  const std::string log = client.log();
  const std::string nav = lineStarting(log, "nav_map_id ");
  const std::string deltas = lineStarting(log, "map_id ");
  SCOPED_TRACE(nav);
  SCOPED_TRACE(deltas);
  const auto last = mapper.latestStatus();
  ASSERT_TRUE(last);
  EXPECT_EQ(outputField(nav, "nav_consistent"), "yes");
  EXPECT_EQ(std::stoll(outputField(nav, "nav_seq")), last->nav_seq);
  EXPECT_EQ(outputField(nav, " nav_checksum"), hex(last->nav_checksum)) << "the client's grid is not the mapper's";
  EXPECT_EQ(outputField(nav, " nav_checksum"), outputField(nav, "mapper_nav_checksum"));
  EXPECT_EQ(std::stoll(outputField(nav, "nav_known_columns")), last->nav_known_columns);
  EXPECT_GT(std::stoll(outputField(nav, "nav_gaps")), 0) << "the injection should have made gaps";
  EXPECT_GE(std::stoll(outputField(nav, "nav_keyframes")), 2) << "one at the start, one per gap";
  EXPECT_EQ(outputField(nav, "nav_malformed"), "0");
  // The 3-D deltas, followed beside the grid.
  EXPECT_EQ(outputField(deltas, "consistent"), "yes");
  EXPECT_EQ(outputField(deltas, " published_checksum"), outputField(deltas, "mapper_published_checksum"));

  // The grid is the room's.
  ASSERT_TRUE(listener.consistentAt(last->nav_seq));
  const auto grid = listener.grid();
  std::int64_t occupied = 0, free = 0, outside = 0, occupied_near_wall = 0, free_inside = 0;
  for (std::int32_t row = 0; row < grid.height; ++row)
    for (std::int32_t col = 0; col < grid.width; ++col) {
      const auto cls = grid.column_class[grid.index(col, row)];
      if (cls == ogf::navigation::kClassUnknown) continue;
      const double x = (grid.origin.x + col + 0.5) * kRes, y = (grid.origin.y + row + 0.5) * kRes;
      // Distance inside the room to the nearest wall (negative outside).
      const double to_wall = std::min(5.0 - std::abs(x), 4.0 - std::abs(y));
      outside += to_wall < -0.5 ? 1 : 0;
      if (cls == ogf::navigation::kClassOccupied) {
        ++occupied;
        occupied_near_wall += std::abs(to_wall) <= 0.5 ? 1 : 0;
      } else {
        ++free;
        free_inside += to_wall > 0.5 ? 1 : 0;
      }
    }
  std::printf("[ figures  ] nav grid of the room: %lld occupied columns (%lld within 0.5 m of a wall), %lld free "
              "(%lld more than 0.5 m inside), %lld beyond the walls; %lld updates, %lld bytes sent\n",
              static_cast<long long>(occupied), static_cast<long long>(occupied_near_wall), static_cast<long long>(free),
              static_cast<long long>(free_inside), static_cast<long long>(outside),
              static_cast<long long>(last->nav_seq), static_cast<long long>(last->nav_bytes_sent));
  EXPECT_EQ(static_cast<std::int64_t>(grid.knownColumns()), last->nav_known_columns);
  EXPECT_GT(occupied, 0);
  EXPECT_GT(free, 0);
  EXPECT_EQ(outside, 0) << "a column known more than 0.5 m beyond the walls";
  // The walls are 36 m of perimeter, 180 columns at 0.2 m; the room's floor is 80 m², 2000 columns.
  EXPECT_GE(occupied_near_wall, 150);
  EXPECT_GE(static_cast<double>(occupied_near_wall), 0.9 * static_cast<double>(occupied));
  EXPECT_GE(free_inside, 1000);
  EXPECT_TRUE(mapper.stop());
}

// The mapper restarted on its state directory: the same known columns from the first status on, a new
// stream (seq 0), and a client following only the grid gets them by keyframe.
void gridSurvivesARestart(const fs::path& dir, int channel, bool paging) {
  std::ofstream(dir / "mapper.yaml") << "status_interval_s: 0.1\nstate_dir: " << (dir / "state").string() << "\n"
                                     << (paging ? "page_out_distance_m: 1.0\n" : "");
  const std::string url = ogf::testing::loopbackUdpmUrl(channel);
  const std::vector<std::string> args{kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir / "mapper.yaml").string(),
                                      "--log-level", "warn"};
  lcm::LCM lcm(url);
  std::int64_t known = 0;
  {
    Mapper mapper(args, (dir / "mapper-1.log").string(), url, kMapperStatusChannel);
    ASSERT_TRUE(mapper.reportsStatus(10s));
    const auto done = feedRoom(lcm, mapper, 0, 60, 1000, 20ms);
    ASSERT_TRUE(done) << mapper.log();
    std::this_thread::sleep_for(300ms);  // a status after the last scan's grid update
    known = mapper.latestStatus()->nav_known_columns;
    EXPECT_GT(known, 500);
    EXPECT_TRUE(mapper.stop());
  }
  Mapper mapper(args, (dir / "mapper-2.log").string(), url, kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(10s));
  const auto first = mapper.latestStatus();
  ASSERT_TRUE(first);
  EXPECT_EQ(first->nav_known_columns, known) << mapper.log();
  EXPECT_EQ(first->nav_seq, 0);
  ChildProcess client({kBin + "/ogf-map-client", "--lcm-url", url, "--nav-only", "--idle-exit", "2", "--duration",
                       "60", "--log-level", "warn"},
                      (dir / "client.log").string());
  const auto rc = client.wait(60s);
  ASSERT_TRUE(rc.has_value()) << client.log();
  const std::string log = client.log();
  EXPECT_EQ(lineStarting(log, "map_id "), "") << "--nav-only follows no 3-D deltas";
  const std::string nav = lineStarting(log, "nav_map_id ");
  SCOPED_TRACE(nav);
  EXPECT_EQ(outputField(nav, "nav_consistent"), "yes");
  EXPECT_EQ(std::stoll(outputField(nav, "nav_known_columns")), known);
  EXPECT_EQ(outputField(nav, "nav_seq"), "0");
  EXPECT_TRUE(mapper.stop());
}

TEST_F(NavGridTest, TheGridAfterARestartFromTheStateDirectoryHasTheSameColumns) {
  gridSurvivesARestart(dir_, 48, false);
}

TEST_F(NavGridTest, TheGridAfterARestartHasTheColumnsOfRegionsPagedOut) { gridSurvivesARestart(dir_, 49, true); }

TEST_F(NavGridTest, KeyframeRequestsAreCountedMalformedOnesRejectedAndAFloodGetsAtMostOneKeyframeASecond) {
  std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.1\nnav:\n  keyframe_interval_s: 1000\n";
  const std::string url = ogf::testing::loopbackUdpmUrl(50);
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir_ / "mapper.yaml").string(), "--in-memory",
                 "--log-level", "warn"},
                (dir_ / "mapper.log").string(), url, kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(10s));
  lcm::LCM lcm(url);
  const std::uint8_t junk[] = {1, 2, 3, 4, 5};
  for (int i = 0; i < 7; ++i) lcm.publish("OGF_NAV_REQUEST", junk, sizeof junk);
  // 2 s of requests every 5 ms: about 400 requests.
  const auto began = std::chrono::steady_clock::now();
  int sent = 0;
  while (std::chrono::steady_clock::now() - began < 2s) {
    askForGridKeyframe(lcm);
    ++sent;
    std::this_thread::sleep_for(5ms);
  }
  const double flood_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  const auto s = mapper.waitForStatus(
      [&](const ogf::mapper_status_t& m) { return m.nav_requests_in == sent + 7 && m.nav_requests_rejected == 7; }, 10s);
  const auto last = mapper.latestStatus();
  ASSERT_TRUE(s) << "nav_requests_in " << (last ? last->nav_requests_in : -1) << " (sent " << sent + 7
                 << "), nav_requests_rejected " << (last ? last->nav_requests_rejected : -1) << "\n"
                 << mapper.log();
  // One keyframe at the first request, then at most one a second while the flood lasts (one more for a
  // request delivered late).
  EXPECT_GE(s->nav_keyframes_sent, 1);
  EXPECT_LE(s->nav_keyframes_sent, static_cast<std::int64_t>(flood_s) + 2) << sent << " requests in " << flood_s << " s";
  EXPECT_TRUE(mapper.running());
  EXPECT_TRUE(mapper.stop());
}

}  // namespace
