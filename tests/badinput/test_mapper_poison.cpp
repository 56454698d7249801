// Single poisoned messages and damaged state at ogf-mapper as a real process on udpm over loopback, with
// ogf-map-client following its deltas: one pose or one scan dated in the year 2100, an odometry jump of
// 1 km and of 10 km, a pose at x = 1e300, 16 bytes flipped in the middle of the journal, the snapshot cut
// to half. After each, a valid drive goes on: every one of its scans is mapped, the map is exactly the
// valid scans mapped offline through the same pipeline, the refusal is counted on its own counter in
// OGF_MAPPER_STATUS, and the client ends with the daemon's checksum. A snapshot that cannot be read is
// left where it is, not set aside as damaged.
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/odometry_t.hpp>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "offline_checksum.hpp"
#include "ogf/persistence/journal.hpp"
#include "ogf/persistence/state_directory.hpp"
#include "scan_feeder.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/file_text.hpp"
#include "support/multicast.hpp"
#include "support/output_field.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using ogf::testing::outputField;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;
using ogf::testing::FeedStep;
using ogf::testing::feedStep;

const std::string kBin = OGF_BIN_DIR;
constexpr int kPoints = 400;
constexpr std::int64_t kYear2100 = 4'102'444'800'000'000LL;  // 2100-01-01, microseconds

std::vector<FeedStep> drive(int from, int to) {
  std::vector<FeedStep> out;
  for (int i = from; i < to; ++i) out.push_back(feedStep(i, kPoints));
  return out;
}

