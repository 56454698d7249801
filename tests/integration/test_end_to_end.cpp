// The main job's pipeline as real processes on real LCM (udpm on loopback), on a short simulated world:
// ogf-sim writes a capture, odometry and ground truth; ogf-replay sends the capture over UDP to ogf-driver
// and publishes the odometry on LCM on the same clock; ogf-mapper maps; ogf-map-client follows the deltas.
// Checked at 1x and 4x replay speed:
//   - the mapper received every scan the driver published (VELODYNE_STATUS scans_published equals
//     OGF_MAPPER_STATUS scans_in) and dropped none (behind, no pose, late, rejected) and lost no packet;
//   - the client's rebuilt map has the daemon's checksum;
//   - ogf-eval scores the daemon's final snapshot above an accuracy threshold measured on this world.
// Also measured and printed, never asserted: end-to-end latency from a scan's last packet (the driver's
// receive time of it, lidar_scan_t.host_utime_end) to the arrival of the last part of that scan's delta on
// OGF_MAP_DELTA (LCM's receive time at this listener), matched by the scan's utime; p50 and p99.
// OGF_E2E_SECONDS (default 3) sets the world's duration (longer runs give steadier latency figures).
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/driver_status_t.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/map_delta_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <sstream>
#include <thread>

#include "support/file_text.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/lcm_thread.hpp"
#include "support/multicast.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using Driver = ogf::testing::DaemonProcess<ogf::driver_status_t>;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;

const std::string kBin = OGF_BIN_DIR;

// Measured on this 2-core machine (shared, load average ~10) with the default 3 s lab world (loop
// trajectory, 0.2 m cells, max range 30 m): ogf-eval accuracy of the daemon's final snapshot 0.6164 at 1x
// and 0.6164 at 4x (eq. 13 over all 35740 known truth cells, unknown counted wrong: 3 s of driving does not
// see the whole room, so about 31 % of the known cells stay unknown). The threshold leaves room for a
// machine that times scans differently, not for a broken pipeline (an empty map scores 0, a map in the
// wrong frame far less).
constexpr double kAccuracyThreshold = 0.55;

double worldSeconds() {
  const char* s = std::getenv("OGF_E2E_SECONDS");
  return s != nullptr ? std::atof(s) : 3.0;
}

