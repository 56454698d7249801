// The byte budget of a delta channel: an update carries at most its allowance, the cells beyond it wait
// (one entry per cell, its latest state) and go out in later updates, class changes first; a client that
// applies every message stays consistent with the checksum on each and ends with the mapper's map.
// LinkBudget: the token bucket the allowance comes from.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <vector>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/delta/link_budget.hpp"
#include "ogf/delta/map_receiver.hpp"

namespace {

using namespace ogf::delta;

std::int8_t budgetClassOf(double p) {
  return p > 0.65 ? ogf::map_delta_t::CLASS_OCCUPIED : (p < 0.35 ? ogf::map_delta_t::CLASS_FREE : ogf::map_delta_t::CLASS_UNKNOWN);
}

PublishedCell cellAt(int x, int y, double p) { return {{x, y, 0}, quantiseProbability(p), budgetClassOf(p), 0.5f}; }

std::vector<PublishedCell> cellsIn(const std::vector<ogf::map_delta_t>& msgs) {
  std::vector<PublishedCell> out;
  for (const auto& m : msgs)
    for (std::size_t i = 0; i < static_cast<std::size_t>(m.num_cells); ++i)
      out.push_back({{m.key_x[i], m.key_y[i], m.key_z[i]}, m.probability[i], m.cell_class[i], m.variance[i]});
  return out;
}

TEST(DeltaBudget, UpdateCarriesNoMoreBytesThanItsAllowanceAndTheRestWaits) {
  DeltaStream s({0.2, 1, 50}, PublishingRule{0.02, 0.0});
  const std::int64_t allowance = DeltaStream::partBytes(50) + DeltaStream::partBytes(20);
  s.allow(allowance);
  std::vector<PublishedCell> cells;
  for (int x = 0; x < 300; ++x) cells.push_back(cellAt(x, 0, 0.9));
  const auto msgs = s.update(1, cells);
  EXPECT_EQ(cellsIn(msgs).size(), 70u);
  EXPECT_LE(DeltaStream::bytesOf(msgs), allowance);
  EXPECT_EQ(s.lastUpdate().bytes, DeltaStream::bytesOf(msgs));
  EXPECT_EQ(s.deferred().size(), 230u);
  EXPECT_EQ(s.lastUpdate().deferred, 230u);
  // Nothing allowed: the update still goes out, numbered, without cells.
  s.allow(0);
  const auto empty = s.update(2, std::vector<PublishedCell>{});
  ASSERT_EQ(empty.size(), 1u);
  EXPECT_EQ(empty[0].num_cells, 0);
  EXPECT_EQ(empty[0].seq, 2);
}

TEST(DeltaBudget, WaitingClassChangesGoOutBeforeProbabilityMoves) {
  DeltaStream s({0.2, 1, 100}, PublishingRule{0.02, 0.0});
  // Publish 50 free cells, then move them within free (probability only) and turn 10 others occupied.
  std::vector<PublishedCell> first;
  for (int x = 0; x < 50; ++x) first.push_back(cellAt(x, 0, 0.2));
  s.update(1, first);
  std::vector<PublishedCell> second;
  for (int x = 0; x < 50; ++x) second.push_back(cellAt(x, 0, 0.1));
  for (int x = 100; x < 110; ++x) second.push_back(cellAt(x, 0, 0.9));
  s.allow(0);
  s.update(2, second);
  ASSERT_EQ(s.deferred().size(), 60u);
  EXPECT_EQ(s.deferred().classChanges(), 10u);
  s.allow(DeltaStream::partBytes(15));
  const auto sent = cellsIn(s.update(3, std::vector<PublishedCell>{}));
  ASSERT_EQ(sent.size(), 15u);
  for (std::size_t i = 0; i < 10; ++i) EXPECT_EQ(sent[i].cell_class, ogf::map_delta_t::CLASS_OCCUPIED) << i;
  for (std::size_t i = 10; i < 15; ++i) EXPECT_EQ(sent[i].key.x, static_cast<int>(i) - 10) << "oldest probability moves next";
}

TEST(DeltaBudget, WaitingCellSendsItsLatestStateOnceAndLeavesWhenBackWithinTheStep) {
  DeltaStream s({0.2, 1, 100}, PublishingRule{0.02, 0.0});
  s.update(1, std::vector{cellAt(0, 0, 0.2), cellAt(1, 0, 0.2)});
  s.allow(0);
  s.update(2, std::vector{cellAt(0, 0, 0.25), cellAt(1, 0, 0.25)});
  s.update(3, std::vector{cellAt(0, 0, 0.28), cellAt(1, 0, 0.21)});  // cell 1 back within 0.02 of 0.2
  EXPECT_EQ(s.deferred().size(), 1u);
  s.allow(LinkBudget::kUnbounded);
  const auto sent = cellsIn(s.update(4, std::vector<PublishedCell>{}));
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].key.x, 0);
  EXPECT_EQ(sent[0].probability, quantiseProbability(0.28));
  EXPECT_TRUE(s.deferred().empty());
}