class MapperPoison : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    dir_ = ogf::testing::emptyTestDirectory("ogf-poison");
    std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.1\nsnapshot_interval_s: 1000\nstate_dir: "
                                        << (dir_ / "state").string() << "\n";
    url_ = ogf::testing::loopbackUdpmUrl(61);
    lcm_.emplace(url_);
  }
  void TearDown() override {
    mapper_.reset();
    client_.reset();
    fs::remove_all(dir_);
  }

  // (Re)starts the mapper on the state directory and waits for its first status.
  void startMapper() {
    mapper_.reset();
    mapper_.emplace(std::vector<std::string>{kBin + "/ogf-mapper", "--lcm-url", url_, "--config",
                                             (dir_ / "mapper.yaml").string(), "--log-level", "warn"},
                    (dir_ / "mapper.log").string(), url_, ogf::testing::kMapperStatusChannel);
    ASSERT_TRUE(mapper_->reportsStatus(15s));
  }
  void startClient() {
    client_.emplace(std::vector<std::string>{kBin + "/ogf-map-client", "--lcm-url", url_, "--idle-exit", "3",
                                             "--duration", "120", "--log-level", "warn"},
                    (dir_ / "client.log").string());
    std::this_thread::sleep_for(300ms);
  }
  void publish(const std::vector<FeedStep>& steps) {
    for (const auto& step : steps) {
      for (const auto& p : step.poses) lcm_->publish("POSE", &p);
      lcm_->publish("VELODYNE_SCAN", &step.scan);
      std::this_thread::sleep_for(20ms);
    }
  }
  // The drive from step `from` on, after a restart: the odometry the new process needs before scan `from`
  // (the previous step's poses, heard by the process before it) comes first.
  void resume(const std::vector<FeedStep>& steps, int from) {
    for (const auto& p : feedStep(from - 1, kPoints).poses) lcm_->publish("POSE", &p);
    publish(steps);
  }
  ogf::mapper_status_t waitMapped(std::int64_t delta_seq) {
    const auto s = mapper_->waitForStatus([&](const ogf::mapper_status_t& m) { return m.delta_seq == delta_seq; }, 30s);
    EXPECT_TRUE(s) << "never reached update " << delta_seq << "\n" << mapper_->log();
    std::this_thread::sleep_for(300ms);  // a status after the last update, with every counter in it
    return mapper_->latestStatus().value_or(ogf::mapper_status_t{});
  }
  // Asks for a keyframe, as a client that just started would, and checks the client ends with the map.
  void expectClientConsistent(const ogf::mapper_status_t& last) {
    ogf::map_request_t req{};
    req.requester = "poison-test";
    req.last_seq = -1;
    lcm_->publish("OGF_MAP_REQUEST", &req);
    const auto rc = client_->wait(60s);
    ASSERT_TRUE(rc.has_value()) << client_->log();
    EXPECT_EQ(*rc, 0) << client_->log();
    const std::string log = client_->log();
    const std::string line = log.substr(log.rfind("consistent") == std::string::npos ? 0 : log.rfind('\n', log.rfind("consistent")) + 1);
    SCOPED_TRACE(line);
    EXPECT_EQ(outputField(line, "consistent"), "yes");
    EXPECT_EQ(std::stoll(outputField(line, "seq")), last.delta_seq);
    EXPECT_FALSE(outputField(line, " published_checksum").empty());
    EXPECT_EQ(outputField(line, " published_checksum"), outputField(line, "mapper_published_checksum"));
  }
  // Five scans of the drive, `poison`, five more: every scan is mapped, the map is that of the ten alone,
  // and the client ends consistent. Returns the last status, for the test's own counter.
  template <class Poison>
  ogf::mapper_status_t driveAround(Poison poison) {
    startMapper();
    startClient();
    publish(drive(0, 5));
    waitMapped(5);
    poison();
    publish(drive(5, 10));
    const auto s = waitMapped(10);
    EXPECT_EQ(s.scans_mapped, 10);
    EXPECT_EQ(s.scans_dropped_no_pose, 0);
    EXPECT_EQ(s.scans_dropped_pose_jump, 0);
    EXPECT_EQ(static_cast<std::uint64_t>(s.filter_checksum), ogf::testing::offlineChecksum(10, kPoints));
    expectClientConsistent(s);
    stopMapper();
    return s;
  }
  // Five scans with regions paged out 1 m beyond the robot (after every scan), then a clean stop: the final
  // snapshot names pages.
  void mapFiveScansPagingAfterEach() {
    std::ofstream(dir_ / "mapper.yaml", std::ios::app) << "page_out_distance_m: 1.0\n";
    startMapper();
    publish(drive(0, 5));
    waitMapped(5);
    stopMapper();
  }
  void stopMapper() {
    EXPECT_TRUE(mapper_->stop());
  }
  // (Re)starts the mapper on a saved map it cannot restore: it starts a new map in memory and says so.
  void startMapperOnAMapItCannotRestore() {
    startMapper();
    const auto s = mapper_->latestStatus();
    ASSERT_TRUE(s);
    EXPECT_EQ(s->delta_seq, 0) << "a new map";
    EXPECT_FALSE(s->persistence_ok);
    EXPECT_NE(s->persistence_error.find("cannot be restored"), std::string::npos) << s->persistence_error;
  }

  fs::path dir_;
  std::string url_;
  std::optional<lcm::LCM> lcm_;
  std::optional<Mapper> mapper_;
  std::optional<ChildProcess> client_;
};

TEST_F(MapperPoison, OnePoseDatedInTheYear2100IsRefusedAndTheDriveGoesOn) {
  const auto s = driveAround([&] {
    ogf::odometry_t bad = feedStep(4, kPoints).poses.back();
    bad.utime = kYear2100;
    lcm_->publish("POSE", &bad);
  });
  EXPECT_EQ(s.poses_refused_time, 1);
  EXPECT_EQ(s.poses_rejected, 0);
}

TEST_F(MapperPoison, OneScanDatedInTheYear2100IsRefusedAndTheDriveGoesOn) {
  const auto s = driveAround([&] {
    ogf::lidar_scan_t bad = feedStep(5, kPoints).scan;
    const std::int64_t shift = kYear2100 - bad.utime;
    for (std::int64_t* t : {&bad.utime, &bad.device_utime_start, &bad.device_utime_end, &bad.host_utime_start,
                            &bad.host_utime_end})
      *t += shift;
    lcm_->publish("VELODYNE_SCAN", &bad);
  });
  EXPECT_EQ(s.scans_refused_time, 1);
  EXPECT_EQ(s.scans_late, 0);
}

