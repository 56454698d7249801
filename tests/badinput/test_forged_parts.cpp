// Parts of updates and keyframes that never complete, as anyone on the bus can send them: full-sized
// OGF_MAP_DELTA parts (3 300 cells, 66 kB each) and OGF_NAV_GRID parts (24 tiles) of keyframes claiming
// thousands of parts. What a receiver holds waiting is bounded by bytes (delta/update_sequence.hpp): the
// receivers on their own (the bound, the oldest dropped first, the real keyframe applied after the flood, a
// keyframe as large as the map held still taken), then ogf-map-client, ogf-map-client --nav-only and ogf-view
// as real processes on udpm, whose peak resident set must stay under 100 MB where 6 000 parts would hold about
// 400 MB.
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <ogf/map_delta_t.hpp>
#include <ogf/nav_grid_t.hpp>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "ogf/delta/map_receiver.hpp"
#include "ogf/navigation/nav_receiver.hpp"
#include "support/child_process.hpp"
#include "support/multicast.hpp"
#include "support/output_field.hpp"
#include "support/process_memory.hpp"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using ogf::delta::MapReceiver;
using ogf::navigation::NavReceiver;

const std::string kBin = OGF_BIN_DIR;
constexpr std::int32_t kCellsPerPart = 3300;  // what the mapper puts in one OGF_MAP_DELTA part
constexpr std::int32_t kTilesPerPart = 24;    // and in one OGF_NAV_GRID part

// Part `index` of a keyframe `seq` of map 7 that claims `part_count` parts, each with its own cells.
ogf::map_delta_t mapPart(std::int64_t seq, std::int32_t index, std::int32_t part_count, std::int32_t cells) {
  ogf::map_delta_t m{};
  m.map_id = 7;
  m.seq = seq;
  m.base_seq = -1;
  m.kind = ogf::map_delta_t::KIND_KEYFRAME;
  m.part_index = index;
  m.part_count = part_count;
  m.resolution = 0.1;
  m.num_cells = cells;
  for (std::int32_t i = 0; i < cells; ++i) {
    m.key_x.push_back(i);
    m.key_y.push_back(index);
    m.key_z.push_back(static_cast<std::int32_t>(seq % 1000));
    m.probability.push_back(9000);
    m.cell_class.push_back(ogf::map_delta_t::CLASS_OCCUPIED);
    m.variance.push_back(0.01f);
  }
  return m;
}

// An update `seq` (on top of seq - 1) of map 7 in `part_count` parts, of which this is `index`.
ogf::map_delta_t mapUpdatePart(std::int64_t seq, std::int32_t index, std::int32_t part_count) {
  auto m = mapPart(seq, index, part_count, kCellsPerPart);
  m.kind = ogf::map_delta_t::KIND_DELTA;
  m.base_seq = seq - 1;
  return m;
}

ogf::nav_grid_t navPart(std::int64_t seq, std::int32_t index, std::int32_t part_count) {
  ogf::nav_grid_t m{};
  m.map_id = 7;
  m.seq = seq;
  m.base_seq = -1;
  m.kind = ogf::nav_grid_t::KIND_KEYFRAME;
  m.part_index = index;
  m.part_count = part_count;
  m.resolution = 0.1;
  m.floor_z = 0.0;
  m.min_height = 0.1;
  m.max_height = 1.8;
  m.tile_size = ogf::navigation::kTileSize;
  m.num_tiles = kTilesPerPart;
  for (std::int32_t t = 0; t < kTilesPerPart; ++t) {
    m.tile_x.push_back(t);
    m.tile_y.push_back(index);
  }
  m.num_columns = static_cast<std::int32_t>(kTilesPerPart * ogf::navigation::kTileColumns);
  m.cost.assign(static_cast<std::size_t>(m.num_columns), 0);
  m.column_class.assign(static_cast<std::size_t>(m.num_columns), ogf::nav_grid_t::CLASS_FREE);
  return m;
}

