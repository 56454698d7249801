// Faults on the daemons as real processes on real LCM (udpm on loopback):
// - ogf-mapper killed (SIGKILL) at random instants, OGF_MAPPER_KILLS times (default 20; one in four while
//   it starts and restores, the others while or after it maps a few scans): after every kill
//   the snapshot loads with the strict loaders (container CRC, then the map file's checksums and fields)
//   and the journal's header reads; the restarted daemon resumes with exactly the map an uninterrupted run
//   has at the update it restored (same filter checksum) and never behind the last update it acknowledged.
// - ogf-driver killed at random instants, OGF_DRIVER_KILLS times (default 20), while ogf-replay keeps the
//   VLP-16 stream coming: each restart publishes again, and its first scan is cut at the first crossing of
//   the cut angle it sees (it spans at most one revolution of sensor time), so no more than one scan is lost.
// - A full state directory (a small tmpfs, filled) and a read-only one (a bind mount remounted ro): a logged
//   error, mapping goes on in memory (the same checksum as offline), OGF_MAPPER_STATUS says
//   persistence_ok = false with the reason, and once space or write access returns the next snapshot saves
//   the whole map again, which a kill -9 and restart then shows. Skipped with the reason when mounts
//   cannot be made (not root, no mount namespace).
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/driver_status_t.hpp>
#include <ogf/filter/map_file.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <thread>

#include "integration/scan_feeder.hpp"
#include "support/message_counter.hpp"
#include "offline_reference.hpp"
#include "ogf/persistence/journal.hpp"
#include "ogf/persistence/state_directory.hpp"
#include "programs.hpp"
#include "scratch_mount.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using ogf::testing::MessageCounter;
using ogf::testing::OfflineReference;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;
using Driver = ogf::testing::DaemonProcess<ogf::driver_status_t>;
using ogf::testing::ScratchMount;
using ogf::testing::binDir;

constexpr int kPoints = 800;

int envCount(const char* name, int fallback) {
  const char* s = std::getenv(name);
  return s != nullptr ? std::atoi(s) : fallback;
}

// The state directory as the strict loaders see it: "" when the snapshot (if any) decodes, container and
// map file both, and the journal's header reads; else what is wrong.
std::string strictLoadProblems(const fs::path& state) {
  std::string problems;
  const fs::path snap = state / "snapshot.ogfs";
  if (fs::exists(snap)) {
    std::ifstream in(snap, std::ios::binary);
    const std::vector<char> raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto decoded = ogf::persistence::decodeSnapshot(
        std::span(reinterpret_cast<const std::byte*>(raw.data()), raw.size()), snap.string());
    if (!decoded) {
      problems += decoded.error().message + "\n";
    } else if (auto map = ogf::filter::decodeMap(decoded->map_bytes, snap.string()); !map) {
      problems += map.error().message + "\n";
    }
  }
  if (fs::exists(state / "journal.ogfj")) {
    if (auto j = ogf::persistence::readJournal(state / "journal.ogfj"); !j) problems += j.error().message + "\n";
  }
  return problems;
}

class FaultTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    dir_ = ogf::testing::emptyTestDirectory("ogf-faults");
    // A deep queue: a burst of scans waits for the mapper instead of being dropped, so update k is scan k-1.
    std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.1\nfusion:\n  max_pending_scans: 64\n";
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }

  std::unique_ptr<Mapper> startMapper(const std::string& url, const fs::path& state, const std::string& log) {
    return std::make_unique<Mapper>(
        std::vector<std::string>{binDir() + "/ogf-mapper", "--lcm-url", url, "--state-dir", state.string(), "--config",
                                 (dir_ / "mapper.yaml").string(), "--snapshot-interval", "0.3", "--log-level", "info"},
        (dir_ / log).string(), url, ogf::testing::kMapperStatusChannel);
  }

  // Publishes scans [from, to) with their odometry (and the poses of scan from-1, which a restarted mapper
  // needs to place scan `from`'s first points), `gap` apart.
  static void feed(lcm::LCM& lcm, int from, int to, std::chrono::milliseconds gap) {
    if (from > 0)
      for (const auto& p : ogf::testing::feedStep(from - 1, kPoints).poses) lcm.publish("POSE", &p);
    for (int i = from; i < to; ++i) {
      const auto step = ogf::testing::feedStep(i, kPoints);
      for (const auto& p : step.poses) lcm.publish("POSE", &p);
      lcm.publish("VELODYNE_SCAN", &step.scan);
      std::this_thread::sleep_for(gap);
    }
  }

  fs::path dir_;
};

