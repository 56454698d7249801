// Memory and speed of delta::PublishedMap, the state ogf-mapper has published and every client rebuilds.
// Memory: the map is filled with `cells` cells in one of three shapes, and the growth of the heap in use
// (mallinfo2: bytes malloc handed out, headers included, plus mmapped chunks such as large bucket arrays) and
// of the resident set (/proc/self/statm) is divided by the cell count. The heap figure is the exact one; the
// resident figure shows what the operating system sees, and only the first iteration of a fresh process
// grows it (freed memory is reused after that), hence one iteration. Time: set() per cell, for cells new to
// the map and for overwrites of cells it holds, in a scan-sized batch; and DeltaStream::update, which the
// daemon calls once per scan with the changed cells; and sortedCells(), which every keyframe starts with.
#include <benchmark/benchmark.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <memory>
#include <random>
#include <vector>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/delta/published_map.hpp"

namespace {

using ogf::CellKey;
using ogf::delta::PublishedCell;
using ogf::delta::PublishedMap;

// The cell shapes a published map takes. kVolume: every cell of a 3-D box (what free-space rays sweep);
// kPlane: a square at z = 0 (a 2-D map); kShell: only the six faces of 3-D boxes (walls, floor and
// ceiling without the space between them: the sparsest block fill a lidar map plausibly has).
enum Shape : int { kVolume = 0, kPlane = 1, kShell = 2 };

// `count` distinct cells of the shape, around the origin (negative keys included), in the order given.
std::vector<CellKey> cellsOf(Shape shape, std::size_t count) {
  std::vector<CellKey> keys;
  keys.reserve(count);
  if (shape == kPlane) {
    for (std::int32_t x = -1024; keys.size() < count; ++x)
      for (std::int32_t y = -1024; y < 1024 && keys.size() < count; ++y) keys.push_back({x, y, 0});
  } else if (shape == kVolume) {
    for (std::int32_t x = -512; keys.size() < count; ++x)
      for (std::int32_t y = -256; y < 256 && keys.size() < count; ++y)
        for (std::int32_t z = -8; z < 24 && keys.size() < count; ++z) keys.push_back({x, y, z});
  } else {
    // Rooms of 40 × 40 × 30 cells side by side along x, each contributing its surface.
    constexpr std::int32_t kSide = 40, kHeight = 30;
    for (std::int32_t room = -200; keys.size() < count; ++room)
      for (std::int32_t x = room * kSide; x < (room + 1) * kSide && keys.size() < count; ++x)
        for (std::int32_t y = 0; y < kSide && keys.size() < count; ++y)
          for (std::int32_t z = 0; z < kHeight && keys.size() < count; ++z) {
            const bool face = x == room * kSide || x == (room + 1) * kSide - 1 || y == 0 || y == kSide - 1 ||
                              z == 0 || z == kHeight - 1;
            if (face) keys.push_back({x, y, z});
          }
  }
  return keys;
}

PublishedCell cellAt(const CellKey& k, std::uint32_t salt) {
  const auto p = static_cast<std::int16_t>((static_cast<std::uint32_t>(k.x * 31 + k.y * 17 + k.z) + salt) % 30001U);
  return {k, p, static_cast<std::int8_t>(p % 3), static_cast<float>(p) * 1e-5f};
}

std::int64_t heapInUse() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<std::int64_t>(m.uordblks + m.hblkhd);
}

std::int64_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  std::int64_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * sysconf(_SC_PAGESIZE);
}