// The scans and the map deltas on the bus, for the latency from a scan to its delta, on its own thread.
class BusProbe {
 public:
  explicit BusProbe(const std::string& url) : bus_(url) {
    bus_.lcm().subscribe("VELODYNE_SCAN", &BusProbe::onScan, this)->setQueueCapacity(10000);
    bus_.lcm().subscribe("OGF_MAP_DELTA", &BusProbe::onDelta, this)->setQueueCapacity(10000);
    bus_.start(std::chrono::milliseconds(50));
  }
  bool good() { return bus_.lcm().good(); }
  // Latencies (µs) of the scans seen on both channels.
  std::vector<std::int64_t> latencies() const {
    std::lock_guard lk(mu_);
    std::vector<std::int64_t> out;
    for (const auto& [utime, arrived] : delta_arrival_) {
      const auto it = scan_end_.find(utime);
      if (it != scan_end_.end()) out.push_back(arrived - it->second);
    }
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  void onScan(const lcm::ReceiveBuffer*, const std::string&, const ogf::lidar_scan_t* s) {
    std::lock_guard lk(mu_);
    scan_end_[s->utime] = s->host_utime_end;
  }
  void onDelta(const lcm::ReceiveBuffer* rb, const std::string&, const ogf::map_delta_t* d) {
    if (d->kind != ogf::map_delta_t::KIND_DELTA || d->part_index != d->part_count - 1) return;
    std::lock_guard lk(mu_);
    delta_arrival_.emplace(d->utime, rb->recv_utime);
  }

  mutable std::mutex mu_;
  std::map<std::int64_t, std::int64_t> scan_end_;       // scan utime -> host_utime_end
  std::map<std::int64_t, std::int64_t> delta_arrival_;  // delta utime (= its scan's utime) -> recv_utime
  ogf::testing::LcmThread bus_;  // last: its thread stops before the state above is gone
};

std::string lastLine(const std::string& text) {
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

std::string field(const std::string& text, const std::string& key) {
  std::smatch m;
  if (std::regex_search(text, m, std::regex(key + " +(\\S+)"))) return m[1];
  return {};
}

// The exit status of a program run to its end (-1000 when it did not end within `limit`).
int runToEnd(const std::vector<std::string>& argv, const fs::path& log, std::chrono::seconds limit) {
  return ogf::testing::runAndCapture(argv, log.string(), limit).rc;
}

class EndToEnd : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (ensureLoopbackMulticast()) return;
    root_ = fs::temp_directory_path() / ("ogf-e2e-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    // The simulated sensor's GPS time is now, as a live sensor's is: the driver's device clock (top-of-hour
    // counter + host hour until the first NMEA sentence) then agrees with the NMEA time from the start.
    const auto now_us = std::chrono::duration_cast<std::chrono::microseconds>(
                            std::chrono::system_clock::now().time_since_epoch()).count();
    sim_rc_ = runToEnd({kBin + "/ogf-sim", "--world", "lab", "--duration", std::to_string(worldSeconds()), "--out",
                        (root_ / "sim").string(), "--start-utime", std::to_string(now_us), "--log-level", "warn"},
                       root_ / "sim.log", 120s);
    // The mapper must know where the sensor sits on the body (sim.yaml's sensor_to_body).
    const std::string sim_yaml = ogf::testing::fileText(root_ / "sim" / "sim.yaml");
    std::smatch m;
    if (std::regex_search(sim_yaml, m, std::regex(R"(sensor_to_body: \{xyz: (\[[^\]]*\]), quaternion_wxyz: (\[[^\]]*\])\})")))
      // A queue deep enough for the 3 s world's 4x burst: with the default 10 scans, the mapper on this
      // loaded 2-core machine (about 15 scans/s here while the map grows) dropped 4 of 31 scans as "behind"
      // at 4x; the scans are then mapped late, never lost, which is what this test checks. (A 20 s world
      // at 4x outruns even this queue here: 16 of 201 dropped. At 1x none is, on either world.)
      std::ofstream(root_ / "mapper.yaml") << "status_interval_s: 0.1\nmap:\n  extrinsic: {translation: " << m[1]
                                           << ", quaternion: " << m[2] << "}\n"
                                           << "fusion:\n  max_pending_scans: 64\n  max_pending_points: 2000000\n";
  }
  static void TearDownTestSuite() {
    if (!root_.empty() && std::getenv("OGF_E2E_KEEP") == nullptr) fs::remove_all(root_);
  }
  static std::optional<std::string> ensureLoopbackMulticast() { return ogf::testing::ensureLoopbackMulticast(); }

  void SetUp() override {
    if (auto why = ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    ASSERT_EQ(sim_rc_, 0) << ogf::testing::fileText(root_ / "sim.log");
    ASSERT_TRUE(fs::exists(root_ / "mapper.yaml")) << "no sensor_to_body in sim.yaml";
  }

  struct Run {
    ogf::driver_status_t driver{};
    ogf::mapper_status_t mapper{};
    std::string client_line;
    std::string eval_table;
    std::vector<std::int64_t> latencies;
  };

  // The whole pipeline at `speed`; failures are reported through gtest assertions by the caller.
  void runPipeline(double speed, int slot, Run& run) {
    const std::string url = ogf::testing::loopbackUdpmUrl(slot);
    const fs::path dir = root_ / ("speed-" + std::to_string(static_cast<int>(speed)));
    fs::create_directories(dir);
    const std::string data_port = std::to_string(20000 + (::getpid() % 20000) + slot);
    const std::string position_port = std::to_string(40000 + (::getpid() % 20000) + slot);
    BusProbe probe(url);
    ASSERT_TRUE(probe.good());
    Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--state-dir", (dir / "state").string(), "--config",
                   (root_ / "mapper.yaml").string(), "--log-level", "warn"},
                  (dir / "mapper.log").string(), url, ogf::testing::kMapperStatusChannel);
    Driver driver({kBin + "/ogf-driver", "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port", data_port,
                   "--position-port", position_port, "--log-level", "warn"},
                  (dir / "driver.log").string(), url, ogf::testing::kDriverStatusChannel);
    ASSERT_TRUE(driver.started());
    ASSERT_TRUE(mapper.reportsStatus(15s));
    // Runs until stopped: a scan that changes no published cell publishes no delta, so silence on the delta
    // channel does not mean the mapper is done; its status says that.
    ChildProcess client({kBin + "/ogf-map-client", "--lcm-url", url, "--duration", "300", "--log-level", "warn"},
                        (dir / "client.log").string());
    const int replay_rc =
        runToEnd({kBin + "/ogf-replay", "--pcap", (root_ / "sim" / "capture.pcap").string(), "--dest", "127.0.0.1",
                  "--data-port", data_port, "--position-port", position_port, "--speed", std::to_string(speed),
                  "--odometry", (root_ / "sim" / "odometry.csv").string(), "--lcm-url", url, "--start-delay", "1"},
                 dir / "replay.log", 120s);
    ASSERT_EQ(replay_rc, 0) << ogf::testing::fileText(dir / "replay.log");
    std::this_thread::sleep_for(300ms);
    // SIGTERM: the driver publishes the scan in progress and a last status.
    ASSERT_TRUE(driver.stop());
    std::this_thread::sleep_for(300ms);
    const auto ds = driver.latestStatus();
    ASSERT_TRUE(ds.has_value());
    run.driver = *ds;
    const auto done = mapper.waitForStatus(
        [&](const ogf::mapper_status_t& s) {
          return s.scans_in >= run.driver.scans_published &&
                 s.scans_mapped + s.scans_dropped_behind + s.scans_dropped_no_pose + s.scans_late + s.scans_rejected >=
                     s.scans_in;
        },
        30s);
    const auto last = mapper.latestStatus();
    ASSERT_TRUE(last.has_value());
    run.mapper = done ? *done : *last;
    std::this_thread::sleep_for(500ms);  // the last delta's way to the client
    client.signal(SIGTERM);
    const auto client_rc = client.wait(30s);
    ASSERT_TRUE(client_rc.has_value()) << client.log();
    run.client_line = lastLine(client.log());
    ASSERT_TRUE(mapper.stop(30s));
    run.latencies = probe.latencies();
    const int eval_rc = runToEnd({kBin + "/ogf-eval", "--map", (dir / "state" / "snapshot.ogfs").string(), "--truth",
                                  (root_ / "sim").string(), "--no-octomap", "--log-level", "warn"},
                                 dir / "eval.log", 120s);
    run.eval_table = ogf::testing::fileText(dir / "eval.log");
    ASSERT_EQ(eval_rc, 0) << run.eval_table;
  }