// A map changing faster than its budget: every update's messages keep the client consistent, nothing
// waits twice for one cell, and once the changes stop the waiting cells drain and the client holds exactly
// the mapper's latest state of every cell (step 0: every visible change is worth sending).
TEST(DeltaBudget, ClientOverATightBudgetStaysConsistentAndEndsWithTheMappersMap) {
  DeltaStream s({0.2, 9, 40}, PublishingRule{0.0, 0.0});
  MapReceiver r;
  for (const auto& m : s.keyframe(0)) r.accept(m);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> coord(0, 40);
  std::uniform_real_distribution<double> prob(0.0, 1.0);
  std::map<std::pair<int, int>, PublishedCell> truth;
  const std::int64_t allowance = DeltaStream::partBytes(40) * 2;  // 80 cells an update
  bool deferred_some = false;
  int scan = 0;
  for (; scan < 100; ++scan) {
    std::map<std::pair<int, int>, PublishedCell> scan_changes;  // each cell once, as ScanMapper::apply reports
    for (int k = 0; k < 200; ++k) {
      const PublishedCell c = cellAt(coord(rng), coord(rng), prob(rng));
      scan_changes[{c.key.x, c.key.y}] = c;
    }
    std::vector<PublishedCell> changed;
    for (const auto& [xy, c] : scan_changes) {
      truth[xy] = c;
      changed.push_back(c);
    }
    s.allow(allowance);
    const auto msgs = s.update(scan, changed);
    EXPECT_LE(DeltaStream::bytesOf(msgs), allowance);
    deferred_some = deferred_some || !s.deferred().empty();
    EXPECT_LE(s.deferred().size(), truth.size());  // one entry per cell
    for (const auto& m : msgs) r.accept(m);
    ASSERT_TRUE(r.consistent()) << "scan " << scan;
  }
  EXPECT_TRUE(deferred_some);
  for (; !s.deferred().empty() && scan < 1000; ++scan) {
    s.allow(allowance);
    for (const auto& m : s.update(scan, std::vector<PublishedCell>{})) r.accept(m);
    ASSERT_TRUE(r.consistent());
  }
  EXPECT_TRUE(s.deferred().empty());
  for (const auto& [xy, c] : truth) {
    const auto held = r.map().find(c.key);
    const PublishedCell client = held.value_or(PublishedCell{c.key});
    EXPECT_FALSE(client.visiblyDiffers(c)) << xy.first << "," << xy.second;
  }
}