TEST_F(MapperPoison, AnOdometryJumpOf1kmOr10kmSplitsTheTrajectoryAndOnlyTheScanSpanningItIsDropped) {
  for (const double jump_m : {1000.0, 10000.0}) {
    SCOPED_TRACE(jump_m);
    fs::remove_all(dir_ / "state");
    startMapper();
    startClient();
    auto steps = drive(0, 10);
    // From the middle of scan 5 on, the odometry reports the robot jump_m further along x.
    const std::int64_t at = steps[5].scan.device_utime_start + 50'000;
    for (int i = 5; i < 10; ++i)
      for (auto& p : steps[static_cast<std::size_t>(i)].poses)
        if (p.utime >= at) p.position[0] += jump_m;
    publish(steps);
    const auto s = waitMapped(9);
    EXPECT_EQ(s.scans_mapped, 9);
    EXPECT_EQ(s.pose_jumps, 1);
    EXPECT_EQ(s.scans_dropped_pose_jump, 1);
    EXPECT_EQ(s.poses_rejected, 0);
    int broken = 0;
    EXPECT_EQ(static_cast<std::uint64_t>(s.filter_checksum), ogf::testing::offlineChecksumOf(steps, {}, &broken));
    EXPECT_EQ(broken, 1);
    std::printf("[ figures  ] a %.0f m jump: %lld cells, %lld bytes after 9 scans\n", jump_m,
                static_cast<long long>(s.cells), static_cast<long long>(s.memory_bytes));
    expectClientConsistent(s);
    stopMapper();
  }
}

TEST_F(MapperPoison, APoseAtX1e300IsRefusedAndTheDriveGoesOn) {
  const auto s = driveAround([&] {
    ogf::odometry_t bad = feedStep(4, kPoints).poses.back();
    bad.utime += 5'000;
    bad.position[0] = 1e300;
    lcm_->publish("POSE", &bad);
  });
  EXPECT_EQ(s.poses_rejected, 1);
  EXPECT_EQ(s.pose_jumps, 0);
}

TEST_F(MapperPoison, SixteenBytesFlippedInTheMiddleOfTheJournalLoseOnlyThatRecord) {
  startMapper();
  publish(drive(0, 10));
  waitMapped(10);
  ASSERT_TRUE(mapper_->kill());  // the journal holds all ten records (no snapshot yet)
  const fs::path journal = dir_ / "state" / "journal.ogfj";
  const auto clean = ogf::persistence::readJournal(journal);
  ASSERT_TRUE(clean.ok()) << clean.error().message;
  ASSERT_EQ(clean->records.size(), 10u);
  // The record holding the middle of the file, and 16 bytes inside it.
  ASSERT_GE(clean->records.size(), 3u);
  std::size_t hit = 0;
  while (hit + 2 < clean->records.size() && clean->records[hit + 1].offset <= fs::file_size(journal) / 2) ++hit;
  const std::uint64_t start = clean->records[hit].offset;
  ASSERT_GT(clean->records[hit + 1].offset, start + 46) << "16 bytes inside the record";
  {
    std::fstream f(journal, std::ios::in | std::ios::out | std::ios::binary);
    for (std::uint64_t at = start + 30; at < start + 46; ++at) {
      f.seekg(static_cast<std::streamoff>(at));
      const char c = static_cast<char>(f.get());
      f.seekp(static_cast<std::streamoff>(at));
      f.put(static_cast<char>(~c));
    }
  }
  startMapper();
  const auto restored = mapper_->waitForStatus([](const ogf::mapper_status_t& m) { return m.delta_seq == 10; }, 15s);
  ASSERT_TRUE(restored) << mapper_->log();
  EXPECT_FALSE(restored->persistence_ok);
  EXPECT_NE(restored->persistence_error.find("journal.ogfj: offset " + std::to_string(start)), std::string::npos)
      << restored->persistence_error;
  const auto steps = drive(0, 15);
  const std::set<int> lost{static_cast<int>(hit)};
  EXPECT_EQ(static_cast<std::uint64_t>(restored->filter_checksum),
            ogf::testing::offlineChecksumOf({steps.begin(), steps.begin() + 10}, lost))
      << "the map is every record but the damaged one";
  bool kept = false;
  for (const auto& e : fs::directory_iterator(dir_ / "state"))
    kept = kept || (e.path().filename().string().rfind("damaged-", 0) == 0 && fs::exists(e.path() / "journal.ogfj"));
  EXPECT_TRUE(kept) << "the damaged journal is kept in damaged-<time>/";
  startClient();
  resume({steps.begin() + 10, steps.end()}, 10);
  const auto s = waitMapped(15);
  EXPECT_EQ(s.scans_mapped, 5);
  EXPECT_EQ(static_cast<std::uint64_t>(s.filter_checksum), ogf::testing::offlineChecksumOf(steps, lost));
  expectClientConsistent(s);
  stopMapper();
}

