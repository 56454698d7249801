// The banded OGF: batch ordering, block allocation, the coloured parallel sweep and the rank-1 update of
// eq. (5) restricted to the stencil.
#include "ogf/filter/banded_ogf.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>
#include <utility>

#include "ogf/filter/map_checksum.hpp"
#include "ogf/filter/occupancy.hpp"
#include "ogf/filter/probit_update.hpp"

namespace ogf::filter {

namespace {

// Beyond this z the update is below 1e-22 of the prior: skipped without evaluating λ when skipping is on.
constexpr double kCertainZ = 10.0;
constexpr std::size_t kSelfBlock = 13;  // (1, 1, 1) in the 3×3×3 neighbourhood of blocks

std::uint32_t colourOf(const CellKey& blockKey) {
  return static_cast<std::uint32_t>((blockKey.x & 1) | ((blockKey.y & 1) << 1) | ((blockKey.z & 1) << 2));
}

}  // namespace

// One measurement of a batch, with where it lives.
struct BandedOgf::Item {
  std::uint32_t colour = 0;
  CellKey block;
  CellKey cell;
  std::uint32_t neighbours = 0;  // bit d set: block d of the 3×3×3 neighbourhood is touched
  std::int8_t y = 1;
};

// A run of items in one block.
struct BandedOgf::Group {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::uint32_t neighbours = 0;
};

Result<BandedOgf> BandedOgf::create(const FilterConfig& config) {
  auto resolved = config.resolved();
  if (!resolved) {
    return resolved.error();
  }
  return BandedOgf(*resolved);
}

BandedOgf::BandedOgf(const FilterConfig& resolved)
    : config_(resolved), prior_(resolved.prior()), stencil_(resolved.dimensions, resolved.stencilShape()),
      storage_(resolved.dimensions, stencil_.forwardOffsets().size()) {
  for (const CellKey& o : stencil_.forwardOffsets()) {
    priorSlots_.push_back(static_cast<float>(prior_(o)));
  }
  priorVariance_ = static_cast<float>(prior_.variance());
  varianceFloor_ = priorVariance_ * 1e-9F;
  for (const CellKey& o : stencil_.offsets()) {
    offsetX_.push_back(o.x);
    offsetY_.push_back(o.y);
    offsetZ_.push_back(o.z);
  }
  // Same-colour blocks are one block apart: their measurements touch disjoint cells iff 2·extent ≤ B.
  parallelSafe_ = 2 * stencil_.extent() <= kBlockSide;
}

void BandedOgf::initialiseBlock(Block& block) {
  const std::size_t n = block.cells();
  float* d = block.data();
  std::fill(d, d + n, 0.0F);
  std::fill(d + n, d + 2 * n, priorVariance_);
  for (std::size_t f = 0; f < priorSlots_.size(); ++f) {
    std::fill(d + (2 + f) * n, d + (3 + f) * n, priorSlots_[f]);
  }
}

Block& BandedOgf::obtainBlock(const CellKey& blockKey, std::size_t& allocated) {
  bool fresh = false;
  Block& block = storage_.obtain(blockKey, fresh);
  if (fresh) {
    initialiseBlock(block);
    ++allocated;
  }
  return block;
}

UpdateStats BandedOgf::update(std::span<const Measurement> batch, ChangeSink* sink) {
  UpdateStats stats;
  const int e = stencil_.extent();
  const bool flat = config_.dimensions == 2;

  // 1. The deterministic order: colour, block, cell.
  std::vector<Item> items;
  items.reserve(batch.size());
  for (const Measurement& m : batch) {
    if ((m.y != 1 && m.y != -1) || (flat && m.key.z != 0)) {
      ++stats.rejected;
      continue;
    }
    Item it;
    it.cell = m.key;
    it.block = blockKeyOf(m.key);
    it.colour = colourOf(it.block);
    it.y = m.y;
    const int local[3] = {m.key.x & 7, m.key.y & 7, flat ? 0 : (m.key.z & 7)};
    int lo[3];
    int hi[3];
    for (int a = 0; a < 3; ++a) {
      const int reach = (a == 2 && flat) ? 0 : e;
      lo[a] = (local[a] - reach) >> 3;
      hi[a] = (local[a] + reach) >> 3;
    }
    for (int dz = lo[2]; dz <= hi[2]; ++dz) {
      for (int dy = lo[1]; dy <= hi[1]; ++dy) {
        for (int dx = lo[0]; dx <= hi[0]; ++dx) {
          it.neighbours |= 1U << static_cast<unsigned>((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1));
        }
      }
    }
    items.push_back(it);
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    if (a.colour != b.colour) {
      return a.colour < b.colour;
    }
    if (a.block != b.block) {
      return a.block < b.block;
    }
    return a.cell < b.cell;
  });