TEST_F(FaultTest, MapperKilledAtRandomInstantsResumesEveryAcknowledgedUpdateAndItsFilesStayLoadable) {
  const int kills = envCount("OGF_MAPPER_KILLS", 20);
  const std::string url = ogf::testing::loopbackUdpmUrl(71);
  lcm::LCM lcm(url);
  OfflineReference reference(kPoints);
  ASSERT_TRUE(reference.ok());
  std::mt19937 rng(20261121);
  std::int64_t acknowledged = 0;
  int survived = 0, killed_starting = 0;
  for (int round = 0; round <= kills; ++round) {
    auto mapper = startMapper(url, dir_ / "state", "mapper-" + std::to_string(round) + ".log");
    if (round < kills && std::uniform_int_distribution<int>(0, 3)(rng) == 0) {
      // One round in four: killed while starting (restoring, cutting a torn journal tail, opening).
      std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 150)(rng)));
      ASSERT_TRUE(mapper->kill());
      ++survived;
      ++killed_starting;
      ASSERT_EQ(strictLoadProblems(dir_ / "state"), "") << "after kill " << survived << " (while starting)";
      continue;
    }
    const auto first = mapper->waitForStatus([](const auto&) { return true; }, 15s);
    ASSERT_TRUE(first) << mapper->log();
    const std::int64_t restored = first->delta_seq;
    SCOPED_TRACE("round " + std::to_string(round) + " restored seq " + std::to_string(restored) + " acknowledged " +
                 std::to_string(acknowledged));
    ASSERT_GE(restored, acknowledged) << "an acknowledged update was lost\n" << mapper->log();
    ASSERT_EQ(static_cast<std::uint64_t>(first->filter_checksum), reference.at(static_cast<int>(restored)))
        << "the restarted map differs from an uninterrupted run at the same update\n" << mapper->log();
    EXPECT_TRUE(first->persistence_ok) << first->persistence_error;
    if (round == kills) {
      // The last round stops cleanly: a final snapshot, and the next start is at the same update.
      feed(lcm, static_cast<int>(restored), static_cast<int>(restored) + 5, 15ms);
      const auto s = mapper->waitForStatus([&](const auto& m) { return m.delta_seq == restored + 5; }, 30s);
      ASSERT_TRUE(s) << mapper->log();
      ASSERT_TRUE(mapper->stop(30s));
      EXPECT_EQ(strictLoadProblems(dir_ / "state"), "");
      break;
    }
    // Every scan so far was mapped (the queue is deep), so update k is scan k-1: go on from scan `restored`.
    feed(lcm, static_cast<int>(restored), static_cast<int>(restored) + std::uniform_int_distribution<int>(3, 20)(rng),
         15ms);
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 400)(rng)));
    if (const auto s = mapper->latestStatus()) acknowledged = s->delta_seq;
    ASSERT_TRUE(mapper->kill());
    ++survived;
    const std::string problems = strictLoadProblems(dir_ / "state");
    ASSERT_EQ(problems, "") << "after kill " << survived;
  }
  std::printf("[ figures  ] mapper kill -9: %d kills survived (%d while starting), last acknowledged seq %lld, "
              "nothing lost\n",
              survived, killed_starting, static_cast<long long>(acknowledged));
}