// Args: shape, cells.
void BM_MemoryPerCell(benchmark::State& state) {
  const auto shape = static_cast<Shape>(state.range(0));
  const auto count = static_cast<std::size_t>(state.range(1));
  const std::vector<CellKey> keys = cellsOf(shape, count);
  double heapPerCell = 0.0, residentPerCell = 0.0;
  for (auto _ : state) {
    const std::int64_t heap0 = heapInUse(), rss0 = residentBytes();
    auto map = std::make_unique<PublishedMap>();
    for (const CellKey& k : keys) map->set(cellAt(k, 0));
    benchmark::DoNotOptimize(map->checksum());
    heapPerCell = static_cast<double>(heapInUse() - heap0) / static_cast<double>(count);
    residentPerCell = static_cast<double>(residentBytes() - rss0) / static_cast<double>(count);
    state.PauseTiming();
    map.reset();
    state.ResumeTiming();
  }
  state.counters["heap_bytes_per_cell"] = heapPerCell;
  state.counters["rss_bytes_per_cell"] = residentPerCell;
  state.counters["ns_per_set"] =
      benchmark::Counter(static_cast<double>(count) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// A scan's worth of changed cells: `batch` cells of the shape in random order. The filter reports a scan's
// changes block by block, each block's cells in order, so this is the worst case for the slab look-ups;
// `ogf-bench-octomap --deltas` prints what the delta stream costs on a street scan in the filter's order.
std::vector<PublishedCell> scanBatch(Shape shape, std::size_t batch, std::uint32_t salt) {
  std::vector<CellKey> keys = cellsOf(shape, batch);
  std::mt19937 rng(42);
  std::shuffle(keys.begin(), keys.end(), rng);
  std::vector<PublishedCell> cells;
  cells.reserve(batch);
  for (const CellKey& k : keys) cells.push_back(cellAt(k, salt));
  return cells;
}

void reportPerSet(benchmark::State& state, std::size_t batch) {
  state.counters["ns_per_set"] =
      benchmark::Counter(static_cast<double>(batch) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(batch));
}

// set() of cells the map does not hold yet (a fresh map per iteration, built and freed outside the timing).
// Args: shape, batch.
void BM_SetNew(benchmark::State& state) {
  const auto batch = static_cast<std::size_t>(state.range(1));
  const auto cells = scanBatch(static_cast<Shape>(state.range(0)), batch, 1);
  for (auto _ : state) {
    state.PauseTiming();
    auto map = std::make_unique<PublishedMap>();
    state.ResumeTiming();
    for (const PublishedCell& c : cells) map->set(c);
    benchmark::DoNotOptimize(map->checksum());
    state.PauseTiming();
    map.reset();
    state.ResumeTiming();
  }
  reportPerSet(state, batch);
}

// set() of cells the map already holds, with other values (alternating two batches).
void BM_SetOverwrite(benchmark::State& state) {
  const auto batch = static_cast<std::size_t>(state.range(1));
  const auto shape = static_cast<Shape>(state.range(0));
  const auto a = scanBatch(shape, batch, 1), b = scanBatch(shape, batch, 2);
  PublishedMap map;
  for (const PublishedCell& c : a) map.set(c);
  bool odd = false;
  for (auto _ : state) {
    for (const PublishedCell& c : odd ? a : b) map.set(c);
    odd = !odd;
    benchmark::DoNotOptimize(map.checksum());
  }
  reportPerSet(state, batch);
}

// DeltaStream::update with every candidate visibly changed, on a stream already holding the cells.
void BM_DeltaStreamUpdate(benchmark::State& state) {
  const auto batch = static_cast<std::size_t>(state.range(1));
  const auto shape = static_cast<Shape>(state.range(0));
  const auto a = scanBatch(shape, batch, 1), b = scanBatch(shape, batch, 2);
  ogf::delta::DeltaStream stream({0.1, 1, ogf::messages::kMaxDeltaCellsPerMessage});
  stream.update(0, a);
  bool odd = false;
  std::int64_t utime = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(stream.update(++utime, odd ? a : b));
    odd = !odd;
  }
  reportPerSet(state, batch);
}

// sortedCells() of a map of `cells` cells: the cost of a keyframe before it is split into messages.
void BM_SortedCells(benchmark::State& state) {
  const auto count = static_cast<std::size_t>(state.range(1));
  PublishedMap map;
  for (const PublishedCell& c : scanBatch(static_cast<Shape>(state.range(0)), count, 1)) map.set(c);
  for (auto _ : state) benchmark::DoNotOptimize(map.sortedCells());
  state.counters["ns_per_cell"] =
      benchmark::Counter(static_cast<double>(count) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void shapes(benchmark::internal::Benchmark* b, std::int64_t cells) {
  b->ArgNames({"shape", "cells"});
  for (int shape : {kVolume, kPlane, kShell}) b->Args({shape, cells});
  b->Unit(benchmark::kMillisecond);
}

}  // namespace

BENCHMARK(BM_MemoryPerCell)->Apply([](auto* b) { shapes(b, 2'000'000); })->Iterations(1);
BENCHMARK(BM_SetNew)->Apply([](auto* b) { shapes(b, 300'000); });
BENCHMARK(BM_SetOverwrite)->Apply([](auto* b) { shapes(b, 300'000); });
BENCHMARK(BM_DeltaStreamUpdate)->Apply([](auto* b) { shapes(b, 300'000); });
BENCHMARK(BM_SortedCells)->Apply([](auto* b) { shapes(b, 2'000'000); });

BENCHMARK_MAIN();
