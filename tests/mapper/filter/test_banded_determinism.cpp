// The banded filter's map is bit-identical for 1 and N threads, for any order of a batch and whether or not
// clamped free measurements are dropped before the batch is ordered, and it reports exactly the cells whose
// class or quantised probability changed.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/occupancy.hpp"

namespace ogf::filter {
namespace {

// A scan-like batch: one measurement per cell in a 40 × 40 × depth region around `centre` (depth 1: the
// z = 0 plane), y from a random wall pattern.
std::vector<Measurement> batchAround(const CellKey& centre, unsigned seed, std::size_t count, int depth = 12) {
  std::mt19937 rng(seed);
  std::set<CellKey> seen;
  std::vector<Measurement> batch;
  while (batch.size() < count) {
    const CellKey k = centre + CellKey{static_cast<int>(rng() % 40U) - 20, static_cast<int>(rng() % 40U) - 20,
                                       static_cast<int>(rng() % static_cast<unsigned>(depth)) - depth / 2};
    if (seen.insert(k).second) {
      batch.push_back({k, static_cast<std::int8_t>((k.x % 7 == 0 || k.z == -depth / 2) ? 1 : -1)});
    }
  }
  return batch;
}

std::uint64_t mapAfter(int threads, bool shuffle) {
  FilterConfig config;
  config.threads = threads;
  auto ogf = BandedOgf::create(config);
  EXPECT_TRUE(ogf.ok());
  std::mt19937 rng(3);
  for (unsigned scan = 0; scan < 4; ++scan) {
    std::vector<Measurement> batch = batchAround(CellKey{static_cast<int>(scan) * 5, 0, 0}, scan, 6000);
    if (shuffle) {
      std::shuffle(batch.begin(), batch.end(), rng);
    }
    ogf->update(batch);
  }
  return ogf->checksum();
}

TEST(BandedDeterminism, OneAndManyThreadsGiveTheSameMapBitForBit) {
  const std::uint64_t one = mapAfter(1, false);
  EXPECT_EQ(one, mapAfter(2, false));
  EXPECT_EQ(one, mapAfter(4, false));
  EXPECT_EQ(one, mapAfter(7, false));
}

TEST(BandedDeterminism, BatchOrderDoesNotMatter) { EXPECT_EQ(mapAfter(1, false), mapAfter(2, true)); }

TEST(BandedDeterminism, ChecksumSeesASingleMeasurement) {
  FilterConfig config;
  auto a = BandedOgf::create(config);
  auto b = BandedOgf::create(config);
  const std::vector<Measurement> batch = batchAround(CellKey{}, 1, 500);
  a->update(batch);
  b->update(batch);
  EXPECT_EQ(a->checksum(), b->checksum());
  b->update(Measurement{CellKey{100, 100, 100}, 1});
  EXPECT_NE(a->checksum(), b->checksum());
}

class RecordingSink : public ChangeSink {
 public:
  void cellChanged(const CellChange& c) override { changes.push_back(c); }
  std::vector<CellChange> changes;
};

// The same region measured scan after scan, walls moving: free cells pass the free clamp, then occupied
// measurements land beside (and on) them. Dropping the clamped free measurements early leaves the map,
// the statistics and the reported changes as they are when every measurement goes through eq. (5)'s path.
void expectEarlySkipsChangeNothing(FilterConfig config, int depth) {
  config.covariance = CovarianceStorage::kCompact;
  auto early = BandedOgf::create(config);
  auto late = BandedOgf::create(config);
  ASSERT_TRUE(early.ok() && late.ok());
  late->setSkipsClampedEarly(false);
  std::size_t dropped = 0;
  for (unsigned scan = 0; scan < 12; ++scan) {
    std::vector<Measurement> batch = batchAround(CellKey{}, 100 + scan % 3, depth == 1 ? 1200 : 9000, depth);
    for (Measurement& m : batch) {
      const bool wall = m.key.x % 7 == 0 || (scan >= 6 && (m.key.x + m.key.y + static_cast<int>(scan)) % 5 == 0);
      m.y = wall ? 1 : -1;  // walls, and from the seventh scan on others moving in
    }
    RecordingSink a;
    RecordingSink b;
    const UpdateStats sa = early->update(batch, &a);
    const UpdateStats sb = late->update(batch, &b);
    ASSERT_EQ(early->checksum(), late->checksum()) << "scan " << scan;
    EXPECT_EQ(sa.applied, sb.applied) << "scan " << scan;
    EXPECT_EQ(sa.skipped, sb.skipped) << "scan " << scan;
    EXPECT_EQ(sb.skippedEarly, 0U);
    ASSERT_EQ(a.changes.size(), b.changes.size()) << "scan " << scan;
    for (std::size_t i = 0; i < a.changes.size(); ++i) {
      EXPECT_EQ(a.changes[i].key, b.changes[i].key);
      EXPECT_EQ(a.changes[i].mean, b.changes[i].mean);
    }
    dropped += sa.skippedEarly;
  }
  EXPECT_GT(dropped, depth == 1 ? 500U : 5000U);
}

TEST(BandedDeterminism, DroppingClampedFreeMeasurementsEarlyChangesNothing) {
  FilterConfig config;
  config.threads = 2;
  expectEarlySkipsChangeNothing(config, 12);
}

TEST(BandedDeterminism, DroppingClampedFreeMeasurementsEarlyChangesNothingIn2D) {
  FilterConfig config;
  config.dimensions = 2;
  expectEarlySkipsChangeNothing(config, 1);
}

// Maps `first`, then `second` with a sink, and checks the sink's report against a comparison of the whole
// map before and after.
void expectSinkReportsExactlyTheChanges(const FilterConfig& config, const std::vector<Measurement>& first,
                                        const std::vector<Measurement>& second) {
  auto ogf = BandedOgf::create(config);
  ASSERT_TRUE(ogf.ok());
  ogf->update(first);
  std::map<CellKey, std::pair<std::uint16_t, std::int8_t>> before;
  auto snapshot = [&](std::map<CellKey, std::pair<std::uint16_t, std::int8_t>>& into) {
    ogf->forEachCell([&](const CellKey& k, float m, float s) {
      into[k] = {quantiseProbability(predictiveProbability(static_cast<double>(m), static_cast<double>(s))),
                 occupancyClass(static_cast<double>(m), 0.65, 0.35)};
    });
  };
  snapshot(before);
  RecordingSink sink;
  ogf->update(second, &sink);
  std::map<CellKey, std::pair<std::uint16_t, std::int8_t>> after;
  snapshot(after);
  std::set<CellKey> expected;
  for (const auto& [k, v] : after) {
    const auto it = before.find(k);
    const auto old = it == before.end() ? std::pair<std::uint16_t, std::int8_t>{5000, 0} : it->second;
    if (old != v) {
      expected.insert(k);
    }
  }
  std::set<CellKey> reported;
  for (const CellChange& c : sink.changes) {
    EXPECT_TRUE(reported.insert(c.key).second) << "reported twice";
    EXPECT_EQ(c.quantisedProbability, after.at(c.key).first);
    EXPECT_EQ(c.occupancyClass, after.at(c.key).second);
  }
  EXPECT_FALSE(expected.empty());
  EXPECT_EQ(reported, expected);
}

TEST(BandedDeterminism, ChangeSinkReportsExactlyTheCellsWhoseClassOrQuantisedProbabilityChanged) {
  FilterConfig config;
  config.threads = 2;
  expectSinkReportsExactlyTheChanges(config, batchAround(CellKey{}, 1, 3000), batchAround(CellKey{3, 0, 0}, 2, 3000));
}

TEST(BandedDeterminism, ChangeSinkReportsExactlyTheChangesInCompactStorage) {
  FilterConfig config;
  config.covariance = CovarianceStorage::kCompact;
  config.threads = 2;
  expectSinkReportsExactlyTheChanges(config, batchAround(CellKey{}, 1, 3000), batchAround(CellKey{3, 0, 0}, 2, 3000));
  // The same cells measured again: most updates are clamped, only the applied ones' stencils can change.
  const auto again = batchAround(CellKey{}, 1, 3000);
  expectSinkReportsExactlyTheChanges(config, again, again);
}

TEST(BandedDeterminism, ChangeSinkReportsExactlyTheChangesOfA2DMap) {
  FilterConfig config;
  config.dimensions = 2;
  expectSinkReportsExactlyTheChanges(config, batchAround(CellKey{}, 1, 600, 1),
                                     batchAround(CellKey{3, -9, 0}, 2, 600, 1));
}

// The largest stencil a 2-D map may have reaches 8 cells along x and y, a whole block: the change
// detection's dilation must carry cells into the neighbouring blocks at that distance too.
TEST(BandedDeterminism, ChangeSinkReportsExactlyTheChangesOfA2DMapWithTheWidestStencil) {
  for (const CovarianceStorage storage : {CovarianceStorage::kBanded, CovarianceStorage::kCompact}) {
    FilterConfig config;
    config.dimensions = 2;
    config.covariance = storage;
    config.kernelSigma = 0.6;  // three cells
    config.stencilRadius = 8.5;
    config.stencilManhattanRadius = 8;
    expectSinkReportsExactlyTheChanges(config, batchAround(CellKey{}, 1, 600, 1),
                                       batchAround(CellKey{3, -9, 0}, 2, 600, 1));
  }
}

// A scan-sized batch in the order a scan's measurement set gives (block by block, cells in key order
// within a block): `count` distinct cells of a 64 × 64 × 16 region shifted by `shift` cells along x, walls
// every seventh x and on the floor, and from scan 4 on other cells moving in and out; `rejected` of the
// measurements have y = 0.
std::vector<Measurement> scanSizedBatch(unsigned scan, std::size_t count, std::size_t rejected, int shift) {
  std::mt19937 rng(1000 + scan);
  std::set<CellKey> cells;
  while (cells.size() < count) {
    cells.insert(CellKey{static_cast<int>(rng() % 64U) - 32 + shift, static_cast<int>(rng() % 64U) - 32,
                         static_cast<int>(rng() % 16U) - 8});
  }
  std::vector<Measurement> batch;
  for (const CellKey& k : cells) {
    const bool wall = k.x % 7 == 0 || k.z == -8 || (scan >= 4 && (k.x + k.y + static_cast<int>(scan)) % 5 == 0);
    batch.push_back({k, static_cast<std::int8_t>(wall ? 1 : -1)});
  }
  for (std::size_t i = 0; i < rejected; ++i) {
    batch[(1 + i * 7919U) % batch.size()].y = 0;
  }
  std::sort(batch.begin(), batch.end(), [](const Measurement& a, const Measurement& b) {
    const CellKey ba = blockKeyOf(a.key);
    const CellKey bb = blockKeyOf(b.key);
    return ba == bb ? a.key < b.key : ba < bb;
  });
  return batch;
}

enum class BatchShape { kScan, kBlockInTwoRuns, kShuffled };

// Twelve scan-sized batches through a filter on `threads` threads: the map's checksum, the statistics and
// the reported changes after each.
struct ScanTrace {
  std::vector<std::uint64_t> checksums;
  std::vector<UpdateStats> stats;
  std::vector<std::vector<CellChange>> changes;
};

ScanTrace traceScans(FilterConfig config, int threads, BatchShape shape) {
  config.threads = threads;
  auto ogf = BandedOgf::create(config);
  EXPECT_TRUE(ogf.ok());
  ScanTrace trace;
  std::mt19937 rng(7);
  for (unsigned scan = 0; scan < 12; ++scan) {
    std::vector<Measurement> batch = scanSizedBatch(scan % 6, 30000, scan == 2 ? 5000 : 40, static_cast<int>(scan % 3));
    if (shape == BatchShape::kBlockInTwoRuns) {
      std::rotate(batch.begin(), batch.begin() + 1, batch.end());  // the first block's first cell comes last
    } else if (shape == BatchShape::kShuffled) {
      std::shuffle(batch.begin(), batch.end(), rng);
    }
    RecordingSink sink;
    trace.stats.push_back(ogf->update(batch, &sink));
    trace.checksums.push_back(ogf->checksum());
    trace.changes.push_back(std::move(sink.changes));
  }
  return trace;
}

void expectSameTrace(const ScanTrace& a, const ScanTrace& b, int threads) {
  ASSERT_EQ(a.checksums.size(), b.checksums.size());
  for (std::size_t scan = 0; scan < a.checksums.size(); ++scan) {
    SCOPED_TRACE(::testing::Message() << "threads " << threads << ", scan " << scan);
    EXPECT_EQ(a.checksums[scan], b.checksums[scan]);
    EXPECT_EQ(a.stats[scan].applied, b.stats[scan].applied);
    EXPECT_EQ(a.stats[scan].skipped, b.stats[scan].skipped);
    EXPECT_EQ(a.stats[scan].skippedEarly, b.stats[scan].skippedEarly);
    EXPECT_EQ(a.stats[scan].rejected, b.stats[scan].rejected);
    EXPECT_EQ(a.stats[scan].heldBack, b.stats[scan].heldBack);
    EXPECT_EQ(a.stats[scan].blocksAllocated, b.stats[scan].blocksAllocated);
    ASSERT_EQ(a.changes[scan].size(), b.changes[scan].size());
    for (std::size_t i = 0; i < a.changes[scan].size(); ++i) {
      ASSERT_EQ(a.changes[scan][i].key, b.changes[scan][i].key) << "change " << i;
      ASSERT_EQ(a.changes[scan][i].mean, b.changes[scan][i].mean) << "change " << i;
    }
  }
}

// Batches as large as a scan's are grouped, thinned of clamped free measurements, ordered and reported by
// all the threads, not only updated by them: every figure must still be one thread's.
void expectScanSizedBatchesAlikeOnAnyThreads(CovarianceStorage storage, BatchShape shape) {
  FilterConfig config;
  config.covariance = storage;
  const ScanTrace one = traceScans(config, 1, shape);
  std::size_t early = 0;
  std::size_t heldBack = 0;
  for (const UpdateStats& s : one.stats) {
    early += s.skippedEarly;
    heldBack += s.heldBack;
  }
  EXPECT_GT(heldBack, 1000U);  // the occupied priority held free measurements back
  EXPECT_EQ(one.stats[2].rejected, 5000U);
  if (storage == CovarianceStorage::kCompact) {
    EXPECT_GT(early, 10000U);  // clamped free measurements dropped before ordering
  }
  for (const int threads : {2, 3}) {
    expectSameTrace(one, traceScans(config, threads, shape), threads);
  }
}

TEST(BandedDeterminism, ScanSizedBatchesGiveOneThreadsMapCountsAndChangesOnTwoAndThree) {
  expectScanSizedBatchesAlikeOnAnyThreads(CovarianceStorage::kCompact, BatchShape::kScan);
}

TEST(BandedDeterminism, ScanSizedBatchesGiveOneThreadsMapCountsAndChangesInBandedStorage) {
  expectScanSizedBatchesAlikeOnAnyThreads(CovarianceStorage::kBanded, BatchShape::kScan);
}

TEST(BandedDeterminism, ScanSizedBatchesWithABlockInTwoRunsGiveOneThreadsMap) {
  expectScanSizedBatchesAlikeOnAnyThreads(CovarianceStorage::kCompact, BatchShape::kBlockInTwoRuns);
}

TEST(BandedDeterminism, ShuffledScanSizedBatchesGiveOneThreadsMap) {
  expectScanSizedBatchesAlikeOnAnyThreads(CovarianceStorage::kCompact, BatchShape::kShuffled);
}

// The same scans in their order and shuffled make the same map.
TEST(BandedDeterminism, ScanSizedBatchesGiveTheSameMapInAnyOrder) {
  FilterConfig config;
  config.covariance = CovarianceStorage::kCompact;
  EXPECT_EQ(traceScans(config, 2, BatchShape::kScan).checksums, traceScans(config, 1, BatchShape::kShuffled).checksums);
}

TEST(BandedDeterminism, RejectsBadMeasurementsAndCountsThem) {
  FilterConfig config;
  config.dimensions = 2;
  config.resolution = 1.0;
  auto ogf = BandedOgf::create(config);
  const std::vector<Measurement> batch = {{{0, 0, 0}, 1}, {{1, 0, 3}, 1}, {{2, 0, 0}, 0}, {{3, 0, 0}, -1}};
  const UpdateStats stats = ogf->update(batch);
  EXPECT_EQ(stats.rejected, 2U);
  EXPECT_EQ(stats.applied, 2U);
}

}  // namespace
}  // namespace ogf::filter