  // 2. Groups of one block, and every block they touch allocated up front (serially, in order).
  std::vector<Group> groups;
  for (std::size_t i = 0; i < items.size();) {
    Group g;
    g.begin = i;
    while (i < items.size() && items[i].block == items[g.begin].block) {
      g.neighbours |= items[i].neighbours;
      ++i;
    }
    g.end = i;
    groups.push_back(g);
  }
  std::vector<CellKey> touched;
  for (const Group& g : groups) {
    const CellKey& centre = items[g.begin].block;
    for (unsigned d = 0; d < 27; ++d) {
      if ((g.neighbours >> d) & 1U) {
        const CellKey key = centre + CellKey{static_cast<int>(d % 3) - 1, static_cast<int>((d / 3) % 3) - 1,
                                             static_cast<int>(d / 9) - 1};
        obtainBlock(key, stats.blocksAllocated);
        if (sink != nullptr) {
          touched.push_back(key);
        }
      }
    }
  }

  // 3. Before values of every touched block, to find what changed.
  const std::size_t n = storage_.cellsPerBlock();
  std::vector<float> before;
  if (sink != nullptr) {
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    before.resize(touched.size() * 2 * n);
    for (std::size_t b = 0; b < touched.size(); ++b) {
      std::memcpy(before.data() + b * 2 * n, storage_.find(touched[b])->data(), 2 * n * sizeof(float));
    }
  }

  // 4. Colour by colour; blocks of one colour in parallel.
  const std::span<const Item> all(items);
  for (std::size_t g0 = 0; g0 < groups.size();) {
    std::size_t g1 = g0;
    while (g1 < groups.size() && items[groups[g1].begin].colour == items[groups[g0].begin].colour) {
      ++g1;
    }
    const std::size_t count = g1 - g0;
    const auto workers = static_cast<std::size_t>(config_.threads);
    if (workers > 1 && parallelSafe_ && count > 1) {
      std::atomic<std::size_t> next{g0};
      std::vector<UpdateStats> partial(std::min(workers, count));
      auto work = [&](std::size_t w) {
        for (std::size_t g = next.fetch_add(1); g < g1; g = next.fetch_add(1)) {
          applyGroup(groups[g], all, partial[w]);
        }
      };
      {
        std::vector<std::jthread> pool;
        for (std::size_t w = 1; w < partial.size(); ++w) {
          pool.emplace_back(work, w);
        }
        work(0);
      }
      for (const UpdateStats& p : partial) {
        stats.applied += p.applied;
        stats.skipped += p.skipped;
      }
    } else {
      for (std::size_t g = g0; g < g1; ++g) {
        applyGroup(groups[g], all, stats);
      }
    }
    g0 = g1;
  }