TEST(ForgedParts, AMapReceiverHoldsNoMoreThanItsBoundAndTheRealKeyframeAfterTheFloodApplies) {
  MapReceiver receiver;
  std::size_t peak = 0;
  for (std::int32_t i = 0; i < 6000; ++i) {
    const auto outcome = receiver.accept(mapPart(1000 + i / 1500, i % 1500, 1 << 16, kCellsPerPart));
    EXPECT_TRUE(outcome == MapReceiver::Outcome::kPartial || outcome == MapReceiver::Outcome::kDropped)
        << ogf::delta::toString(outcome);
    ASSERT_LE(receiver.heldBytes(), receiver.heldBytesLimit()) << "after part " << i;
    peak = std::max(peak, receiver.heldBytes());
  }
  EXPECT_EQ(receiver.heldBytesLimit(), MapReceiver::kDefaultMinHeldBytes);
  EXPECT_GT(peak, MapReceiver::kDefaultMinHeldBytes * 9 / 10) << "the flood fills the bound";
  EXPECT_GT(receiver.dropped(), 0u);
  EXPECT_EQ(receiver.malformed(), 0u);

  // The mapper's keyframe, in two parts, arrives while the flood goes on between them: it is newer than the
  // forged keyframes, which go first.
  EXPECT_EQ(receiver.accept(mapPart(5000, 0, 2, kCellsPerPart)), MapReceiver::Outcome::kPartial);
  for (std::int32_t i = 0; i < 100; ++i) receiver.accept(mapPart(1004, i, 1 << 16, kCellsPerPart));
  EXPECT_EQ(receiver.accept(mapPart(5000, 1, 2, kCellsPerPart)), MapReceiver::Outcome::kKeyframeApplied);
  EXPECT_EQ(receiver.appliedSeq(), 5000);
  EXPECT_EQ(receiver.map().size(), 2u * kCellsPerPart);
}

TEST(ForgedParts, AKeyframeLargerThanTheFloorIsDroppedByAnEmptyReceiverAndTakenBesideAMapAsLarge) {
  constexpr std::int32_t kParts = 40;  // 132 000 cells, 2.6 MB held
  MapReceiver small(MapReceiver::kDefaultBufferedUpdates, 1 << 20);
  MapReceiver::Outcome last{};
  for (std::int32_t i = 0; i < kParts; ++i) last = small.accept(mapPart(10, i, kParts, kCellsPerPart));
  EXPECT_NE(last, MapReceiver::Outcome::kKeyframeApplied);
  EXPECT_GT(small.dropped(), 0u);
  EXPECT_TRUE(small.needsKeyframe());

  // With the floor raised the same keyframe applies.
  MapReceiver large(MapReceiver::kDefaultBufferedUpdates, 8 << 20);
  for (std::int32_t i = 0; i < kParts; ++i) last = large.accept(mapPart(10, i, kParts, kCellsPerPart));
  EXPECT_EQ(last, MapReceiver::Outcome::kKeyframeApplied);
  EXPECT_EQ(large.map().size(), static_cast<std::size_t>(kParts) * kCellsPerPart);

  // With the 1 MB floor, a client that built a map of 2.6 MB from updates takes a keyframe of 2 MB: the map
  // held counts.
  MapReceiver grown(MapReceiver::kDefaultBufferedUpdates, 1 << 20);
  ASSERT_EQ(grown.accept(mapPart(1, 0, 1, 1)), MapReceiver::Outcome::kKeyframeApplied);
  for (std::int64_t seq = 2; seq < 2 + kParts; ++seq)
    ASSERT_EQ(grown.accept(mapUpdatePart(seq, 0, 1)), MapReceiver::Outcome::kApplied);
  ASSERT_GT(grown.appliedBytes(), std::size_t{2} << 20);
  for (std::int32_t i = 0; i < 30; ++i) last = grown.accept(mapPart(100, i, 30, kCellsPerPart));
  EXPECT_EQ(last, MapReceiver::Outcome::kKeyframeApplied);
  EXPECT_EQ(grown.dropped(), 0u);
  EXPECT_EQ(grown.map().size(), 30u * kCellsPerPart);
}

