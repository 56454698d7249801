// The banded OGF: construction, update()'s stages in order (each in its own file: src/banded_batch.hpp),
// and what reads the map or changes its policy.
#include "ogf/filter/banded_ogf.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "banded_batch.hpp"
#include "ogf/filter/variance_code.hpp"

namespace ogf::filter {

Result<BandedOgf> BandedOgf::create(const FilterConfig& config) {
  auto resolved = config.resolved();
  if (!resolved) {
    return resolved.error();
  }
  return BandedOgf(*resolved);
}

BandedOgf::BandedOgf(BandedOgf&&) noexcept = default;
BandedOgf& BandedOgf::operator=(BandedOgf&&) noexcept = default;
BandedOgf::~BandedOgf() = default;

BandedOgf::BandedOgf(const FilterConfig& resolved)
    : config_(resolved),
      prior_(resolved.prior()),
      stencil_(resolved.dimensions, resolved.stencilShape()),
      storage_(resolved.dimensions, floatsPerBlockOf(resolved.dimensions, resolved.covariance, stencil_)),
      published_(resolved.occupiedThreshold, resolved.freeThreshold),
      band_(stencil_, resolved.dimensions, resolved.covariance),
      locate_(resolved.covariance == CovarianceStorage::kBanded ? bandLocateFor(band_) : &compactBandLocate),
      kernel_(resolved.covariance == CovarianceStorage::kBanded ? bandKernelFor(band_)
                                                                : compactBandKernelFor(band_)),
      layerChanges_(layerChangesFor(cpuHasFma())),
      scratch_(std::make_unique<Scratch>()) {
  if (resolved.covariance == CovarianceStorage::kBanded) {
    for (const CellKey& o : stencil_.forwardOffsets()) {
      priorSlots_.push_back(static_cast<float>(prior_(o)));
    }
  } else {
    for (const CellKey& o : stencil_.offsets()) {
      band_.correlation.push_back(static_cast<float>(prior_(o)));
    }
    band_.priorVariance = static_cast<float>(prior_.variance());
  }
  priorVariance_ = static_cast<float>(prior_.variance());
  varianceFloor_ = priorVariance_ * 1e-9F;
  if (compact()) {
    inverseScales_.resize(std::size_t{1} << 16);
    for (std::size_t c = 0; c < inverseScales_.size(); ++c) {
      const double var =
          static_cast<double>(priorVariance_ * decodeVarianceRatio(static_cast<std::uint16_t>(c)));
      inverseScales_[c] = 1.0 / std::sqrt(1.0 + var);
    }
  }
  dropsClampedFree_ = compact() && std::ranges::all_of(band_.correlation, [](float c) { return c >= 0.0F; });
  derivePolicyState();
  // Same-colour blocks are one block apart: their measurements touch disjoint cells iff 2·extent ≤ B.
  parallelSafe_ = 2 * stencil_.extent() <= kBlockSide;
  // The stencil by rows along x: per (dy, dz), the set of its dx (bit dx + 8), and the distinct sets.
  for (const CellKey& o : stencil_.offsets()) {
    const std::uint32_t bit = 1U << static_cast<unsigned>(o.x + 8);
    const auto it = std::ranges::find_if(
        stencilRows_, [&](const StencilRow& row) { return row.dy == o.y && row.dz == o.z; });
    if (it == stencilRows_.end()) {
      stencilRows_.push_back({o.y, o.z, bit});
    } else {
      it->set |= bit;  // the set itself until every offset is in
    }
  }
  for (StencilRow& row : stencilRows_) {
    const std::uint32_t dxs = row.set;
    auto it = std::ranges::find(stencilRowSets_, dxs);
    if (it == stencilRowSets_.end()) {
      stencilRowSets_.push_back(dxs);
      it = stencilRowSets_.end() - 1;
    }
    row.set = static_cast<std::uint32_t>(it - stencilRowSets_.begin());
  }
  // Which neighbouring blocks a measurement at each local position reaches.
  const int e = stencil_.extent();
  const bool flat = config_.dimensions == 2;
  neighbourMask_.resize(storage_.cellsPerBlock());
  for (std::size_t l = 0; l < neighbourMask_.size(); ++l) {
    const int local[3] = {static_cast<int>(l & 7U), static_cast<int>((l >> 3) & 7U),
                          static_cast<int>(l >> 6)};
    int lo[3];
    int hi[3];
    for (int a = 0; a < 3; ++a) {
      const int reach = (a == 2 && flat) ? 0 : e;
      lo[a] = (local[a] - reach) >> 3;
      hi[a] = (local[a] + reach) >> 3;
    }
    std::uint32_t mask = 0;
    for (int dz = lo[2]; dz <= hi[2]; ++dz) {
      for (int dy = lo[1]; dy <= hi[1]; ++dy) {
        for (int dx = lo[0]; dx <= hi[0]; ++dx) {
          mask |= 1U << static_cast<unsigned>((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1));
        }
      }
    }
    neighbourMask_[l] = mask;
  }
}

std::size_t BandedOgf::floatsPerBlockOf(int dimensions, CovarianceStorage storage, const Stencil& stencil) {
  const std::size_t cells = dimensions == 3 ? 512 : 64;
  // Compact: a float mean and a 16-bit variance code per cell.
  return storage == CovarianceStorage::kCompact ? cells + cells / 2
                                                : cells * (2 + stencil.forwardOffsets().size());
}

void BandedOgf::initialiseBlock(Block& block) {
  block.clearMarks();
  if (compact()) {
    const std::size_t cells = block.cells();
    std::fill_n(block.data(), cells, 0.0F);
    std::fill_n(reinterpret_cast<std::uint16_t*>(block.data() + cells), cells, encodeVarianceRatio(1.0F));
    return;
  }
  // The prior record in the first cell, then copied over the block in doubling steps.
  float* d = block.data();
  d[0] = 0.0F;
  d[1] = priorVariance_;
  std::copy(priorSlots_.begin(), priorSlots_.end(), d + 2);
  const std::size_t total = block.values().size();
  for (std::size_t done = floatsPerCell(); done < total; done *= 2) {
    std::memcpy(d + done, d, std::min(done, total - done) * sizeof(float));
  }
}

WorkerPool* BandedOgf::pool() {
  if (config_.threads <= 1) {
    return nullptr;
  }
  if (pool_ == nullptr || pool_->threads() != static_cast<std::size_t>(config_.threads)) {
    pool_ = std::make_unique<WorkerPool>(config_.threads);
  }
  return pool_.get();
}

void BandedOgf::initialiseBlocks(std::span<Block* const> blocks) {
  const auto initialise = [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      initialiseBlock(*blocks[b]);
    }
  };
  // In allocation order, so each thread writes its own run of the arena's pages.
  shareOut(blocks.size(), blocks.size() >= kParallelBlocksMin, initialise);
}

