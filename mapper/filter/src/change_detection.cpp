// Stages 4 and 6 of BandedOgf::update, with a change sink: before the updates, the state of every cell
// the batch's stencils reach; after them, the cells whose class or quantised probability changed.

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "banded_batch.hpp"
#include "ogf/filter/layer_changes.hpp"

namespace ogf::filter {

namespace {

template <class Visit>
void forEachBit(const std::array<std::uint64_t, 8>& bits, Visit&& visit) {
  for (std::size_t w = 0; w < bits.size(); ++w) {
    for (std::uint64_t rest = bits[w]; rest != 0; rest &= rest - 1) {
      visit(w * 64 + static_cast<std::size_t>(std::countr_zero(rest)));
    }
  }
}

// Bits of each 8-bit row with x in [from, 8), replicated over the 8 rows of a layer.
constexpr std::uint64_t rowsFrom(int from) { return (0xFFULL << from & 0xFFULL) * 0x0101010101010101ULL; }

// A z layer of a block's cells (bit x + 8y) dilated along x by the offsets of `dxs` (bit dx + 8 per dx,
// |dx| ≤ 8, a 2-D stencil's reach): the parts in the block before (index 0), in the block itself (1) and in
// the block after (2).
std::array<std::uint64_t, 3> dilatedAlongX(std::uint64_t w, std::uint32_t dxs) {
  std::array<std::uint64_t, 3> parts{};
  for (std::uint32_t rest = dxs; rest != 0; rest &= rest - 1) {
    const int dx = std::countr_zero(rest) - 8;
    if (dx >= 0) {
      parts[1] |= (w << dx) & rowsFrom(dx);
      parts[2] |= dx == 0 ? 0 : (w >> (8 - dx)) & ~rowsFrom(dx);
    } else {
      parts[1] |= (w >> -dx) & ~rowsFrom(8 + dx);
      parts[0] |= (w << (8 + dx)) & rowsFrom(8 + dx);
    }
  }
  return parts;
}

}  // namespace

void BandedOgf::recordChangeableCells(std::span<const Group> sorted) {
  Batch& work = scratch_->batch;
  // Per neighbour (of the 3×3×3 blocks) and z layer, the group's cells the stencil reaches; kept zero
  // between groups.
  std::array<std::array<std::uint64_t, 8>, 27> reached{};
  for (std::size_t r = 0; r < sorted.size(); ++r) {
    markStencilReach(sorted[r], &work.groupTouched[r * 27], reached);
  }
  std::vector<std::uint32_t>& touchedOrder = work.touchedOrder;
  touchedOrder.resize(work.touched.size());
  for (std::uint32_t t = 0; t < touchedOrder.size(); ++t) {
    touchedOrder[t] = t;
  }
  std::sort(touchedOrder.begin(), touchedOrder.end(),
            [&](std::uint32_t a, std::uint32_t b) { return work.touched[a].key < work.touched[b].key; });
  if (compact()) {
    copyTouchedLayers();
  } else {
    copyTouchedCells();
  }
}

// The cells the stencils of group g's measurements reach, added to the TouchedBlock::cells of its
// neighbourhood (`touchedOfGroup`: the touched block number of each of its 27 neighbours); `reached` is
// zero before and after.
void BandedOgf::markStencilReach(const Group& g, const std::uint32_t* touchedOfGroup,
                                 std::array<std::array<std::uint64_t, 8>, 27>& reached) {
  Batch& work = scratch_->batch;
  banded::ChangeScratch& own = scratch_->changes;
  std::vector<std::array<std::uint64_t, 3>>& alongX = own.alongX;
  // The group's measured positions, dilated by the stencil a row of it at a time: along x once per set of
  // dx (dilatedAlongX), then shifted by the row's dy and dz as whole 8-bit rows and layers.
  std::array<std::uint64_t, 8> measured{};
  for (std::size_t i = g.begin; i < g.end; ++i) {
    const std::size_t l = work.sorted[i] >> 1;
    measured[l >> 6] |= std::uint64_t{1} << (l & 63U);
  }
  alongX.resize(stencilRowSets_.size() * 8);
  for (std::size_t k = 0; k < stencilRowSets_.size(); ++k) {
    for (std::size_t z = 0; z < 8; ++z) {
      alongX[k * 8 + z] =
          measured[z] == 0 ? std::array<std::uint64_t, 3>{} : dilatedAlongX(measured[z], stencilRowSets_[k]);
    }
  }
  std::uint32_t reachedBlocks = 0;
  for (const StencilRow& row : stencilRows_) {
    for (int z = 0; z < 8; ++z) {
      if (measured[static_cast<std::size_t>(z)] == 0) {
        continue;
      }
      const int zz = z + row.dz;
      const int dzb = zz < 0 ? -1 : (zz >= 8 ? 1 : 0);
      const auto layer = static_cast<std::size_t>(zz - 8 * dzb);
      const std::array<std::uint64_t, 3>& parts = alongX[row.set * 8 + static_cast<std::size_t>(z)];
      for (int dxb = -1; dxb <= 1; ++dxb) {
        const std::uint64_t bx = parts[static_cast<std::size_t>(dxb + 1)];
        if (bx == 0) {
          continue;
        }
        // Along y: whole rows of 8 bits, in this block's row of blocks and the next (or previous) one.
        const unsigned here = static_cast<unsigned>((dxb + 1) + 3 + 9 * (dzb + 1));
        const unsigned next = row.dy >= 0 ? here + 3 : here - 3;
        // |dy| = 8 (a 2-D stencil's reach) moves every row into the next row of blocks.
        const std::uint64_t stay =
            row.dy >= 8 || row.dy <= -8 ? 0 : (row.dy >= 0 ? bx << (8 * row.dy) : bx >> (-8 * row.dy));
        const std::uint64_t cross =
            row.dy > 0 ? bx >> (64 - 8 * row.dy) : (row.dy < 0 ? bx << (64 + 8 * row.dy) : 0);
        reached[here][layer] |= stay;
        reached[next][layer] |= cross;
        reachedBlocks |= (std::uint32_t{stay != 0} << here) | (std::uint32_t{cross != 0} << next);
      }
    }
  }
  for (std::uint32_t rest = reachedBlocks; rest != 0; rest &= rest - 1) {
    const auto d = static_cast<unsigned>(std::countr_zero(rest));
    if (((g.neighbours >> d) & 1U) != 0) {
      std::array<std::uint64_t, 8>& cells = work.touched[touchedOfGroup[d]].cells;
      for (std::size_t layer = 0; layer < 8; ++layer) {
        cells[layer] |= reached[d][layer];
      }
    }
    reached[d] = {};
  }
}

void BandedOgf::copyTouchedCells() {
  const Batch& work = scratch_->batch;
  banded::ChangeScratch& own = scratch_->changes;
  // Banded storage: the touched cells' means and stored variances, blocks in key order.
  std::size_t cells = 0;
  for (const TouchedBlock& block : work.touched) {
    for (const std::uint64_t word : block.cells) {
      cells += static_cast<std::size_t>(std::popcount(word));
    }
  }
  own.meansBefore.resize(cells);
  own.variancesBefore.resize(cells);
  std::size_t visited = 0;
  for (const std::uint32_t t : work.touchedOrder) {
    const TouchedBlock& block = work.touched[t];
    const float* data = block.block->data();
    forEachBit(block.cells, [&](std::size_t l) {
      own.meansBefore[visited] = meanAt(data, l);
      own.variancesBefore[visited] = storedVarianceAt(data, l);
      ++visited;
    });
  }
}

// for flushChanges: where each is (touched block << 9 | position), its mean and stored variance after and
// before.
struct BandedOgf::ChangeChunk {
  static constexpr std::size_t kCells = 512;
  std::array<float, kCells> means1;
  std::array<float, kCells> variances1;
  std::array<float, kCells> means0;
  std::array<float, kCells> variances0;
  std::array<std::uint32_t, kCells> stored1;  // the variances as stored, decoded in flushChanges
  std::array<std::uint32_t, kCells> stored0;
  std::array<std::uint32_t, kCells> where;
  std::array<PublishedState, kCells> now;
  std::array<PublishedState, kCells> was;
  std::array<CellChange, kCells> changes;
  std::size_t n = 0;
};

// 6. Reports the cells whose class or quantised probability changed. In compact storage with threads, each
//    takes a share of the touched layers: the calling thread reports the first share to the sink as it
//    goes, the others keep theirs, which follow in order.
void BandedOgf::reportChanges(ChangeSink& sink) {
  if (!compact()) {
    ChangeChunk chunk;
    collectCellChanges(chunk, sink);
    flushChanges(chunk, sink);
    return;
  }
  const std::size_t layers = scratch_->changes.touchedLayers.size();
  WorkerPool* threads = layers >= kParallelLayersMin ? pool() : nullptr;
  const EvenSplit split{layers, threads != nullptr ? threads->threads() : 1};
  std::vector<banded::ChangeScratch::Buffer>& kept = scratch_->changes.keptChanges;
  kept.resize(split.parts);
  const auto report = [&](std::size_t p) {
    ChangeSink& to = p == 0 ? sink : static_cast<ChangeSink&>(kept[p]);
    kept[p].changes.clear();
    ChangeChunk chunk;
    collectLayerChanges(chunk, to, split.begin(p), split.begin(p + 1));
    flushChanges(chunk, to);
  };
  if (threads == nullptr) {
    report(0);
    return;
  }
  threads->run(report);
  for (std::size_t p = 1; p < split.parts; ++p) {
    sink.cellsChanged(kept[p].changes);
  }
}

// Compact storage, a layer at a time (touched layers [e0, e1)): the cells whose mean or code differ from
// the copy, found in vectors, then only those read.
void BandedOgf::collectLayerChanges(ChangeChunk& chunk, ChangeSink& sink, std::size_t e0,
                                    std::size_t e1) const {
  const Batch& work = scratch_->batch;
  const banded::ChangeScratch& own = scratch_->changes;
  const std::size_t cellsPerBlock = storage_.cellsPerBlock();
  const std::vector<banded::ChangeScratch::Layer>& layers = own.touchedLayers;
  if (e0 < e1) {
    prefetchTouchedLayers(e0, e1);
  }
  for (std::size_t e = e0; e < e1; ++e) {
    if (e + 1 < e1 && layers[e + 1].touched != layers[e].touched) {
      prefetchTouchedLayers(e + 1, e1);
    }
    const banded::ChangeScratch::Layer& layer = layers[e];
    const float* data = work.touched[layer.touched].block->data();
    const float* means = data + layer.layer * kLayerCells;
    const auto* codes =
        reinterpret_cast<const std::uint16_t*>(data + cellsPerBlock) + layer.layer * kLayerCells;
    const float* meansCopy = own.layerMeansBefore.data() + e * kLayerCells;
    const std::uint16_t* codesCopy = own.layerCodesBefore.data() + e * kLayerCells;
    const std::uint32_t base = layer.touched << 9 | layer.layer * static_cast<std::uint32_t>(kLayerCells);
    for (std::uint64_t rest = layer.cells & layerChanges_(means, codes, meansCopy, codesCopy); rest != 0;
         rest &= rest - 1) {
      const auto j = static_cast<std::size_t>(std::countr_zero(rest));
      std::size_t& n = chunk.n;
      chunk.means1[n] = means[j];
      chunk.stored1[n] = codes[j];
      chunk.means0[n] = meansCopy[j];
      chunk.stored0[n] = codesCopy[j];
      chunk.where[n] = base | static_cast<std::uint32_t>(j);
      if (++n == ChangeChunk::kCells) {
        flushChanges(chunk, sink);
      }
    }
  }
}

// Banded storage: every touched cell compared with its copy.
void BandedOgf::collectCellChanges(ChangeChunk& chunk, ChangeSink& sink) {
  const Batch& work = scratch_->batch;
  const banded::ChangeScratch& own = scratch_->changes;
  std::size_t visited = 0;
  for (const std::uint32_t t : work.touchedOrder) {
    const TouchedBlock& block = work.touched[t];
    const float* data = block.block->data();
    forEachBit(block.cells, [&](std::size_t l) {
      const float mean = meanAt(data, l);
      const std::uint32_t stored = storedVarianceAt(data, l);
      std::size_t& n = chunk.n;
      chunk.means1[n] = mean;
      chunk.stored1[n] = stored;
      chunk.means0[n] = own.meansBefore[visited];
      chunk.stored0[n] = own.variancesBefore[visited];
      chunk.where[n] = t << 9 | static_cast<std::uint32_t>(l);
      n += static_cast<std::size_t>(
          !(mean == own.meansBefore[visited] && stored == own.variancesBefore[visited]));
      ++visited;
      if (n == ChangeChunk::kCells) {
        flushChanges(chunk, sink);
      }
    });
  }
}

// The chunk's states after and before in one call each, then compared: the cells whose state differs go to
// the sink.
void BandedOgf::flushChanges(ChangeChunk& chunk, ChangeSink& sink) const {
  const std::size_t n = chunk.n;
  for (std::size_t i = 0; i < n; ++i) {
    chunk.variances1[i] = varianceOfStored(chunk.stored1[i]);
    chunk.variances0[i] = varianceOfStored(chunk.stored0[i]);
  }
  published_.statesOf(std::span(chunk.means1).first(n), std::span(chunk.variances1).first(n),
                      std::span(chunk.now).first(n));
  published_.statesOf(std::span(chunk.means0).first(n), std::span(chunk.variances0).first(n),
                      std::span(chunk.was).first(n));
  std::size_t changed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    CellChange& c = chunk.changes[changed];
    c.key = storage_.cellKey(scratch_->batch.touched[chunk.where[i] >> 9].key, chunk.where[i] & 511U);
    c.mean = chunk.means1[i];
    c.variance = chunk.variances1[i];
    c.quantisedProbability = chunk.now[i].quantisedProbability;
    c.occupancyClass = chunk.now[i].occupancyClass;
    changed += static_cast<std::size_t>(!(chunk.now[i] == chunk.was[i]));
  }
  sink.cellsChanged(std::span(chunk.changes).first(changed));
  chunk.n = 0;
}