TEST(ForgedParts, UpdatesOverTheBoundAreDroppedOldestFirstAndTheReceiverThenAsksForAKeyframe) {
  MapReceiver receiver(MapReceiver::kDefaultBufferedUpdates, 1 << 20);
  ASSERT_EQ(receiver.accept(mapPart(1, 0, 1, 1)), MapReceiver::Outcome::kKeyframeApplied);
  ASSERT_FALSE(receiver.needsKeyframe());
  // Update 2 in 8 parts of which 7 come, held waiting; then later updates' parts until the bound drops it.
  for (std::int32_t i = 0; i < 7; ++i) receiver.accept(mapUpdatePart(2, i, 8));
  std::int64_t seq = 3;
  while (receiver.dropped() == 0 && seq < 200) receiver.accept(mapUpdatePart(seq++, 0, 2));
  EXPECT_GT(receiver.dropped(), 0u);
  EXPECT_LE(receiver.heldBytes(), receiver.heldBytesLimit());
  // The last part of update 2 now starts a new assembly of one part of eight: it cannot complete, and
  // update 3 completes after it, so the receiver declares the gap.
  receiver.accept(mapUpdatePart(2, 7, 8));
  receiver.accept(mapUpdatePart(3, 1, 2));
  EXPECT_TRUE(receiver.needsKeyframe());
  EXPECT_EQ(receiver.appliedSeq(), 1);
}

TEST(ForgedParts, ANavReceiverHoldsNoMoreThanItsBoundAndTheRealKeyframeAfterTheFloodApplies) {
  NavReceiver receiver;
  for (std::int32_t i = 0; i < 3000; ++i) {
    receiver.accept(navPart(100 + i / 1000, i % 1000, 1 << 14));
    ASSERT_LE(receiver.heldBytes(), receiver.heldBytesLimit()) << "after part " << i;
  }
  EXPECT_GT(receiver.dropped(), 0u);
  EXPECT_EQ(receiver.malformed(), 0u);
  EXPECT_EQ(receiver.accept(navPart(900, 0, 1)), NavReceiver::Outcome::kKeyframeApplied);
  EXPECT_EQ(receiver.knownColumns(), kTilesPerPart * ogf::navigation::kTileColumns);
}

TEST(ForgedParts, ADenseGridIsRefusedBeyondTheLimitAskedNamingIt) {
  NavReceiver receiver;
  auto far = navPart(1, 0, 1);
  far.tile_x[kTilesPerPart - 1] = 20000;  // 20 000 tiles of 32 columns east: 640 032 columns by 32
  ASSERT_EQ(receiver.accept(far), NavReceiver::Outcome::kKeyframeApplied);
  const auto refused = receiver.grid(std::int64_t{1} << 24);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("limit of 16777216"), std::string::npos) << refused.error().message;
  const auto dense = receiver.grid();
  ASSERT_TRUE(dense) << dense.error().message;
  EXPECT_EQ(dense->width, 20001 * ogf::navigation::kTileSize);
}

