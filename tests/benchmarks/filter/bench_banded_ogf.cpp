// Cost of one measurement of the banded OGF in 3-D, free (y = -1) and occupied (y = +1), for stencil radii
// R = 1, √2, √3, 2 (plain balls) and the default stencil (√2 ball + Manhattan radius 2), on one and two
// threads; memory per allocated cell. Each iteration applies a scan-sized batch of first measurements to a
// fresh map (the map is rebuilt outside the timing), so every update is applied, none skipped, and the
// blocks they reach are allocated in the timing; a second benchmark times the update alone on allocated
// blocks, a third re-measures a static scene, where agreeing measurements are clamped. ns_per_measurement is CPU
// time on one thread and wall time on two.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"

namespace {

using ogf::CellKey;
using ogf::filter::BandedOgf;
using ogf::filter::FilterConfig;
using ogf::filter::Measurement;

constexpr std::size_t kBatch = 32768;

// Half of the cells of a 64 × 64 × 16 box, each once, in random order (a scan's measurement set).
std::vector<Measurement> scanBatch(std::int8_t y) {
  std::mt19937 rng(42);
  std::vector<Measurement> batch;
  std::set<CellKey> seen;
  while (batch.size() < kBatch) {
    const CellKey k{static_cast<int>(rng() % 64U), static_cast<int>(rng() % 64U), static_cast<int>(rng() % 16U)};
    if (seen.insert(k).second) {
      batch.push_back({k, y});
    }
  }
  return batch;
}

// What every benchmark here reports of its batches: time per measurement, measurements per second, and the
// fraction skipped (below the tolerance or clamped). The same counters in all of them, since the CSV
// reporter takes its columns from the first benchmark's counters and aborts on a counter it has not seen.
void reportMeasurements(benchmark::State& state, std::size_t skipped) {
  const auto measurements = state.iterations() * static_cast<std::int64_t>(kBatch);
  state.counters["ns_per_measurement"] =
      benchmark::Counter(static_cast<double>(kBatch) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["skipped_fraction"] = static_cast<double>(skipped) / static_cast<double>(measurements);
  state.SetItemsProcessed(measurements);
}

// R² > 0: a ball of that radius, banded storage; 0: the default stencil, banded; -1: the default stencil,
// compact storage (what the mapping programs use); -2: the √2 ball in compact storage (Manhattan radius 0,
// the lean stencil of docs/mapping.md).
FilterConfig configFor(int radiusSquared, int threads) {
  FilterConfig config;  // 3-D, 0.2 m cells, σ = 0.1 m
  config.threads = threads;
  if (radiusSquared < 0) {
    config.covariance = ogf::filter::CovarianceStorage::kCompact;
  }
  if (radiusSquared > 0) {
    config.stencilRadius = std::sqrt(static_cast<double>(radiusSquared));
    config.stencilManhattanRadius = 0;
  }
  if (radiusSquared == -2) {
    config.stencilManhattanRadius = 0;
  }
  return config;
}

// Args: R² (0 = the default stencil, -1 the same in compact storage, -2 the lean stencil), y, threads.
void BM_FirstMeasurement(benchmark::State& state) {
  const auto y = static_cast<std::int8_t>(state.range(1));
  const FilterConfig config = configFor(static_cast<int>(state.range(0)), static_cast<int>(state.range(2)));
  const std::vector<Measurement> batch = scanBatch(y);
  double bytesPerCell = 0.0;
  std::size_t skipped = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto map = BandedOgf::create(config);
    state.ResumeTiming();
    const auto stats = map->update(batch);
    benchmark::DoNotOptimize(stats);
    state.PauseTiming();
    skipped += stats.skipped;
    bytesPerCell = static_cast<double>(map->memoryBytes()) / static_cast<double>(map->allocatedCells());
    map = ogf::Error{};  // free outside the timing
    state.ResumeTiming();
  }
  state.counters["bytes_per_cell"] = bytesPerCell;
  reportMeasurements(state, skipped);
}

// The update alone: the same batch on a map whose blocks the batch has already allocated (one warm-up
// pass), with clamping and the skip tolerance off so every update is applied. Each iteration continues the
// same map (the cells' values drift, the cost does not).
void BM_AllocatedMeasurement(benchmark::State& state) {
  FilterConfig config = configFor(static_cast<int>(state.range(0)), static_cast<int>(state.range(2)));
  config.clampZ = 0.0;
  config.skipTolerance = 0.0;
  const std::vector<Measurement> batch = scanBatch(static_cast<std::int8_t>(state.range(1)));
  auto map = BandedOgf::create(config);
  map->update(batch);
  std::size_t skipped = 0;
  for (auto _ : state) {
    const auto stats = map->update(batch);
    skipped += stats.skipped;
  }
  reportMeasurements(state, skipped);
}

// A static scene measured again and again after `passes` warm-up passes: as the cells converge, more and
// more updates fall below the skip tolerance.
void BM_RepeatedMeasurement(benchmark::State& state) {
  const FilterConfig config = configFor(static_cast<int>(state.range(0)), static_cast<int>(state.range(2)));
  std::vector<Measurement> batch = scanBatch(static_cast<std::int8_t>(state.range(1)));
  auto map = BandedOgf::create(config);
  for (std::int64_t pass = 0; pass < state.range(3); ++pass) {
    map->update(batch);
  }
  std::size_t skipped = 0;
  for (auto _ : state) {
    const auto stats = map->update(batch);
    skipped += stats.skipped;
  }
  reportMeasurements(state, skipped);
}

// One thread: CPU time, which a busy shared machine inflates far less than wall time. Two threads: wall
// time (the main thread's CPU time would leave out the worker's).
void stencilsOnThreads(benchmark::internal::Benchmark* b, int threads) {
  b->ArgNames({"R2", "y", "threads"});
  for (int r2 : {1, 2, 3, 4, 0, -1, -2}) {
    for (int y : {-1, 1}) {
      b->Args({r2, y, threads});
    }
  }
  b->Unit(benchmark::kMillisecond);
  if (threads > 1) {
    b->UseRealTime();
  }
}
void oneThread(benchmark::internal::Benchmark* b) { stencilsOnThreads(b, 1); }
void twoThreads(benchmark::internal::Benchmark* b) { stencilsOnThreads(b, 2); }

BENCHMARK(BM_FirstMeasurement)->Apply(oneThread);
BENCHMARK(BM_FirstMeasurement)->Apply(twoThreads);
BENCHMARK(BM_AllocatedMeasurement)->Apply(oneThread);
BENCHMARK(BM_AllocatedMeasurement)->Apply(twoThreads);
BENCHMARK(BM_RepeatedMeasurement)
    ->ArgNames({"R2", "y", "threads", "passes"})
    ->Args({0, -1, 1, 10})
    ->Args({0, 1, 1, 10})
    ->Args({0, -1, 1, 200})
    ->Args({0, 1, 1, 200})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