void BandedOgf::copyTouchedLayers() {
  const Batch& work = scratch_->batch;
  banded::ChangeScratch& own = scratch_->changes;
  // The touched layers in block key order, then their means and codes copied before the updates (by the
  // threads, a share of the layers each, where there are enough).
  std::vector<banded::ChangeScratch::Layer>& layers = own.touchedLayers;
  layers.clear();
  for (const std::uint32_t t : work.touchedOrder) {
    const std::array<std::uint64_t, 8>& cells = work.touched[t].cells;
    for (std::uint32_t layer = 0; layer < cells.size(); ++layer) {
      if (cells[layer] != 0) {
        layers.push_back({t, layer, cells[layer]});
      }
    }
  }
  own.layerMeansBefore.resize(layers.size() * kLayerCells);
  own.layerCodesBefore.resize(layers.size() * kLayerCells);
  const std::size_t cellsPerBlock = storage_.cellsPerBlock();
  const auto copyLayers = [&](std::size_t e0, std::size_t e1) {
    if (e0 < e1) {
      prefetchTouchedLayers(e0, e1);
    }
    for (std::size_t e = e0; e < e1; ++e) {
      if (e + 1 < e1 && layers[e + 1].touched != layers[e].touched) {
        prefetchTouchedLayers(e + 1, e1);
      }
      const float* data = work.touched[layers[e].touched].block->data();
      const auto* codes = reinterpret_cast<const std::uint16_t*>(data + cellsPerBlock);
      std::memcpy(own.layerMeansBefore.data() + e * kLayerCells, data + layers[e].layer * kLayerCells,
                  kLayerCells * sizeof(float));
      std::memcpy(own.layerCodesBefore.data() + e * kLayerCells, codes + layers[e].layer * kLayerCells,
                  kLayerCells * sizeof(std::uint16_t));
    }
  };
  shareOut(layers.size(), layers.size() >= kParallelLayersMin, copyLayers);
}

void BandedOgf::prefetchTouchedLayers(std::size_t e, std::size_t end) const {
  const Batch& work = scratch_->batch;
  const banded::ChangeScratch& own = scratch_->changes;
  // The touched layers of the block whose first touched layer is e (up to `end`): a layer's 64 means take
  // four cache lines, their variance codes two.
  const std::vector<banded::ChangeScratch::Layer>& layers = own.touchedLayers;
  const std::uint32_t t = layers[e].touched;
  const float* data = work.touched[t].block->data();
  const auto* codes = reinterpret_cast<const std::uint16_t*>(data + storage_.cellsPerBlock());
  for (; e < end && layers[e].touched == t; ++e) {
    const std::size_t first = layers[e].layer * kLayerCells;
    for (std::size_t line = 0; line < 4; ++line) {
      __builtin_prefetch(data + first + line * 16);
    }
    __builtin_prefetch(codes + first);
    __builtin_prefetch(codes + first + 32);
  }
}

}  // namespace ogf::filter
