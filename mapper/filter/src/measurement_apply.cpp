// Stage 5 of BandedOgf::update: the rank-1 update of eq. (5) restricted to the stencil, colour by colour,
// the groups of one colour in parallel.

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "banded_batch.hpp"
#include "ogf/filter/probit_update.hpp"
#include "ogf/filter/variance_code.hpp"

namespace ogf::filter {

namespace {

// applyRun finds the stencil records of the measurement this many places ahead, into ring slots of which
// there are a power of two above it.
constexpr std::size_t kPrefetchAhead = 4;
constexpr std::size_t kRingSlots = 8;
static_assert(std::has_single_bit(kRingSlots) && kRingSlots > kPrefetchAhead);
constexpr std::size_t kParallelGroups = 16;  // groups a filter thread takes at a time

}  // namespace

// 5. The updates of eq. (5), colour by colour: the groups of one colour touch disjoint state, and run in
//    parallel when there are threads (applyColourInParallel).
void BandedOgf::applyColours(std::span<const Group> sorted, UpdateStats& stats) {
  Batch& work = scratch_->batch;
  for (std::size_t g0 = 0; g0 < sorted.size();) {
    std::size_t g1 = g0;
    while (g1 < sorted.size() && sorted[g1].colour == sorted[g0].colour) {
      ++g1;
    }
    const std::size_t count = g1 - g0;
    if (config_.threads > 1 && parallelSafe_ && count > 1) {
      applyColourInParallel(sorted, g0, g1, stats);
    } else {
      std::vector<float*>& ring = scratch_->apply.ring;
      ring.resize(kRingSlots * band_.pointers);
      applyRun(sorted.subspan(g0, count), work.sorted, &work.neighbourhoods[g0 * 27], ring, stats);
    }
    g0 = g1;
  }
}

// Groups [g0, g1) of one colour on config_.threads threads (the calling one among them), each taking the
// next few groups (up to kParallelGroups) as it finishes the ones before: a run of groups keeps applyRun's
// prefetch going from one block to the next, where a group at a time restarts it at every block.
void BandedOgf::applyColourInParallel(std::span<const Group> sorted, std::size_t g0, std::size_t g1,
                                      UpdateStats& stats) {
  Batch& work = scratch_->batch;
  const std::size_t ringSize = kRingSlots * band_.pointers;
  std::atomic<std::size_t> next{g0};
  std::vector<UpdateStats> partial(std::min(static_cast<std::size_t>(config_.threads), g1 - g0));
  // Eight shares a thread at least, for the balance, where the colour has fewer than kParallelGroups each.
  const std::size_t step = std::clamp<std::size_t>((g1 - g0) / (partial.size() * 8), 1, kParallelGroups);
  auto run = [&](std::size_t w) {
    std::vector<float*> ring(ringSize);
    // Counted on the thread's stack: the threads' entries of `partial` share a cache line, and counting
    // there made every update of one thread invalidate the other's line.
    UpdateStats counted;
    for (std::size_t g = next.fetch_add(step); g < g1; g = next.fetch_add(step)) {
      const std::size_t n = std::min(step, g1 - g);
      applyRun(sorted.subspan(g, n), work.sorted, &work.neighbourhoods[g * 27], ring, counted);
    }
    partial[w] = counted;
  };
  pool()->run([&](std::size_t w) {
    if (w < partial.size()) {
      run(w);
    }
  });
  for (const UpdateStats& p : partial) {
    stats.applied += p.applied;
    stats.skipped += p.skipped;
  }
}

void BandedOgf::applyRun(std::span<const Group> groups, std::span<const std::uint16_t> codes,
                         float* const* neighbourhoods, std::span<float*> ring, UpdateStats& stats) {
  // The groups' measurements are consecutive in `codes`; measurement i's records are in ring slot i mod
  // kRingSlots, found kPrefetchAhead measurements earlier.
  const std::size_t cells = band_.pointers;
  const std::size_t first = groups.front().begin;
  const std::size_t last = groups.back().end;
  const auto slot = [&](std::size_t i) { return ring.data() + (i & (kRingSlots - 1)) * cells; };
  std::size_t aheadGroup = 0;
  const auto locateAhead = [&](std::size_t i) {
    while (i >= groups[aheadGroup].end) {
      ++aheadGroup;
    }
    locate_(neighbourhoods + aheadGroup * 27, static_cast<std::size_t>(codes[i] >> 1), band_, slot(i));
  };
  for (std::size_t i = first; i < std::min(first + kPrefetchAhead, last); ++i) {
    locateAhead(i);
  }
  for (std::size_t i = first; i < last; ++i) {
    if (i + kPrefetchAhead < last) {
      locateAhead(i + kPrefetchAhead);
    }
    if (applyMeasurement(slot(i), (codes[i] & 1U) != 0 ? 1 : -1)) {
      ++stats.applied;
    } else {
      ++stats.skipped;
    }
  }
}

bool BandedOgf::applyMeasurement(float* const* records, int y) {
  const float* self = records[band_.self];
  double var = 0.0;
  double inverseScale = 0.0;
  if (compact()) {
    const std::uint16_t code = *reinterpret_cast<const std::uint16_t*>(records[band_.cells + band_.self]);
    var = static_cast<double>(priorVariance_ * decodeVarianceRatio(code));
    inverseScale = inverseScales_[code];
  } else {
    var = static_cast<double>(self[1]);
    inverseScale = 1.0 / std::sqrt(1.0 + var);
  }
  const double tolerance = config_.skipTolerance;
  const double z = static_cast<double>(y) * static_cast<double>(self[0]) * inverseScale;
  if (z > (y < 0 ? freeClampZ_ : clampZ_)) {
    return false;
  }
  const ProbitUpdate u = probitUpdateScaled(y, inverseScale, z, (*lambda_)(z));
  if (tolerance > 0.0 && std::abs(var * u.meanGain) < tolerance && var * var * u.covShrink < tolerance) {
    return false;
  }
  // Eq. (5) inside the band: m += Σ[:, i]·gain, Σ_jk −= shrink·Σ_ji·Σ_ki for every stored pair, in float.
  kernel_(records, {static_cast<float>(u.meanGain), static_cast<float>(u.covShrink), varianceFloor_}, band_);
  return true;
}

}  // namespace ogf::filter