// The stages of a batch, in order; the change detection (recordChangeableCells, reportChanges) only with a
// sink.
UpdateStats BandedOgf::update(std::span<const Measurement> batch, ChangeSink* sink) {
  UpdateStats stats;
  std::vector<Group> groups = groupByBlock(batch, stats);
  if (dropsClampedFree_ && skipsClampedEarly_ && std::isfinite(freeClampZ_)) {
    dropClampedFree(groups, stats);
  }
  const std::vector<Group> sorted = orderGroups(groups);
  obtainNeighbourhoods(sorted, stats);
  scratch_->batch.touchedOrder.clear();
  if (sink != nullptr) {
    recordChangeableCells(sorted);
  }
  applyColours(sorted, stats);
  if (sink != nullptr) {
    reportChanges(*sink);
  }
  return stats;
}

BandedOgf BandedOgf::withCovarianceStorage(CovarianceStorage storage) const {
  FilterConfig config = config_;
  config.covariance = storage;
  BandedOgf out(config);  // config_ is resolved and valid; only the storage differs
  const double v0 = prior_.variance();
  std::vector<float> values;
  for (const CellKey& key : storage_.sortedKeys()) {
    const Block* b = storage_.find(key);
    values.clear();
    for (std::size_t l = 0; l < b->cells(); ++l) {
      const Moments c = momentsAt(b->data(), l);
      values.push_back(c.mean);
      values.push_back(c.variance);
      if (storage == CovarianceStorage::kBanded) {
        const CellKey cell = storage_.cellKey(key, l);
        for (const CellKey& o : stencil_.forwardOffsets()) {
          const double other = estimate(cell + o).variance;
          values.push_back(
              static_cast<float>(prior_(o) * (static_cast<double>(c.variance) / v0) * (other / v0)));
        }
      }
    }
    static_cast<void>(out.restoreBlock(key, values, b->marks()));  // same keys, sizes of `out`'s layout
  }
  return out;
}