  // 5. Report the cells whose class or quantised probability changed.
  if (sink != nullptr) {
    for (std::size_t b = 0; b < touched.size(); ++b) {
      const float* now = storage_.find(touched[b])->data();
      const float* old = before.data() + b * 2 * n;
      for (std::size_t l = 0; l < n; ++l) {
        if (std::memcmp(now + l, old + l, sizeof(float)) == 0 &&
            std::memcmp(now + n + l, old + n + l, sizeof(float)) == 0) {
          continue;
        }
        const double m1 = static_cast<double>(now[l]);
        const double s1 = static_cast<double>(now[n + l]);
        const double m0 = static_cast<double>(old[l]);
        const double s0 = static_cast<double>(old[n + l]);
        CellChange c;
        c.quantisedProbability = quantiseProbability(predictiveProbability(m1, s1));
        c.occupancyClass = occupancyClass(m1, config_.occupiedThreshold, config_.freeThreshold);
        if (c.quantisedProbability == quantiseProbability(predictiveProbability(m0, s0)) &&
            c.occupancyClass == occupancyClass(m0, config_.occupiedThreshold, config_.freeThreshold)) {
          continue;
        }
        c.key = storage_.cellKey(touched[b], l);
        c.mean = now[l];
        c.variance = now[n + l];
        sink->cellChanged(c);
      }
    }
  }
  return stats;
}

void BandedOgf::applyGroup(const Group& group, std::span<const Item> items, UpdateStats& stats) {
  Block* neighbourhood[27] = {};
  const CellKey& centre = items[group.begin].block;
  for (unsigned d = 0; d < 27; ++d) {
    if ((group.neighbours >> d) & 1U) {
      neighbourhood[d] = storage_.find(centre + CellKey{static_cast<int>(d % 3) - 1,
                                                        static_cast<int>((d / 3) % 3) - 1,
                                                        static_cast<int>(d / 9) - 1});
    }
  }
  for (std::size_t i = group.begin; i < group.end; ++i) {
    if (applyMeasurement(neighbourhood, localIndexOf(items[i].cell), items[i].y)) {
      ++stats.applied;
    } else {
      ++stats.skipped;
    }
  }
}

bool BandedOgf::applyMeasurement(Block* const* neighbourhood, std::size_t local, int y) {
  const std::size_t n = storage_.cellsPerBlock();
  float* self = neighbourhood[kSelfBlock]->data() + local;
  const double mean = static_cast<double>(self[0]);
  const double var = static_cast<double>(self[n]);
  const double tolerance = config_.skipTolerance;
  if (tolerance > 0.0 && static_cast<double>(y) * mean / std::sqrt(1.0 + var) > kCertainZ) {
    return false;
  }
  const ProbitUpdate u = probitUpdate(y, mean, var);
  if (tolerance > 0.0 && std::abs(var * u.meanGain) < tolerance && var * var * u.covShrink < tolerance) {
    return false;
  }

  // Where every stencil cell lives, and its covariance with the measured cell (the column Σ[:, i]).
  constexpr std::size_t kMaxStencil = 4913;  // (2·8 + 1)³, R < 9
  float* base[kMaxStencil];
  double column[kMaxStencil];
  const std::size_t cells = stencil_.offsets().size();
  const auto lx = static_cast<int>(local & 7U);
  const auto ly = static_cast<int>((local >> 3) & 7U);
  const auto lz = static_cast<int>(local >> 6);
  const std::span<const std::int16_t> fwd = stencil_.forwardSlot();
  const std::span<const std::int16_t> bwd = stencil_.backwardSlot();
  for (std::size_t s = 0; s < cells; ++s) {
    const int gx = lx + offsetX_[s];
    const int gy = ly + offsetY_[s];
    const int gz = lz + offsetZ_[s];
    const auto d = static_cast<std::size_t>(((gx >> 3) + 1) + 3 * ((gy >> 3) + 1) + 9 * ((gz >> 3) + 1));
    base[s] = neighbourhood[d]->data() + ((gx & 7) + 8 * ((gy & 7) + 8 * (gz & 7)));
  }
  for (std::size_t s = 0; s < cells; ++s) {
    float v;
    if (fwd[s] >= 0) {
      v = self[(2 + static_cast<std::size_t>(fwd[s])) * n];
    } else if (bwd[s] >= 0) {
      v = base[s][(2 + static_cast<std::size_t>(bwd[s])) * n];
    } else {
      v = self[n];
    }
    column[s] = static_cast<double>(v);
  }

  // Eq. (5) inside the band: m += Σ[:, i]·gain, Σ_jk −= shrink·Σ_ji·Σ_ki for every stored pair.
  const double gain = u.meanGain;
  const double shrink = u.covShrink;
  for (std::size_t s = 0; s < cells; ++s) {
    float* p = base[s];
    p[0] = static_cast<float>(static_cast<double>(p[0]) + gain * column[s]);
    const double v = static_cast<double>(p[n]) - shrink * column[s] * column[s];
    p[n] = std::max(static_cast<float>(v), varianceFloor_);
  }
  for (const StencilPair& pair : stencil_.pairs()) {
    float* p = base[pair.from] + (2 + static_cast<std::size_t>(pair.forward)) * n;
    *p = static_cast<float>(static_cast<double>(*p) - shrink * column[pair.from] * column[pair.to]);
  }
  return true;
}

