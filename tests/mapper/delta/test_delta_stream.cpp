// The delta stream and its receiver: a client that sees every message rebuilds the mapper's published map
// exactly (equal checksums); a lost update is detected as a gap, never guessed over, and a keyframe
// brings the client back. KeyframeWriter: a keyframe whose cells are added after its cut, in any order,
// while updates go on, still rebuilds the map; its part count is fixed at the cut.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <span>
#include <vector>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/delta/keyframe_writer.hpp"
#include "ogf/delta/map_receiver.hpp"

namespace {

using namespace ogf::delta;
using Outcome = MapReceiver::Outcome;

PublishedCell cell(int x, int y, int z, double p, std::int8_t cls, float var = 0.5f) {
  return {{x, y, z}, quantiseProbability(p), cls, var};
}

std::vector<PublishedCell> randomUpdate(std::mt19937& rng, int n) {
  std::uniform_int_distribution<int> coord(-20, 20);
  std::uniform_real_distribution<double> prob(0.0, 1.0);
  std::vector<PublishedCell> out;
  for (int i = 0; i < n; ++i) {
    const double p = prob(rng);
    const std::int8_t cls = p > 0.65 ? 1 : (p < 0.35 ? -1 : 0);
    out.push_back(cell(coord(rng), coord(rng), coord(rng) / 4, p, cls, static_cast<float>(prob(rng))));
  }
  return out;
}

TEST(PublishedMap, ChecksumDependsOnContentNotOrder) {
  PublishedMap a, b;
  const auto c1 = cell(1, 2, 3, 0.9, 1);
  const auto c2 = cell(-4, 5, 0, 0.1, -1);
  a.set(c1);
  a.set(c2);
  b.set(c2);
  b.set(c1);
  EXPECT_EQ(a.checksum(), b.checksum());
  EXPECT_NE(a.checksum(), 0u);
  b.set(cell(1, 2, 3, 0.8, 1));  // a different probability
  EXPECT_NE(a.checksum(), b.checksum());
  b.set(c1);  // and back
  EXPECT_EQ(a.checksum(), b.checksum());
  a.clear();
  EXPECT_EQ(a.checksum(), 0u);
}

TEST(QuantiseProbability, RoundsToTenThousandths) {
  EXPECT_EQ(quantiseProbability(0.5), 5000);
  EXPECT_EQ(quantiseProbability(0.12345), 1235);  // 1234.5 rounds half away from zero
  EXPECT_EQ(quantiseProbability(1.7), 10000);
  EXPECT_EQ(quantiseProbability(-1.0), 0);
  EXPECT_EQ(quantiseProbability(std::nan("")), 5000);
}

TEST(DeltaStream, PublishesOnlyCellsAClientWouldSeeChange) {
  DeltaStream s({0.2, 7, 100});
  auto first = s.update(10, std::vector{cell(0, 0, 0, 0.9, 1), cell(1, 0, 0, 0.5, 0)});
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].num_cells, 1);  // the prior-valued cell is not news
  EXPECT_EQ(first[0].seq, 1);
  EXPECT_EQ(first[0].base_seq, 0);
  // Same quantised probability and class, other variance: nothing to publish, but the update is numbered.
  auto second = s.update(20, std::vector{cell(0, 0, 0, 0.90001, 1, 0.1f)});
  ASSERT_EQ(second.size(), 1u);
  EXPECT_EQ(second[0].num_cells, 0);
  EXPECT_EQ(second[0].seq, 2);
  EXPECT_EQ(static_cast<std::uint64_t>(second[0].map_checksum), s.map().checksum());
}

TEST(DeltaStream, SplitsLargeUpdatesIntoNumberedParts) {
  DeltaStream s({0.2, 1, 100});
  std::vector<PublishedCell> cells;
  for (int i = 0; i < 250; ++i) cells.push_back(cell(i, 0, 0, 0.9, 1));
  const auto msgs = s.update(1, cells);
  ASSERT_EQ(msgs.size(), 3u);
  int total = 0;
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    EXPECT_EQ(msgs[i].part_index, static_cast<int>(i));
    EXPECT_EQ(msgs[i].part_count, 3);
    EXPECT_LE(msgs[i].num_cells, 100);
    total += msgs[i].num_cells;
  }
  EXPECT_EQ(total, 250);
}