TEST_F(FaultTest, DriverKilledAtRandomInstantsPublishesAgainWithinOneScan) {
  const int kills = envCount("OGF_DRIVER_KILLS", 20);
  const std::string url = ogf::testing::loopbackUdpmUrl(72);
  const int slot = 72;
  const std::string data_port = std::to_string(20000 + (::getpid() % 20000) + slot);
  const std::string position_port = std::to_string(40000 + (::getpid() % 20000) + slot);
  ASSERT_EQ(ogf::testing::simulateCapture(dir_ / "sim", 2.0), std::nullopt);
  // The sensor: the capture over and over at the VLP-16 rate, while the driver dies and comes back.
  ChildProcess sensor({binDir() + "/ogf-replay", "--pcap", (dir_ / "sim" / "capture.pcap").string(), "--dest",
                       "127.0.0.1", "--data-port", data_port, "--position-port", position_port, "--loop", "100000",
                       "--log-level", "warn"},
                      (dir_ / "replay.log").string());
  ASSERT_TRUE(sensor.started());
  std::mutex mu;
  std::vector<ogf::lidar_scan_t> heard;  // scans since the last restart (points dropped to save memory)
  MessageCounter<ogf::lidar_scan_t> scans(url, "VELODYNE_SCAN", [&](const ogf::lidar_scan_t& s) {
    ogf::lidar_scan_t head = s;
    head.x.clear();
    head.y.clear();
    head.z.clear();
    std::lock_guard lk(mu);
    heard.push_back(std::move(head));
  });
  const auto scansHeard = [&] {
    std::lock_guard lk(mu);
    return heard;
  };
  std::mt19937 rng(20261122);
  // 600 rpm: one revolution is 100 ms of sensor time; a scan cut at the first crossing spans at most that,
  // plus one packet (1.33 ms) in which the crossing falls.
  constexpr std::int64_t kRevolutionUs = 100'000 + 1'400;
  int survived = 0;
  std::int64_t worst_first_span_us = 0;
  for (int round = 0; round <= kills; ++round) {
    {
      std::lock_guard lk(mu);
      heard.clear();
    }
    Driver driver({binDir() + "/ogf-driver", "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port",
                   data_port, "--position-port", position_port, "--no-packets", "--log-level", "warn"},
                  (dir_ / ("driver-" + std::to_string(round) + ".log")).string(), url,
                  ogf::testing::kDriverStatusChannel);
    ASSERT_TRUE(driver.started());
    SCOPED_TRACE("round " + std::to_string(round));
    // Publishing again: two scans, the first one (partial, from wherever the stream was) and a whole one.
    const auto deadline = std::chrono::steady_clock::now() + 15s;
    while (scansHeard().size() < 2 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(10ms);
    const auto got = scansHeard();
    ASSERT_GE(got.size(), 2u) << "the restarted driver did not publish\n" << driver.log();
    const auto span = got[0].device_utime_end - got[0].device_utime_start;
    worst_first_span_us = std::max(worst_first_span_us, span);
    EXPECT_LE(span, kRevolutionUs) << "the first scan after a restart must end at the first cut it crosses";
    EXPECT_EQ(got[0].seq + 1, got[1].seq);
    if (round == kills) {
      EXPECT_TRUE(driver.stop());
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 300)(rng)));
    ASSERT_TRUE(driver.kill());
    ++survived;
  }
  sensor.signal(SIGTERM);
  sensor.wait(10s);
  std::printf("[ figures  ] driver kill -9: %d kills survived; first scan after a restart spans at most %.1f ms of "
              "sensor time (one revolution = 100 ms)\n",
              survived, static_cast<double>(worst_first_span_us) / 1000.0);
}

// What the persistence fault tests share: a mapper on a state directory that breaks and heals, fed scans
// paced to what it maps, checked against the offline map.
class PersistenceFaultTest : public FaultTest {
 protected:
  // Feeds scans [from, to) and waits until all are mapped; the status then.
  static std::optional<ogf::mapper_status_t> feedAndWait(const Mapper& mapper, lcm::LCM& lcm, int from, int to) {
    feed(lcm, from, to, 20ms);
    return mapper.waitForStatus([&](const auto& s) { return s.delta_seq == to; }, 30s);
  }
  static std::optional<ogf::mapper_status_t> waitPersistence(const Mapper& mapper, bool ok) {
    return mapper.waitForStatus([&](const auto& s) { return s.persistence_ok == ok; }, 20s);
  }
  // Kills the mapper (kill -9: only what is on disk counts), checks its files load, restarts it and checks it
  // restored exactly the map after `updates` updates.
  void killRestartAndCheck(std::unique_ptr<Mapper>& mapper, const std::string& url, const std::string& log,
                           int updates) {
    ASSERT_TRUE(mapper->kill());
    EXPECT_EQ(strictLoadProblems(dir_ / "state"), "");
    mapper = startMapper(url, dir_ / "state", log);
    const auto s = mapper->waitForStatus([](const auto&) { return true; }, 15s);
    ASSERT_TRUE(s) << mapper->log();
    EXPECT_EQ(s->delta_seq, updates) << "the saved map and what was mapped while it could not be saved";
    EXPECT_EQ(static_cast<std::uint64_t>(s->filter_checksum), reference_.at(updates));
    EXPECT_TRUE(s->persistence_ok) << s->persistence_error;
    EXPECT_TRUE(mapper->stop(30s));
  }
  OfflineReference reference_{kPoints};
};