CellEstimate BandedOgf::estimate(const CellKey& cell) const {
  const Block* b = storage_.find(blockKeyOf(cell));
  if (b == nullptr || (config_.dimensions == 2 && cell.z != 0)) {
    return {0.0, prior_.variance(), false};
  }
  const std::size_t l = localIndexOf(cell);
  return {static_cast<double>(b->data()[l]), static_cast<double>(b->data()[b->cells() + l]), true};
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
  const Block* blk = storage_.find(blockKeyOf(owner));
  if (blk == nullptr) {
    return prior_(o);
  }
  const std::size_t n = blk->cells();
  return static_cast<double>(blk->data()[(2 + static_cast<std::size_t>(slot)) * n + localIndexOf(owner)]);
}

void BandedOgf::forEachCell(const std::function<void(const CellKey&, float, float)>& visit) const {
  const std::size_t n = storage_.cellsPerBlock();
  const int side = kBlockSide;
  const int zSide = config_.dimensions == 3 ? kBlockSide : 1;
  for (const CellKey& key : storage_.sortedKeys()) {
    const float* d = storage_.find(key)->data();
    for (int x = 0; x < side; ++x) {
      for (int y = 0; y < side; ++y) {
        for (int z = 0; z < zSide; ++z) {
          const auto l = static_cast<std::size_t>(x + side * (y + side * z));
          visit(CellKey{key.x * side + x, key.y * side + y, key.z * side + z}, d[l], d[n + l]);
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

std::uint64_t BandedOgf::checksum() const {
  MapChecksum sum;
  sum.addValue(config_.dimensions);
  sum.addValue(config_.resolution);
  sum.addValue(*config_.kernelSigma);
  sum.addValue(*config_.kernelAmplitude);
  sum.addValue(*config_.stencilRadius);
  sum.addValue(*config_.taperSupport);
  for (const CellKey& key : storage_.sortedKeys()) {
    sum.addValue(key);
    sum.add(std::as_bytes(storage_.find(key)->values()));
  }
  return sum.value();
}

std::span<const float> BandedOgf::blockValues(const CellKey& blockKey) const {
  const Block* b = storage_.find(blockKey);
  return b == nullptr ? std::span<const float>{} : b->values();
}

Status BandedOgf::restoreBlock(const CellKey& blockKey, std::span<const float> values) {
  if (values.size() != floatsPerBlock()) {
    return Error{"block " + std::to_string(blockKey.x) + "," + std::to_string(blockKey.y) + "," +
                 std::to_string(blockKey.z) + ": " + std::to_string(values.size()) + " values, expected " +
                 std::to_string(floatsPerBlock())};
  }
  if (config_.dimensions == 2 && blockKey.z != 0) {
    return Error{"block z = " + std::to_string(blockKey.z) + " in a 2-D map"};
  }
  if (storage_.find(blockKey) != nullptr) {
    return Error{"block " + std::to_string(blockKey.x) + "," + std::to_string(blockKey.y) + "," +
                 std::to_string(blockKey.z) + " appears twice"};
  }
  bool fresh = false;
  Block& b = storage_.obtain(blockKey, fresh);
  std::copy(values.begin(), values.end(), b.data());
  return okStatus();
}

}  // namespace ogf::filter