TEST(MapReceiver, RebuildsThePublishedMapExactlyFromEveryMessage) {
  std::mt19937 rng(11);
  DeltaStream s({0.2, 3, 50});
  MapReceiver r;
  // A client joining at the start asks for a keyframe: the empty map at seq 0.
  for (const auto& m : s.keyframe(0)) r.accept(m);
  ASSERT_FALSE(r.needsKeyframe());
  for (int scan = 0; scan < 200; ++scan) {
    auto msgs = s.update(scan, randomUpdate(rng, 120));
    std::shuffle(msgs.begin(), msgs.end(), rng);  // parts of one update may arrive in any order
    for (const auto& m : msgs) EXPECT_NE(r.accept(m), Outcome::kMalformed);
  }
  EXPECT_EQ(r.appliedSeq(), s.seq());
  EXPECT_TRUE(r.consistent());
  EXPECT_EQ(r.map().checksum(), s.map().checksum());
  EXPECT_EQ(r.map().sortedCells().size(), s.map().size());
  EXPECT_EQ(r.gaps(), 0u);
}

TEST(MapReceiver, CellSinkSeesEveryDeltaCellInApplyOrder) {
  std::mt19937 rng(15);
  DeltaStream s({0.2, 3, 30});
  MapReceiver r;
  PublishedMap followed;
  std::size_t calls = 0;
  r.onDeltaCell([&](const PublishedCell& c) {
    followed.set(c);
    ++calls;
  });
  for (const auto& m : s.keyframe(0)) r.accept(m);
  EXPECT_EQ(calls, 0u);  // keyframes do not go through the sink
  for (int scan = 0; scan < 50; ++scan) {
    auto msgs = s.update(scan, randomUpdate(rng, 80));
    std::shuffle(msgs.begin(), msgs.end(), rng);
    for (const auto& m : msgs) r.accept(m);
  }
  EXPECT_GT(calls, 0u);
  EXPECT_EQ(followed.checksum(), r.map().checksum());
}

TEST(MapReceiver, LostUpdateIsAGapUntilAKeyframeRestoresTheMap) {
  std::mt19937 rng(12);
  DeltaStream s({0.2, 3, 40});
  MapReceiver r;
  for (const auto& m : s.keyframe(0)) r.accept(m);
  for (int scan = 0; scan < 30; ++scan) {
    const auto msgs = s.update(scan, randomUpdate(rng, 100));
    if (scan == 10) continue;  // the whole update is lost
    for (const auto& m : msgs) r.accept(m);
  }
  EXPECT_TRUE(r.needsKeyframe());
  EXPECT_EQ(r.gaps(), 1u);
  EXPECT_EQ(r.appliedSeq(), 10);  // stopped before the hole, applied nothing after it
  for (const auto& m : s.keyframe(99)) r.accept(m);
  EXPECT_FALSE(r.needsKeyframe());
  EXPECT_EQ(r.appliedSeq(), s.seq());
  EXPECT_TRUE(r.consistent());
  // And it keeps up afterwards.
  for (int scan = 30; scan < 40; ++scan)
    for (const auto& m : s.update(scan, randomUpdate(rng, 100))) r.accept(m);
  EXPECT_TRUE(r.consistent());
  EXPECT_EQ(r.map().checksum(), s.map().checksum());
}