TEST_F(PersistenceFaultTest, FullDiskKeepsMappingInMemorySaysSoAndSavesAgainWhenSpaceReturns) {
  // 8 MiB holds this map's snapshot (~1 MiB) and journal; it is filled before the scans come.
  auto disk = ScratchMount::tmpfs(dir_ / "state", "8m");
  if (disk.unavailable()) GTEST_SKIP() << "cannot make a small file system: " << *disk.unavailable();
  const std::string url = ogf::testing::loopbackUdpmUrl(73);
  lcm::LCM lcm(url);
  auto mapper = startMapper(url, dir_ / "state", "mapper-full.log");
  ASSERT_TRUE(waitPersistence(*mapper, true)) << mapper->log();
  ASSERT_TRUE(feedAndWait(*mapper, lcm, 0, 5)) << mapper->log();

  const auto filled = ogf::testing::fillFileSystem(dir_ / "state" / "filler");
  ASSERT_GT(filled, 0u);
  auto s = feedAndWait(*mapper, lcm, 5, 15);
  ASSERT_TRUE(s) << "mapping must go on when the disk is full\n" << mapper->log();
  EXPECT_EQ(static_cast<std::uint64_t>(s->filter_checksum), reference_.at(15)) << "the map in memory is complete";
  s = waitPersistence(*mapper, false);
  ASSERT_TRUE(s) << mapper->log();
  EXPECT_NE(s->persistence_error.find("No space left on device"), std::string::npos) << s->persistence_error;
  EXPECT_NE(mapper->log().find("persistence: "), std::string::npos) << "a clear logged error";
  std::printf("[ figures  ] full disk: status persistence_ok=false \"%s\"\n", s->persistence_error.c_str());

  fs::remove(dir_ / "state" / "filler");
  s = waitPersistence(*mapper, true);
  ASSERT_TRUE(s) << "the next snapshot after space returns saves the map\n" << mapper->log();
  EXPECT_EQ(s->persistence_error, "");
  // Saved indeed: killed and restarted, it has the whole map (scans 0..14).
  killRestartAndCheck(mapper, url, "mapper-full-after.log", 15);
}

TEST_F(PersistenceFaultTest, ReadOnlyStateDirectoryKeepsTheSavedMapMapsOnInMemoryAndSavesWhenWritable) {
  fs::create_directories(dir_ / "backing");
  auto mount = ScratchMount::bind(dir_ / "backing", dir_ / "state");
  if (mount.unavailable()) GTEST_SKIP() << "cannot make a bind mount: " << *mount.unavailable();
  const std::string url = ogf::testing::loopbackUdpmUrl(74);
  lcm::LCM lcm(url);
  {  // A saved map: scans 0..9, stopped cleanly.
    auto mapper = startMapper(url, dir_ / "state", "mapper-rw.log");
    ASSERT_TRUE(waitPersistence(*mapper, true)) << mapper->log();
    ASSERT_TRUE(feedAndWait(*mapper, lcm, 0, 10)) << mapper->log();
    ASSERT_TRUE(mapper->stop(30s));
  }
  ASSERT_EQ(mount.setReadOnly(true), std::nullopt);
  auto mapper = startMapper(url, dir_ / "state", "mapper-ro.log");
  auto s = mapper->waitForStatus([](const auto&) { return true; }, 15s);
  ASSERT_TRUE(s) << mapper->log();
  EXPECT_FALSE(s->persistence_ok);
  EXPECT_NE(s->persistence_error.find("Read-only file system"), std::string::npos) << s->persistence_error;
  EXPECT_EQ(s->delta_seq, 10) << "the saved map is still read and used";
  EXPECT_NE(mapper->log().find("persistence: "), std::string::npos) << "a clear logged error";
  std::printf("[ figures  ] read-only: status persistence_ok=false \"%s\"\n", s->persistence_error.c_str());
  s = feedAndWait(*mapper, lcm, 10, 20);
  ASSERT_TRUE(s) << "mapping must go on in memory\n" << mapper->log();
  EXPECT_FALSE(s->persistence_ok);
  EXPECT_EQ(static_cast<std::uint64_t>(s->filter_checksum), reference_.at(20));

  ASSERT_EQ(mount.setReadOnly(false), std::nullopt);
  s = waitPersistence(*mapper, true);
  ASSERT_TRUE(s) << "writable again: the next snapshot saves the map\n" << mapper->log();
  killRestartAndCheck(mapper, url, "mapper-ro-after.log", 20);
}

}  // namespace
