// What BandedOgf::update carries from one stage to the next (a Group per block of the batch, the Batch),
// and each stage's own scratch, kept from batch to batch so a scan allocates nothing once the first ones
// have sized it. Private to the filter's sources: the stages are banded_ogf.cpp's update() in order,
//   1. batch_grouping.cpp       groups by block, rejects, holds back (occupied priority)
//      free_clamp_drop.cpp      drops the free measurements certain to be skipped (compact storage)
//   2. batch_order.cpp          the deterministic order
//   3. block_neighbourhoods.cpp every block the batch touches, allocated; occupied measurements marked
//   4. change_detection.cpp     with a sink, the state before of every cell the batch can change
//   5. measurement_apply.cpp    eq. (5), colour by colour
//   6. change_detection.cpp     with a sink, what changed
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <ogf/core/cell_key.hpp>
#include <ogf/core/huge_pages.hpp>
#include <span>
#include <utility>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/block_key_table.hpp"
#include "ogf/filter/block_storage.hpp"
#include "ogf/filter/change_sink.hpp"
#include "ogf/filter/worker_pool.hpp"

namespace ogf::filter {

// The measurements of a batch in one block.
struct BandedOgf::Group {
  CellKey block;
  std::uint32_t colour = 0;
  std::uint32_t neighbours = 0;  // bit d set: block d of the 3×3×3 neighbourhood is touched
  std::size_t begin = 0;         // range in the sorted measurement keys
  std::size_t end = 0;
  std::uint8_t* marks =
      nullptr;                  // the block's cell marks when it existed before the batch (occupied priority)
  const float* data = nullptr;  // the block's values when it existed before the batch (dropClampedFree)
};

// A block the batch looks up: its key, the block (null while it does not exist) and, with a change sink,
// which of its cells the updates can change (bit per position).
struct BandedOgf::TouchedBlock {
  CellKey key;
  Block* block = nullptr;
  bool written = false;  // obtained for the updates (BlockStorage::obtain: allocated, hash forgotten)
  bool fresh = false;    // allocated by the batch, initialised after all its blocks are (initialiseBlocks)
  std::array<std::uint64_t, 8> cells{};
};

// What the stages hand on: per measurement its group and code (position << 1 | y) from stage 1, the codes
// in the order of application from stage 2, per group the data of its 3×3×3 neighbourhood of blocks from
// stage 3; every block looked up, numbered (the map's table is searched once per block and batch, not once
// per group that neighbours it), and per group and neighbour the block's number.
struct BandedOgf::Batch {
  BlockKeyTable blocks;  // block key → group
  std::vector<std::uint32_t> groupOf;
  std::vector<std::uint16_t> codes;
  // Whether each group's measurements are consecutive in groupOf and codes, the groups in the order they
  // were made (a batch whose blocks came in one run each).
  bool groupsInRuns = false;
  std::vector<std::uint16_t> sorted;
  std::vector<float*> neighbourhoods;
  BlockKeyTable touchedIndex;
  std::vector<TouchedBlock> touched;
  std::vector<std::uint32_t> groupTouched;
  std::vector<std::uint32_t> touchedOrder;  // stage 4: the touched blocks in key order
};

namespace banded {

// Stage 1's: where each run of measurements in one block starts (and the batch's end), and for the
// threads' pass (groupInParallel) per thread its part, then per run its block, whether it holds a
// measurement to accept and its group.
struct GroupingScratch {
  // A thread's share: the runs that start in its part of the batch, their blocks as found in the map and
  // whether they hold a measurement to accept; then where its accepted measurements start, how many it
  // kept and what it counted.
  struct alignas(64) Part {
    std::vector<std::size_t> starts;
    std::vector<Block*> blocks;
    std::vector<std::uint8_t> acceptable;
    std::size_t from = 0;
    std::size_t kept = 0;
    UpdateStats counts;
  };
  std::vector<std::size_t> runs;
  std::vector<Part> parts;
  std::vector<Block*> runBlocks;
  std::vector<std::uint8_t> runAcceptable;
  std::vector<std::uint32_t> runGroups;
};

// dropClampedFree's: per group the cells within reach of an occupied measurement, per group its 27
// neighbours' groups once looked up, and per thread its share.
struct DropScratch {
  // A thread's share: how many of its range it kept, and the drops per group. The shares are written by
  // their threads side by side: a cache line each.
  struct alignas(64) Part {
    std::size_t kept = 0;
    std::size_t dropped = 0;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> groupDrops;
  };
  std::vector<std::array<std::uint64_t, 8>> occupiedReach;
  std::vector<std::uint32_t> around;
  std::vector<Part> parts;
};

// Stage 2's: where each group's measurements start in Batch::codes.
struct OrderScratch {
  std::vector<std::size_t> groupFrom;
};

// Stage 3's: the blocks it allocated, and the groups whose own block is one of them (their occupied
// measurements are marked once the block is initialised).
struct NeighbourhoodScratch {
  std::vector<Block*> freshBlocks;
  std::vector<std::uint32_t> freshOwnGroups;
};

// Stages 4 and 6: the state before the batch of every cell it can change, and what the threads found.
struct ChangeScratch {
  // A z layer of a touched block with cells the updates can change (compact storage).
  struct Layer {
    std::uint32_t touched = 0;  // in Batch::touched
    std::uint32_t layer = 0;
    std::uint64_t cells = 0;  // bit per position in the layer
  };
  // The changes a thread found while the calling one reports to the sink, kept for it in order: at most a
  // share of a scan's changes, 24 bytes each (a first 0.1 m street scan changes 3.4 M cells), in huge pages.
  struct alignas(64) Buffer : ChangeSink {
    std::vector<CellChange, HugePageAllocator<CellChange>> changes;
    void cellChanged(const CellChange& change) override { changes.push_back(change); }
    void cellsChanged(std::span<const CellChange> some) override {
      changes.insert(changes.end(), some.begin(), some.end());
    }
  };
  std::vector<float> meansBefore;              // banded storage: of each touched cell, its mean
  std::vector<std::uint32_t> variancesBefore;  // and its stored variance (storedVarianceAt)
  // Compact storage: the touched layers in block key order, and their 64 means and codes before the batch.
  std::vector<Layer> touchedLayers;
  std::vector<float> layerMeansBefore;
  std::vector<std::uint16_t> layerCodesBefore;
  std::vector<std::array<std::uint64_t, 3>> alongX;  // a group's layers dilated along x, per set of dx
  std::vector<Buffer> keptChanges;                   // per thread after the first, its changes
};

// Stage 5's: applyRun's records on the calling thread.
struct ApplyScratch {
  std::vector<float*> ring;
};

// Block d of the 3×3×3 neighbourhood of `block`, d = (dx+1) + 3(dy+1) + 9(dz+1).
inline CellKey neighbourOf(const CellKey& block, unsigned d) {
  return block +
         CellKey{static_cast<int>(d % 3) - 1, static_cast<int>((d / 3) % 3) - 1, static_cast<int>(d / 9) - 1};
}

}  // namespace banded

struct BandedOgf::Scratch {
  Batch batch;
  banded::GroupingScratch grouping;
  banded::DropScratch drop;
  banded::OrderScratch order;
  banded::NeighbourhoodScratch neighbourhoods;
  banded::ChangeScratch changes;
  banded::ApplyScratch apply;
};

// The number of `blockKey` in Batch::touched, looked up in the map the first time in a batch.
inline std::uint32_t BandedOgf::lookUp(const CellKey& blockKey) {
  Batch& work = scratch_->batch;
  bool inserted = false;
  const auto next = static_cast<std::uint32_t>(work.touched.size());
  const std::uint32_t t = work.touchedIndex.findOrInsert(blockKey, next, inserted);
  if (inserted) {
    work.touched.push_back({blockKey, storage_.find(blockKey), {}});
  }
  return t;
}

template <class Body>
void BandedOgf::shareOut(std::size_t n, bool worthSharing, Body&& body) {
  WorkerPool* threads = worthSharing ? pool() : nullptr;
  if (threads == nullptr) {
    body(std::size_t{0}, n);
    return;
  }
  const EvenSplit split{n, threads->threads()};
  threads->run([&](std::size_t p) { body(split.begin(p), split.begin(p + 1)); });
}

}  // namespace ogf::filter