  static void checkRun(const Run& run, double speed) {
    SCOPED_TRACE("replay speed " + std::to_string(speed));
    const auto& d = run.driver;
    const auto& m = run.mapper;
    EXPECT_GT(d.scans_published, 5);
    EXPECT_EQ(d.packets_lost, 0);
    EXPECT_EQ(d.bad_size + d.bad_block_flag + d.foreign_sender + d.bad_other, 0);
    EXPECT_EQ(d.publish_errors, 0);
    EXPECT_EQ(m.scans_in, d.scans_published) << "the mapper must receive every scan the driver published";
    EXPECT_EQ(m.scans_dropped_behind, 0);
    EXPECT_EQ(m.scans_dropped_no_pose, 0);
    EXPECT_EQ(m.scans_late, 0);
    EXPECT_EQ(m.scans_rejected, 0);
    EXPECT_EQ(m.scans_mapped, m.scans_in);
    EXPECT_EQ(m.poses_rejected, 0);
    SCOPED_TRACE(run.client_line);
    EXPECT_EQ(field(run.client_line, "consistent"), "yes");
    EXPECT_FALSE(field(run.client_line, " published_checksum").empty());
    EXPECT_EQ(field(run.client_line, " published_checksum"), field(run.client_line, "mapper_published_checksum"));
    EXPECT_EQ(field(run.client_line, " seq"), std::to_string(m.delta_seq));
    const std::string acc = field(run.eval_table, R"(accuracy \(eq\. 13, unknown = wrong\))");
    ASSERT_FALSE(acc.empty()) << run.eval_table;
    EXPECT_GT(std::stod(acc), kAccuracyThreshold) << run.eval_table;
    // The figures (measured, not asserted).
    const auto& l = run.latencies;
    if (!l.empty()) {
      const auto pct = [&](double q) { return static_cast<double>(l[static_cast<std::size_t>(q * static_cast<double>(l.size() - 1))]) / 1000.0; };
      std::printf("[ figures  ] speed %.0fx: scans %lld, accuracy %s, latency last packet -> delta: n %zu p50 %.1f ms "
                  "p99 %.1f ms max %.1f ms\n",
                  speed, static_cast<long long>(m.scans_in), acc.c_str(), l.size(), pct(0.5), pct(0.99), pct(1.0));
    }
  }

  static inline fs::path root_;
  static inline int sim_rc_ = -1;
};

TEST_F(EndToEnd, AtOneTimesEveryScanIsMappedNoneDroppedAndTheClientHasTheDaemonsMap) {
  Run run;
  runPipeline(1.0, 41, run);
  if (HasFatalFailure()) return;
  checkRun(run, 1.0);
}

TEST_F(EndToEnd, AtFourTimesEveryScanIsMappedNoneDroppedAndTheClientHasTheDaemonsMap) {
  Run run;
  runPipeline(4.0, 42, run);
  if (HasFatalFailure()) return;
  checkRun(run, 4.0);
}

}  // namespace