Status BandedOgf::adoptPolicy(const FilterConfig& config) {
  FilterConfig next = config_;
  next.occupiedThreshold = config.occupiedThreshold;
  next.freeThreshold = config.freeThreshold;
  next.skipTolerance = config.skipTolerance;
  next.clampZ = config.clampZ;
  next.freeClampZ = config.freeClampZ;
  next.occupiedPriority = config.occupiedPriority;
  next.freeReleaseCount = config.freeReleaseCount;
  next.threads = config.threads;
  // Only the policy changed: the structure (and its prior's certificate) is the map's own.
  if (auto st = next.validatePolicy(); !st) {
    return st;
  }
  config_ = next;
  derivePolicyState();
  return okStatus();
}

void BandedOgf::derivePolicyState() {
  published_ = PublishedStateRule(config_.occupiedThreshold, config_.freeThreshold);
  clampZ_ = config_.clampZ > 0.0 ? config_.clampZ : std::numeric_limits<double>::infinity();
  freeClampZ_ =
      config_.clampZ > 0.0 && config_.freeClampZ > 0.0 ? std::min(clampZ_, config_.freeClampZ) : clampZ_;
}

CellEstimate BandedOgf::estimate(const CellKey& cell) const {
  const Block* b = storage_.find(blockKeyOf(cell));
  if (b == nullptr || (config_.dimensions == 2 && cell.z != 0)) {
    return {0.0, prior_.variance(), false};
  }
  const Moments c = momentsAt(b->data(), localIndexOf(cell));
  return {static_cast<double>(c.mean), static_cast<double>(c.variance), true};
}

double BandedOgf::covariance(const CellKey& a, const CellKey& b) const {
  if (a == b) {
    return estimate(a).variance;
  }
  const CellKey o = b - a;
  const bool forward = isForward(o);
  const CellKey& owner = forward ? a : b;
  const int slot = stencil_.forwardIndexOf(forward ? o : a - b);
  if (slot < 0) {
    return 0.0;
  }
  if (compact()) {
    // The prior's covariance scaled by both cells' variance ratios (FilterConfig::covariance).
    const double v0 = prior_.variance();
    return prior_(o) * (estimate(a).variance / v0) * (estimate(b).variance / v0);
  }
  const Block* blk = storage_.find(blockKeyOf(owner));
  if (blk == nullptr) {
    return prior_(o);
  }
  return static_cast<double>(
      blk->data()[localIndexOf(owner) * floatsPerCell() + 2 + static_cast<std::size_t>(slot)]);
}

void BandedOgf::forEachCell(const std::function<void(const CellKey&, float, float)>& visit) const {
  const int side = kBlockSide;
  const int zSide = config_.dimensions == 3 ? kBlockSide : 1;
  for (const CellKey& key : storage_.sortedKeys()) {
    const float* d = storage_.find(key)->data();
    for (int x = 0; x < side; ++x) {
      for (int y = 0; y < side; ++y) {
        for (int z = 0; z < zSide; ++z) {
          const auto l = static_cast<std::size_t>(x + side * (y + side * z));
          const Moments c = momentsAt(d, l);
          visit(CellKey{key.x * side + x, key.y * side + y, key.z * side + z}, c.mean, c.variance);
        }
      }
    }
  }
}

std::size_t BandedOgf::memoryBytes() const {
  return storage_.memoryBytes() + sizeof(*this) +
         stencil_.offsets().size() * (sizeof(CellKey) + 3 * sizeof(std::int32_t) + 2 * sizeof(std::int16_t)) +
         stencil_.pairs().size() * sizeof(StencilPair);
}

}  // namespace ogf::filter