// The waiting set holds at most its capacity: the changes beyond it leave only their slab, once each.
TEST(DeltaBudget, WaitingCellsStopAtTheCapacityAndTheRestMarkTheirSlabsStale) {
  DeltaStream s({0.2, 1, 50}, PublishingRule{0.02, 0.0});
  s.limitWaiting(100);
  s.allow(0);
  std::vector<PublishedCell> cells;
  for (int x = 0; x < 300; ++x) cells.push_back(cellAt(x, 0, 0.9));
  s.update(1, cells);
  EXPECT_EQ(s.deferred().size(), 100u);
  EXPECT_EQ(s.lastUpdate().overflowed, 200u);
  EXPECT_EQ(s.overflowed(), 200u);
  // Cells 100 to 299 lie in slabs 12 (x 96 to 103) to 37.
  EXPECT_EQ(s.stale().size(), 26u);
  EXPECT_EQ(s.lastUpdate().stale, 26u);
  // Full: no slab is read.
  EXPECT_TRUE(s.staleSlabsToRead().empty());
  // Room for two slabs' worth of cells once 128 of the waiting cells went out.
  s.allow(DeltaStream::partBytes(50) * 2 + DeltaStream::partBytes(28));
  s.update(2, std::vector<PublishedCell>{});
  EXPECT_EQ(s.deferred().size(), 0u);
  const auto slabs = s.staleSlabsToRead(10);
  ASSERT_EQ(slabs.size(), 1u) << "100 cells of room hold one slab of 64";
  EXPECT_EQ(slabs[0], (ogf::CellKey{12, 0, 0}));
  EXPECT_EQ(s.stale().size(), 25u);
  // Cells read again that find the set full count in the next update's figures.
  s.limitWaiting(0);
  s.refreshStale(std::vector{cellAt(500, 0, 0.9), cellAt(501, 0, 0.9)});
  s.allow(0);
  s.update(3, std::vector<PublishedCell>{});
  EXPECT_EQ(s.lastUpdate().overflowed, 2u);
  EXPECT_EQ(s.overflowed(), 202u);
  EXPECT_EQ(s.stale().size(), 26u);
}