TEST(MapReceiver, LostPartIsAGapOnceTheNextUpdateCompletes) {
  std::mt19937 rng(13);
  DeltaStream s({0.2, 3, 30});
  MapReceiver r;
  for (const auto& m : s.keyframe(0)) r.accept(m);
  auto a = s.update(1, randomUpdate(rng, 100));
  ASSERT_GE(a.size(), 2u);
  for (std::size_t i = 1; i < a.size(); ++i) EXPECT_EQ(r.accept(a[i]), Outcome::kPartial);  // part 0 lost
  EXPECT_FALSE(r.needsKeyframe());
  Outcome last = Outcome::kPartial;
  for (const auto& m : s.update(2, randomUpdate(rng, 10))) last = r.accept(m);
  EXPECT_EQ(last, Outcome::kGap);
  EXPECT_TRUE(r.needsKeyframe());
}

TEST(MapReceiver, DeltasArrivingDuringKeyframeAreAppliedAfterIt) {
  std::mt19937 rng(14);
  DeltaStream s({0.2, 5, 40});
  MapReceiver r;
  for (int scan = 0; scan < 5; ++scan) s.update(scan, randomUpdate(rng, 60));
  const auto kf = s.keyframe(5);  // at seq 5
  const auto d6 = s.update(6, randomUpdate(rng, 60));
  for (const auto& m : d6) EXPECT_EQ(r.accept(m), Outcome::kBuffered);  // no keyframe yet
  for (const auto& m : kf) r.accept(m);
  EXPECT_EQ(r.appliedSeq(), 6);
  EXPECT_TRUE(r.consistent());
}

TEST(MapReceiver, NewMapIdDemandsAKeyframe) {
  DeltaStream first({0.2, 1, 100});
  MapReceiver r;
  for (const auto& m : first.keyframe(0)) r.accept(m);
  for (const auto& m : first.update(1, std::vector{cell(0, 0, 0, 0.9, 1)})) r.accept(m);
  ASSERT_TRUE(r.consistent());
  DeltaStream restarted({0.2, 2, 100});  // the mapper restarted with another map id
  for (const auto& m : restarted.update(1, std::vector{cell(5, 5, 0, 0.1, -1)})) r.accept(m);
  EXPECT_TRUE(r.needsKeyframe());
  for (const auto& m : restarted.keyframe(2)) r.accept(m);
  EXPECT_EQ(r.mapId(), 2);
  EXPECT_TRUE(r.consistent());
  EXPECT_FALSE(r.map().find({0, 0, 0}).has_value());  // nothing of the old map survives
}

TEST(MapReceiver, MalformedMessagesAreCountedAndIgnored) {
  DeltaStream s({0.2, 1, 100});
  MapReceiver r;
  for (const auto& m : s.keyframe(0)) r.accept(m);
  auto m = s.update(1, std::vector{cell(0, 0, 0, 0.9, 1)})[0];
  auto bad = m;
  bad.part_index = 3;  // beyond part_count
  EXPECT_EQ(r.accept(bad), Outcome::kMalformed);
  bad = m;
  bad.key_y.pop_back();  // arrays disagree with num_cells
  EXPECT_EQ(r.accept(bad), Outcome::kMalformed);
  bad = m;
  bad.kind = 9;
  EXPECT_EQ(r.accept(bad), Outcome::kMalformed);
  bad = m;
  bad.part_count = 1 << 30;
  bad.part_index = 0;
  EXPECT_EQ(r.accept(bad), Outcome::kMalformed);
  EXPECT_EQ(r.malformed(), 4u);
  EXPECT_EQ(r.accept(m), Outcome::kApplied);
  EXPECT_TRUE(r.consistent());
}

TEST(MapReceiver, DuplicateMessagesAreHarmless) {
  DeltaStream s({0.2, 1, 100});
  MapReceiver r;
  for (const auto& m : s.keyframe(0)) r.accept(m);
  const auto msgs = s.update(1, std::vector{cell(0, 0, 0, 0.9, 1)});
  EXPECT_EQ(r.accept(msgs[0]), Outcome::kApplied);
  EXPECT_EQ(r.accept(msgs[0]), Outcome::kStale);
  EXPECT_TRUE(r.consistent());
}