TEST_F(MapperPoison, ASnapshotCutToHalfFallsBackToThePreviousOneAndTheJournals) {
  startMapper();
  publish(drive(0, 5));
  waitMapped(5);
  stopMapper();  // snapshot at update 5
  startMapper();
  resume(drive(5, 10), 5);
  waitMapped(10);
  stopMapper();  // snapshot at update 10; the one at 5 and the journal after it are the previous generation
  const fs::path snapshot = dir_ / "state" / "snapshot.ogfs";
  fs::resize_file(snapshot, fs::file_size(snapshot) / 2);
  startMapper();
  const auto restored = mapper_->waitForStatus([](const ogf::mapper_status_t& m) { return m.delta_seq == 10; }, 15s);
  ASSERT_TRUE(restored) << mapper_->log();
  EXPECT_FALSE(restored->persistence_ok);
  EXPECT_NE(restored->persistence_error.find("snapshot.ogfs"), std::string::npos) << restored->persistence_error;
  EXPECT_EQ(static_cast<std::uint64_t>(restored->filter_checksum), ogf::testing::offlineChecksum(10, kPoints));
  startClient();
  resume(drive(10, 15), 10);
  const auto s = waitMapped(15);
  EXPECT_EQ(static_cast<std::uint64_t>(s.filter_checksum), ogf::testing::offlineChecksum(15, kPoints));
  expectClientConsistent(s);
  stopMapper();
}

// The page files the state directory's snapshot names (to poison).
std::vector<fs::path> namedPages(const fs::path& state) {
  auto snap = ogf::persistence::StateDirectory::read(state, 1);
  std::vector<fs::path> out;
  if (snap) {
    for (const auto& name : snap->pages) out.push_back(state / "pages" / name);
  }
  return out;
}