// The waiting cells ogf-mapper allows: what max_wait_s seconds of max_bytes_per_s carry, in whole messages
// and a last partial one; a configuration's product beyond int64 is capped, not wrapped.
TEST(DeltaBudget, TheWaitingCellsAreWhatSecondsOfTheRateCarry) {
  DeltaStream s({0.2, 1, 50}, PublishingRule{0.02, 0.0});
  s.limitWaitingTo(2'000'000.0, 1.5);
  EXPECT_EQ(s.deferred().capacity(), s.cellsWithin(3'000'000));
  EXPECT_GT(s.deferred().capacity(), 100'000u);
  s.limitWaitingTo(1e300, 1e300);
  EXPECT_EQ(s.deferred().capacity(), s.cellsWithin(std::int64_t{1'000'000'000'000'000}));
  s.limitWaitingTo(100.0, 0.0);
  EXPECT_EQ(s.deferred().capacity(), 0u);
}

TEST(DeltaBudget, ClassChangeTakesTheOldestWaitingProbabilityMovesPlaceWhenFull) {
  DeltaStream s({0.2, 1, 50}, PublishingRule{0.02, 0.0});
  std::vector<PublishedCell> first;
  for (int x = 0; x < 10; ++x) first.push_back(cellAt(x, 0, 0.2));
  s.update(1, first);
  s.limitWaiting(10);
  s.allow(0);
  std::vector<PublishedCell> moves;
  for (int x = 0; x < 10; ++x) moves.push_back(cellAt(x, 0, 0.1));  // within free: probability moves
  s.update(2, moves);
  ASSERT_EQ(s.deferred().size(), 10u);
  s.update(3, std::vector{cellAt(40, 0, 0.9), cellAt(41, 0, 0.6)});  // a class change, and a move up
  EXPECT_EQ(s.deferred().size(), 10u);
  EXPECT_EQ(s.deferred().classChanges(), 1u);
  EXPECT_EQ(s.lastUpdate().overflowed, 2u);
  // The oldest move (x 0, slab 0) made way; the second move found the set full (slab 5).
  ASSERT_EQ(s.stale().size(), 2u);
  s.allow(DeltaStream::partBytes(1));
  const auto sent = cellsIn(s.update(4, std::vector<PublishedCell>{}));
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].key.x, 40);
}

// A scan with more class changes than an update can send and the waiting set hold: the first ones go out, the
// next ones fill the waiting set, and every change beyond them, class change or probability move, leaves
// its slab stale.
TEST(DeltaBudget, ChangesBeyondWhatAnUpdateSendsAndTheWaitingCellsHoldMarkTheirSlabsStale) {
  DeltaStream s({0.2, 1, 50}, PublishingRule{0.02, 0.0});
  std::vector<PublishedCell> free_cells;
  for (int x = 100; x < 120; ++x) free_cells.push_back(cellAt(x, 0, 0.2));
  s.update(1, free_cells);
  s.limitWaiting(10);
  s.allow(DeltaStream::partBytes(5));
  std::vector<PublishedCell> scan;
  for (int x = 100; x < 120; ++x) scan.push_back(cellAt(x, 0, 0.1));  // probability moves within free
  for (int x = 0; x < 40; ++x) scan.push_back(cellAt(x, 0, 0.9));     // class changes
  const auto sent = cellsIn(s.update(2, scan));
  ASSERT_EQ(sent.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(sent[static_cast<std::size_t>(i)].key.x, i);
  EXPECT_EQ(s.deferred().size(), 10u);
  EXPECT_EQ(s.deferred().classChanges(), 10u);
  EXPECT_EQ(s.lastUpdate().overflowed, 45u);
  EXPECT_EQ(s.stale().size(), 7u) << "x 15 to 39: slabs 1 to 4; x 100 to 119: slabs 12 to 14";
  // The waiting class changes are x 5 to 14: they go out next.
  s.allow(DeltaStream::partBytes(50));
  const auto next = cellsIn(s.update(3, std::vector<PublishedCell>{}));
  ASSERT_EQ(next.size(), 10u);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(next[static_cast<std::size_t>(i)].key.x, 5 + i);
}

// Once slabs are stale the client is behind by more than the waiting cells hold: a new change worth sending
// joins the stale slabs even where the waiting set has room, so the slabs go out in the order they went
// stale; a waiting cell still takes its newest state, and a change not worth sending marks nothing.
TEST(DeltaBudget, WhileSlabsAreStaleANewChangeJoinsThemAsItsSlabAndAWaitingCellTakesItsNewestState) {
  DeltaStream s({0.2, 1, 50}, PublishingRule{0.02, 0.0});
  s.limitWaiting(10);
  s.allow(0);
  std::vector<PublishedCell> first;
  for (int x = 0; x < 20; ++x) first.push_back(cellAt(x, 0, 0.9));
  s.update(1, first);
  ASSERT_EQ(s.deferred().size(), 10u);
  ASSERT_EQ(s.stale().size(), 2u);  // x 10 to 19: slabs 1 and 2
  s.allow(DeltaStream::partBytes(5));
  s.update(2, std::vector<PublishedCell>{});  // x 0 to 4 go out
  ASSERT_EQ(s.deferred().size(), 5u);
  s.allow(0);
  std::vector<PublishedCell> third{cellAt(7, 0, 0.95)};  // waiting: takes the state
  for (int x = 80; x < 85; ++x) third.push_back(cellAt(x, 0, 0.9));  // slab 10, worth sending
  third.push_back(cellAt(90, 0, 0.5));  // slab 11, the prior: nothing to send
  s.update(3, third);
  EXPECT_EQ(s.deferred().size(), 5u) << "room for five, yet the new changes do not wait";
  EXPECT_EQ(s.stale().size(), 3u);
  EXPECT_EQ(s.lastUpdate().overflowed, 5u);
  // The oldest stale slab is read first; the waiting cell goes out with its newest state.
  s.allow(DeltaStream::partBytes(50));
  const auto sent = cellsIn(s.update(4, std::vector<PublishedCell>{}));
  ASSERT_EQ(sent.size(), 5u);
  EXPECT_EQ(sent[2].key.x, 7);
  EXPECT_EQ(sent[2].probability, quantiseProbability(0.95));
  s.limitWaiting(1000);  // room for the three slabs' cells
  const auto slabs = s.staleSlabsToRead(10);
  ASSERT_EQ(slabs.size(), 3u);
  EXPECT_EQ(slabs[0], (ogf::CellKey{1, 0, 0}));
  EXPECT_EQ(slabs[1], (ogf::CellKey{2, 0, 0}));
  EXPECT_EQ(slabs[2], (ogf::CellKey{10, 0, 0}));
}

// A map changing far faster than its budget for a long spell, with few cells allowed to wait: the client
// stays consistent, and once the changes stop and the stale slabs are read again from the map, it holds
// exactly the map's latest state of every cell.
TEST(DeltaBudget, ClientEndsWithTheMapAfterChangesOverflowedTheWaitingCells) {
  DeltaStream s({0.2, 9, 40}, PublishingRule{0.0, 0.0});
  s.limitWaiting(150);
  MapReceiver r;
  for (const auto& m : s.keyframe(0)) r.accept(m);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> coord(-30, 30);
  std::uniform_real_distribution<double> prob(0.0, 1.0);
  std::map<ogf::CellKey, PublishedCell> truth;  // the map: every cell's latest state
  const auto readSlabs = [&](const std::vector<ogf::CellKey>& slabs) {
    std::vector<PublishedCell> cells;
    for (const ogf::CellKey& slab : slabs)
      for (unsigned local = 0; local < PublishedBlock::kCells; ++local)
        if (auto it = truth.find(PublishedBlock::cellKey(slab, local)); it != truth.end()) cells.push_back(it->second);
    return cells;
  };
  const std::int64_t allowance = DeltaStream::partBytes(40);  // 40 cells an update
  std::size_t most_waiting = 0;
  int scan = 0;
  for (; scan < 100; ++scan) {
    s.refreshStale(readSlabs(s.staleSlabsToRead()));
    std::map<ogf::CellKey, PublishedCell> scan_changes;
    for (int k = 0; k < 300; ++k) {
      const PublishedCell c = cellAt(coord(rng), coord(rng), prob(rng));
      scan_changes[c.key] = c;
    }
    std::vector<PublishedCell> changed;
    for (const auto& [key, c] : scan_changes) {
      truth[key] = c;
      changed.push_back(c);
    }
    s.allow(allowance);
    for (const auto& m : s.update(scan, changed)) r.accept(m);
    ASSERT_TRUE(r.consistent()) << "scan " << scan;
    most_waiting = std::max(most_waiting, s.deferred().size());
  }
  EXPECT_EQ(most_waiting, 150u);
  EXPECT_GT(s.overflowed(), 10000u);
  for (; (!s.deferred().empty() || !s.stale().empty()) && scan < 5000; ++scan) {
    s.refreshStale(readSlabs(s.staleSlabsToRead()));
    s.allow(allowance);
    for (const auto& m : s.update(scan, std::vector<PublishedCell>{})) r.accept(m);
    ASSERT_TRUE(r.consistent());
  }
  EXPECT_TRUE(s.deferred().empty());
  EXPECT_TRUE(s.stale().empty());
  for (const auto& [key, c] : truth) {
    const PublishedCell client = r.map().find(key).value_or(PublishedCell{key});
    EXPECT_FALSE(client.visiblyDiffers(c)) << key.x << "," << key.y;
  }
}

TEST(DeltaBudget, WaitingCellWhoseRegionWentToPagesIsNotSent) {
  DeltaStream s({0.2, 1, 100}, PublishingRule{0.02, 0.0});
  s.update(1, std::vector{cellAt(3, 3, 0.2)});
  s.allow(0);
  s.update(2, std::vector{cellAt(3, 3, 0.9)});
  ASSERT_EQ(s.deferred().size(), 1u);
  const auto checksum = s.map().checksum();
  s.map().evict({0, 0, 0}, {8, 8, 1});  // its region leaves memory with the cell as published
  s.allow(LinkBudget::kUnbounded);
  const auto msgs = s.update(3, std::vector<PublishedCell>{});
  EXPECT_TRUE(cellsIn(msgs).empty());
  EXPECT_TRUE(s.deferred().empty());
  EXPECT_EQ(static_cast<std::uint64_t>(msgs[0].map_checksum), checksum);  // clients still hold that map
}

TEST(LinkBudget, AccruesAtItsRateUpToItsBurstAndPacesDebt) {
  LinkBudget b(1000.0, 0.5, 0);  // 1000 bytes/s, at most 500 held
  EXPECT_EQ(b.allowance(), 500);
  b.spend(800);
  EXPECT_EQ(b.allowance(), 0);
  EXPECT_EQ(b.debtUs(), 300'000);  // 300 bytes of debt at 1000 bytes/s
  b.refill(100'000);
  EXPECT_EQ(b.debtUs(), 200'000);
  b.refill(1'000'000);
  EXPECT_EQ(b.allowance(), 500);  // capped at the burst
  b.refill(500'000);              // a clock going back adds nothing
  EXPECT_EQ(b.allowance(), 500);
  EXPECT_EQ(b.spent(), 800);
  LinkBudget open(0.0, 1.0, 0);
  EXPECT_FALSE(open.bounded());
  EXPECT_EQ(open.allowance(), LinkBudget::kUnbounded);
  open.spend(1'000'000);
  EXPECT_EQ(open.debtUs(), 0);
}

}  // namespace