// A real client process fed forged parts on udpm: its peak resident set and its own count of what it dropped.
class ForgedPartsAtAClient : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
    dir_ = fs::temp_directory_path() / ("ogf-forged-parts-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  struct Flooded {
    std::int64_t peak_mib = 0;
    std::string log;
  };

  // Starts `argv` (with --lcm-url on bus `slot`), waits for its first keyframe request on `request_channel`
  // (it is then subscribed), publishes `count` messages made by `make(i)` on `channel`, paced so the kernel's
  // buffers keep up (a drop would make the flood smaller and the test weaker, not stronger), and stops it.
  template <class Make>
  Flooded flood(int slot, std::vector<std::string> argv, const std::string& request_channel,
                const std::string& channel, int count, Make make) {
    const std::string url = ogf::testing::loopbackUdpmUrl(slot);
    lcm::LCM lcm(url);
    EXPECT_TRUE(lcm.good());
    bool asked = false;
    lcm.subscribeFunction(
        request_channel, +[](const lcm::ReceiveBuffer*, const std::string&, bool* flag) { *flag = true; }, &asked);
    argv.insert(argv.begin() + 1, {"--lcm-url", url});
    ogf::testing::ChildProcess program(argv, (dir_ / "program.log").string());
    for (auto until = std::chrono::steady_clock::now() + 30s; !asked && std::chrono::steady_clock::now() < until;)
      lcm.handleTimeout(100);
    EXPECT_TRUE(asked) << "no keyframe request on " << request_channel << "\n" << program.log();
    for (int i = 0; i < count; ++i) {
      const auto m = make(i);
      lcm.publish(channel, &m);
      if (i % 4 == 3) std::this_thread::sleep_for(2ms);
    }
    std::this_thread::sleep_for(500ms);
    Flooded out;
    out.peak_mib = ogf::testing::peakResidentKiB(program.pid()).value_or(1 << 30) / 1024;
    std::printf("peak resident set %lld MiB\n", static_cast<long long>(out.peak_mib));
    program.signal(SIGTERM);
    EXPECT_TRUE(program.wait(10s).has_value()) << program.log();
    out.log = program.log();
    return out;
  }

  fs::path dir_;
};

ogf::map_delta_t forgedMapPart(int i) { return mapPart(1000 + i / 1500, i % 1500, 1 << 16, kCellsPerPart); }

TEST_F(ForgedPartsAtAClient, MapClientFedSixThousandForgedKeyframePartsStaysUnder100MB) {
  const auto run = flood(280, {kBin + "/ogf-map-client", "--duration", "60"}, "OGF_MAP_REQUEST", "OGF_MAP_DELTA",
                         6000, forgedMapPart);
  EXPECT_LT(run.peak_mib, 100) << "peak resident MiB\n" << run.log;
  const auto summary = run.log.substr(std::min(run.log.size(), run.log.rfind("map_id ")));
  EXPECT_GT(std::atoll(ogf::testing::outputField(summary, "dropped").c_str()), 0) << run.log;
  EXPECT_NE(run.log.find("--max-held-mb"), std::string::npos) << "the warning names the flag\n" << run.log;
}

TEST_F(ForgedPartsAtAClient, NavOnlyClientFedThreeThousandForgedGridPartsStaysUnder100MB) {
  const auto run = flood(281, {kBin + "/ogf-map-client", "--nav-only", "--duration", "60"}, "OGF_NAV_REQUEST",
                         "OGF_NAV_GRID", 3000, [](int i) { return navPart(100 + i / 1000, i % 1000, 1 << 14); });
  EXPECT_LT(run.peak_mib, 100) << "peak resident MiB\n" << run.log;
  const auto summary = run.log.substr(std::min(run.log.size(), run.log.rfind("nav_map_id ")));
  EXPECT_GT(std::atoll(ogf::testing::outputField(summary, "nav_dropped").c_str()), 0) << run.log;
}

TEST_F(ForgedPartsAtAClient, ViewFedSixThousandForgedKeyframePartsStaysUnder100MB) {
  const auto run = flood(282, {kBin + "/ogf-view", "--port", "0"}, "OGF_MAP_REQUEST", "OGF_MAP_DELTA", 6000,
                         forgedMapPart);
  EXPECT_LT(run.peak_mib, 100) << "peak resident MiB\n" << run.log;
  EXPECT_NE(run.log.find("dropped the oldest update or keyframe"), std::string::npos) << run.log;
}

}  // namespace