// Feeds `cells` to the writer in pieces of `piece`, collecting the parts.
std::vector<ogf::map_delta_t> write(KeyframeWriter& w, const std::vector<PublishedCell>& cells, std::size_t piece) {
  std::vector<ogf::map_delta_t> parts;
  for (std::size_t i = 0; i < cells.size(); i += piece)
    w.add(std::span(cells).subspan(i, std::min(piece, cells.size() - i)), parts);
  w.finish(parts);
  return parts;
}

TEST(KeyframeWriter, CellsReadAfterTheCutStillRebuildTheMap) {
  std::mt19937 rng(3);
  DeltaStream s({0.2, 9, 40});
  for (int scan = 0; scan < 6; ++scan) s.update(scan, randomUpdate(rng, 80));
  KeyframeWriter w(s, 6);  // cut at seq 6
  const std::size_t count = s.map().size();
  ASSERT_EQ(w.cells(), count);
  // The cells as they stand at the cut, but read only after two more updates changed some of them: each
  // cell is read at seq 6 or later, as the pages and the copy are (a cell the updates did not add).
  const auto atCut = s.map().sortedCells();
  const auto d7 = s.update(7, randomUpdate(rng, 80));
  const auto d8 = s.update(8, randomUpdate(rng, 80));
  std::vector<PublishedCell> later;
  for (const PublishedCell& c : atCut) later.push_back(*s.map().find(c.key));
  std::shuffle(later.begin(), later.end(), rng);
  const auto parts = write(w, later, 17);
  ASSERT_EQ(parts.size(), (count + 39) / 40);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    EXPECT_EQ(parts[i].part_index, static_cast<std::int32_t>(i));
    EXPECT_EQ(parts[i].part_count, static_cast<std::int32_t>(parts.size()));
    EXPECT_EQ(parts[i].seq, 6);
  }
  EXPECT_EQ(w.missing(), 0u);
  EXPECT_EQ(w.surplus(), 0u);

  // A client that joins now: the updates arrive around the keyframe's parts.
  MapReceiver r;
  for (const auto& m : d7) r.accept(m);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    r.accept(parts[i]);
    if (i == parts.size() / 2)
      for (const auto& m : d8) r.accept(m);
  }
  EXPECT_EQ(r.appliedSeq(), 8);
  EXPECT_TRUE(r.consistent());
  EXPECT_EQ(r.map().checksum(), s.map().checksum());
}

TEST(KeyframeWriter, ShortKeyframeCompletesWithEmptyPartsAndLongOneIsCut) {
  std::mt19937 rng(4);
  DeltaStream s({0.2, 9, 40});
  for (int scan = 0; scan < 4; ++scan) s.update(scan, randomUpdate(rng, 80));
  auto cells = s.map().sortedCells();
  ASSERT_GT(cells.size(), 100u);

  KeyframeWriter shortOne(s, 4);
  const std::vector<PublishedCell> lacking(cells.begin(), cells.end() - 100);
  const auto parts = write(shortOne, lacking, 64);
  EXPECT_EQ(parts.size(), static_cast<std::size_t>(shortOne.partCount()));
  EXPECT_EQ(shortOne.missing(), 100u);
  EXPECT_EQ(parts.back().num_cells, 0);  // a part no cell reached
  MapReceiver r;
  Outcome last = Outcome::kPartial;
  for (const auto& m : parts) last = r.accept(m);
  EXPECT_EQ(last, Outcome::kKeyframeApplied);
  EXPECT_FALSE(r.consistent()) << "the keyframe's checksum must tell the client its map is not the mapper's";

  KeyframeWriter longOne(s, 4);
  auto doubled = cells;
  doubled.insert(doubled.end(), cells.begin(), cells.begin() + 5);
  const auto all = write(longOne, doubled, 1000);
  EXPECT_EQ(longOne.surplus(), 5u);
  EXPECT_EQ(longOne.missing(), 0u);
  MapReceiver r2;
  for (const auto& m : all) r2.accept(m);
  EXPECT_TRUE(r2.consistent());
}

}  // namespace