TEST_F(MapperPoison, ADamagedPageLosesOnlyItsRegionSaysWhichAndMappingGoesOn) {
  mapFiveScansPagingAfterEach();
  const auto pages = namedPages(dir_ / "state");
  ASSERT_FALSE(pages.empty()) << "the snapshot must name pages";
  {
    std::fstream f(pages.front(), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(64);
    f.put(static_cast<char>(0xA5));
  }
  startMapper();
  const auto restored = mapper_->waitForStatus([](const ogf::mapper_status_t& m) { return m.delta_seq == 5; }, 15s);
  ASSERT_TRUE(restored) << mapper_->log();
  EXPECT_FALSE(restored->persistence_ok);
  EXPECT_NE(restored->persistence_error.find(pages.front().filename().string()), std::string::npos)
      << restored->persistence_error;
  EXPECT_NE(static_cast<std::uint64_t>(restored->filter_checksum), ogf::testing::offlineChecksum(5, kPoints))
      << "the damaged page's region is lost";
  resume(drive(5, 8), 5);
  const auto s = waitMapped(8);
  EXPECT_EQ(s.scans_mapped, 3) << "mapping goes on";
  stopMapper();
}

TEST_F(MapperPoison, PagesThatCannotBeListedStartANewMapAndLeaveTheSavedOneAlone) {
  mapFiveScansPagingAfterEach();
  ASSERT_FALSE(namedPages(dir_ / "state").empty());
  fs::rename(dir_ / "state" / "pages", dir_ / "pages-kept");
  std::ofstream(dir_ / "state" / "pages") << "not a directory";
  const auto before = fs::file_size(dir_ / "state" / "snapshot.ogfs");
  startMapperOnAMapItCannotRestore();
  stopMapper();
  EXPECT_EQ(fs::file_size(dir_ / "state" / "snapshot.ogfs"), before) << "the saved map is never written over";
  EXPECT_NE(mapper_->log().find("pages"), std::string::npos) << mapper_->log();
}

// A snapshot made with another stencil does not fit the configuration: the mapper starts a new map in memory,
// names both stencils, and never writes over the saved map.
TEST_F(MapperPoison, ASnapshotOfAnotherStencilStartsANewMapAndLeavesTheSavedOneAlone) {
  startMapper();
  publish(drive(0, 5));
  waitMapped(5);
  stopMapper();
  const std::string before = ogf::testing::fileText(dir_ / "state" / "snapshot.ogfs");
  ASSERT_FALSE(before.empty());
  std::ofstream(dir_ / "mapper.yaml", std::ios::app) << "filter:\n  stencil_manhattan_radius: 0\n";
  startMapperOnAMapItCannotRestore();
  resume(drive(5, 7), 5);
  EXPECT_EQ(waitMapped(2).scans_mapped, 2) << "mapping goes on";
  stopMapper();
  EXPECT_EQ(ogf::testing::fileText(dir_ / "state" / "snapshot.ogfs"), before)
      << "the saved map is never written over";
  EXPECT_NE(mapper_->log().find("stencil Manhattan radius 2"), std::string::npos) << mapper_->log();
}

// A snapshot that cannot be read (a directory in its place: EISDIR, which root meets too) is not damage:
// the mapper starts a new map in memory and says why in its status, but neither sets the state directory
// aside nor writes over it; once the snapshot can be read again, the next start restores the map.
TEST_F(MapperPoison, ASnapshotThatCannotBeReadIsLeftInPlaceAndRestoredOnceReadable) {
  startMapper();
  publish(drive(0, 5));
  waitMapped(5);
  stopMapper();  // snapshot at update 5
  const fs::path state = dir_ / "state";
  fs::rename(state / "snapshot.ogfs", dir_ / "snapshot.kept");
  fs::create_directory(state / "snapshot.ogfs");
  std::error_code ec;
  const auto journal = fs::file_size(state / "journal.ogfj", ec);
  ASSERT_FALSE(ec) << ec.message();
  startMapper();
  const auto s = mapper_->latestStatus();
  ASSERT_TRUE(s);
  EXPECT_EQ(s->delta_seq, 0) << "a new map in memory";
  EXPECT_FALSE(s->persistence_ok);
  EXPECT_NE(s->persistence_error.find("snapshot.ogfs"), std::string::npos) << s->persistence_error;
  EXPECT_NE(s->persistence_error.find(std::strerror(EISDIR)), std::string::npos) << s->persistence_error;
  stopMapper();
  for (const auto& e : fs::directory_iterator(state))
    EXPECT_NE(e.path().filename().string().rfind("damaged-", 0), 0U) << e.path() << ": an unreadable snapshot is not damage";
  EXPECT_TRUE(fs::is_directory(state / "snapshot.ogfs"));
  EXPECT_EQ(fs::file_size(state / "journal.ogfj", ec), journal) << "the saved map is never written over";
  fs::remove(state / "snapshot.ogfs");
  fs::rename(dir_ / "snapshot.kept", state / "snapshot.ogfs");
  startMapper();
  const auto restored = mapper_->waitForStatus([](const ogf::mapper_status_t& m) { return m.delta_seq == 5; }, 15s);
  ASSERT_TRUE(restored) << mapper_->log();
  EXPECT_EQ(static_cast<std::uint64_t>(restored->filter_checksum), ogf::testing::offlineChecksum(5, kPoints));
  stopMapper();
}

}  // namespace
