// The band update of one measurement: run-time tables, the generic kernel and the compiled ones.
#include "ogf/filter/band_kernel.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "ogf/filter/filter_config.hpp"
#include "ogf/filter/variance_code.hpp"

namespace ogf::filter {

BandTables::BandTables(const Stencil& stencil, int dimensions, CovarianceStorage storage) {
  const auto offsets = stencil.offsets();
  cells = offsets.size();
  const bool banded = storage == CovarianceStorage::kBanded;
  stride = banded ? 2 + stencil.forwardOffsets().size() : 1;
  pointers = banded ? cells : 2 * cells;
  self = stencil.selfIndex();
  const std::size_t positions = dimensions == 3 ? 512 : 64;
  blockCells = positions;
  recordBlock.resize(positions * cells);
  recordFloat.resize(positions * cells);
  for (std::size_t l = 0; l < positions; ++l) {
    for (std::size_t c = 0; c < cells; ++c) {
      const int gx = static_cast<int>(l & 7U) + offsets[c].x;
      const int gy = static_cast<int>((l >> 3) & 7U) + offsets[c].y;
      const int gz = static_cast<int>(l >> 6) + offsets[c].z;
      const int d = ((gx >> 3) + 1) + 3 * ((gy >> 3) + 1) + 9 * ((gz >> 3) + 1);
      const int local = (gx & 7) + 8 * ((gy & 7) + 8 * (gz & 7));
      recordBlock[l * cells + c] = static_cast<std::uint8_t>(d);
      recordFloat[l * cells + c] = static_cast<std::uint32_t>(static_cast<std::size_t>(local) * stride);
    }
  }
  if (positions * stride <= std::numeric_limits<std::uint16_t>::max()) {
    recordFloat16.assign(recordFloat.begin(), recordFloat.end());
  }
  // Σ_si: kept by the measured cell for a forward offset, by cell s for a backward one; Σ_ii is the variance.
  for (std::size_t s = 0; s < cells; ++s) {
    const int fwd = stencil.forwardSlot()[s];
    const int bwd = stencil.backwardSlot()[s];
    columnCell.push_back(static_cast<std::uint16_t>(fwd >= 0 || bwd < 0 ? self : s));
    columnFloat.push_back(static_cast<std::uint16_t>(fwd >= 0 ? 2 + fwd : (bwd >= 0 ? 2 + bwd : 1)));
  }
  // Stencil lists the pairs grouped by the cell that keeps them, in forward-slot order.
  pairStart.assign(cells + 1, 0);
  for (const StencilPair& pair : stencil.pairs()) {
    ++pairStart[pair.from + 1U];
    pairOther.push_back(pair.to);
    pairFloat.push_back(static_cast<std::uint16_t>(2 + pair.forward));
  }
  for (std::size_t c = 0; c < cells; ++c) {
    pairStart[c + 1] += pairStart[c];
  }
  for (const CellKey& o : offsets) {
    const CellKey next{o.x + 1, o.y, o.z};
    rowEnd.push_back(std::find(offsets.begin(), offsets.end(), next) == offsets.end() ? 1 : 0);
  }
}

void genericBandLocate(float* const* blocks, std::size_t local, const BandTables& tables, float** records) {
  const std::size_t lastFloat = tables.stride - 1;
  for (std::size_t s = 0; s < tables.cells; ++s) {
    float* record = tables.record(blocks, local, s);
    records[s] = record;
    __builtin_prefetch(record, 1, 3);
    if (tables.rowEnd[s] != 0) {
      __builtin_prefetch(record + lastFloat, 1, 3);
    }
  }
}

void compactBandLocate(float* const* blocks, std::size_t local, const BandTables& tables, float** records) {
  const std::size_t cells = tables.cells;
  for (std::size_t s = 0; s < cells; ++s) {
    float* block = blocks[tables.recordBlock[local * cells + s]];
    const std::size_t cell = tables.recordFloat[local * cells + s];
    float* mean = block + cell;
    auto* code = reinterpret_cast<std::uint16_t*>(block + tables.blockCells) + cell;
    records[s] = mean;
    records[cells + s] = reinterpret_cast<float*>(code);
    __builtin_prefetch(mean, 1, 3);
    __builtin_prefetch(code, 1, 3);
  }
}

namespace {

// The compact update on `Cells` stencil cells (0: the run-time count): the ratios gathered, the columns and
// new ratios computed on arrays (unrolled by the compiler when the count is fixed; on a scratch vector for
// stencils of more than 64 cells), then scattered.
template <std::size_t Cells>
[[gnu::always_inline]] inline void compactBody(float* const* records, const BandUpdate& update,
                                               const BandTables& tables) {
  constexpr std::size_t kMax = 64;
  const std::size_t cells = Cells != 0 ? Cells : tables.cells;
  const std::size_t self = tables.self;
  const float prior = tables.priorVariance;
  const float floor = update.varianceFloor / prior;
  const auto code = [&](std::size_t s) { return reinterpret_cast<std::uint16_t*>(records[cells + s]); };
  std::array<float, 2 * kMax> local;  // NOLINT: every used entry is written below
  float* ratio = local.data();
  if (Cells == 0 && cells > kMax) {  // a large stencil: the same arithmetic on a scratch of this thread's
    thread_local std::vector<float> large;
    large.resize(2 * cells);
    ratio = large.data();
  }
  float* const column = ratio + cells;
  for (std::size_t s = 0; s < cells; ++s) {
    ratio[s] = decodeVarianceRatio(*code(s));
  }
  const float selfRatio = decodeVarianceRatio(*code(self));  // before the update, for every column entry
  for (std::size_t s = 0; s < cells; ++s) {
    column[s] = tables.correlation[s] * (ratio[s] * selfRatio);
  }
  column[self] = prior * selfRatio;
  for (std::size_t s = 0; s < cells; ++s) {
    ratio[s] = std::max(ratio[s] - update.shrink * column[s] * (column[s] / prior), floor);
  }
  for (std::size_t s = 0; s < cells; ++s) {
    *records[s] += update.gain * column[s];
    *code(s) = encodeVarianceRatio(ratio[s]);
  }
}

// The two stencils of 3-D maps in compact storage with a kernel of their own: the default, the √2 ball with
// the six axial cells at distance 2 (25 cells), and the √2 ball alone (19 cells, the lean stencil).
template <std::size_t Cells>
void compactBandKernelFixed(float* const* records, BandUpdate update, const BandTables& tables) {
  compactBody<Cells>(records, update, tables);
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same arithmetic on the first 8·⌊Cells/8⌋ cells in 8-wide vectors and the rest one by one: IEEE
// operations without contraction (this file is built with -ffp-contract=off), in compactBody's order, so the
// same floats as the baseline's, bit for bit. The ratios go from the codes into vector registers directly:
// decoded one by one into memory, as the compiler does compactBody, each 8-wide load of them waited for eight
// narrower stores to drain (a failed store-to-load forward).
template <std::size_t Cells>
__attribute__((target("avx2"))) void compactBandKernelAvx2(float* const* records, BandUpdate update,
                                                           const BandTables& tables) {
  constexpr std::size_t kVectors = Cells / 8;
  constexpr std::size_t kVectorCells = 8 * kVectors;  // the cells after them go one by one
  const auto code = [&](std::size_t s) { return reinterpret_cast<std::uint16_t*>(records[Cells + s]); };
  const float prior = tables.priorVariance;
  const float floor = update.varianceFloor / prior;
  const float selfRatio =
      decodeVarianceRatio(*code(tables.self));  // before the update, for every column entry
  const __m256i codeBase = _mm256_set1_epi32(static_cast<int>(kVarianceCodeBase));
  const __m256 selfRatios = _mm256_set1_ps(selfRatio);
  const __m256 selfColumn = _mm256_set1_ps(prior * selfRatio);
  const __m256i self = _mm256_set1_epi32(static_cast<int>(tables.self));
  const __m256 shrink = _mm256_set1_ps(update.shrink);
  const __m256 priors = _mm256_set1_ps(prior);
  const __m256 floors = _mm256_set1_ps(floor);
  const __m256 smallest = _mm256_set1_ps(kSmallestVarianceRatio);  // encodeVarianceRatio's bounds
  const __m256 two = _mm256_set1_ps(2.0F);
  const __m256i largest = _mm256_set1_epi32(0xFFFF);
  alignas(32) std::array<float, kVectorCells> columns;        // NOLINT: written below before it is read
  alignas(32) std::array<std::uint32_t, kVectorCells> codes;  // NOLINT: written below before it is read
  for (std::size_t v = 0; v < kVectors; ++v) {
    const std::size_t s = 8 * v;
    const __m256i stored = _mm256_setr_epi32(*code(s), *code(s + 1), *code(s + 2), *code(s + 3), *code(s + 4),
                                             *code(s + 5), *code(s + 6), *code(s + 7));
    const __m256 ratio = _mm256_castsi256_ps(_mm256_add_epi32(_mm256_slli_epi32(stored, 12), codeBase));
    __m256 column =
        _mm256_mul_ps(_mm256_loadu_ps(tables.correlation.data() + s), _mm256_mul_ps(ratio, selfRatios));
    const __m256i lane = _mm256_setr_epi32(
        static_cast<int>(s), static_cast<int>(s + 1), static_cast<int>(s + 2), static_cast<int>(s + 3),
        static_cast<int>(s + 4), static_cast<int>(s + 5), static_cast<int>(s + 6), static_cast<int>(s + 7));
    column = _mm256_blendv_ps(column, selfColumn, _mm256_castsi256_ps(_mm256_cmpeq_epi32(lane, self)));
    // std::max(r, floor) is (r < floor ? floor : r): maxps(floor, r) returns r unless floor > r.
    const __m256 next = _mm256_max_ps(
        floors,
        _mm256_sub_ps(ratio, _mm256_mul_ps(_mm256_mul_ps(shrink, column), _mm256_div_ps(column, priors))));
    // encodeVarianceRatio: 0 below 2^-31 (or NaN), 0xFFFF from 2 on, else the rounded mantissa.
    const __m256i rounded = _mm256_min_epu32(
        _mm256_srli_epi32(_mm256_add_epi32(_mm256_sub_epi32(_mm256_castps_si256(next), codeBase),
                                           _mm256_set1_epi32(1 << 11)),
                          12),
        largest);
    const __m256i encoded = _mm256_and_si256(
        _mm256_blendv_epi8(rounded, largest, _mm256_castps_si256(_mm256_cmp_ps(next, two, _CMP_GE_OQ))),
        _mm256_castps_si256(_mm256_cmp_ps(next, smallest, _CMP_GE_OQ)));
    _mm256_store_ps(columns.data() + s, column);
    _mm256_store_si256(reinterpret_cast<__m256i*>(codes.data() + s), encoded);
  }
  // The rest read the codes before the vectors' are stored: no stencil cell is another's record.
  std::array<float, Cells - kVectorCells> restColumns;        // NOLINT: written below before it is read
  std::array<std::uint16_t, Cells - kVectorCells> restCodes;  // NOLINT: written below before it is read
  for (std::size_t s = kVectorCells; s < Cells; ++s) {
    const float ratio = decodeVarianceRatio(*code(s));
    const float column = s == tables.self ? prior * selfRatio : tables.correlation[s] * (ratio * selfRatio);
    restColumns[s - kVectorCells] = column;
    restCodes[s - kVectorCells] =
        encodeVarianceRatio(std::max(ratio - update.shrink * column * (column / prior), floor));
  }
  for (std::size_t s = 0; s < kVectorCells; ++s) {
    *records[s] += update.gain * columns[s];
    *code(s) = static_cast<std::uint16_t>(codes[s]);
  }
  for (std::size_t s = kVectorCells; s < Cells; ++s) {
    *records[s] += update.gain * restColumns[s - kVectorCells];
    *code(s) = restCodes[s - kVectorCells];
  }
}
#endif

}  // namespace

void compactBandKernel(float* const* records, BandUpdate update, const BandTables& tables) {
  compactBody<0>(records, update, tables);
}

BandKernel compactBandKernelFor(const BandTables& tables, bool avx2) {
  static_cast<void>(avx2);
  switch (tables.cells) {
#if defined(__x86_64__) && defined(__GNUC__)
    case 19: return avx2 ? &compactBandKernelAvx2<19> : &compactBandKernelFixed<19>;
    case 25: return avx2 ? &compactBandKernelAvx2<25> : &compactBandKernelFixed<25>;
#else
    case 19: return &compactBandKernelFixed<19>;
    case 25: return &compactBandKernelFixed<25>;
#endif
    default: return &compactBandKernel;
  }
}

namespace {

// The arithmetic of one stored entry, r − a·b: rounded twice (multiply, subtract) on the x86-64 baseline, or
// once as a fused multiply-add where the CPU has FMA. Kernels of one arithmetic give the same floats.
template <bool Fused>
[[gnu::always_inline]] inline float minusProduct(float r, float a, float b) {
  if constexpr (Fused) {
    return std::fma(-a, b, r);
  } else {
    return r - a * b;
  }
}

// The part of eq. (5) on one stencil cell's own mean and variance; returns shrink·Σ_si for its pairs. Every
// kernel calls this, so their arithmetic is the same.
template <bool Fused>
[[gnu::always_inline]] inline float updateMeanAndVariance(float* record, float column, const BandUpdate& u) {
  const float scaled = u.shrink * column;
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
  // The mean and the variance are adjacent: one 8-byte load and one store for both, as two lanes that each
  // do the arithmetic of the portable code below (the mean's lane is held against −∞, which leaves it as it
  // is). The kernel issues about one store per stored entry, and the CPU retires one store per cycle.
  // (Clang wants the FMA target on the function that calls the builtin, not on the kernel it is inlined
  // into; its builds, the fuzzers', take the portable code.)
  __m128 moments = _mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(record));
  const __m128 columns = _mm_set1_ps(column);
  if constexpr (Fused) {
    moments = reinterpret_cast<__m128>(
        __builtin_ia32_vfmaddps(reinterpret_cast<__v4sf>(_mm_setr_ps(u.gain, -scaled, 0.0F, 0.0F)),
                                reinterpret_cast<__v4sf>(columns), reinterpret_cast<__v4sf>(moments)));
  } else {
    moments = _mm_sub_ps(moments, _mm_mul_ps(_mm_setr_ps(-u.gain, scaled, 0.0F, 0.0F), columns));
  }
  moments =
      _mm_max_ps(moments, _mm_setr_ps(-std::numeric_limits<float>::infinity(), u.varianceFloor, 0.0F, 0.0F));
  _mm_storel_pi(reinterpret_cast<__m64*>(record), moments);
#else
  record[0] = minusProduct<Fused>(record[0], -u.gain, column);
  record[1] = std::max(minusProduct<Fused>(record[1], scaled, column), u.varianceFloor);
#endif
  return scaled;
}

template <bool Fused>
[[gnu::always_inline]] inline void genericBandBody(float* const* cell, const BandUpdate& update,
                                                   const BandTables& t) {
  thread_local std::vector<float> columnScratch;
  columnScratch.resize(t.cells);
  float* column = columnScratch.data();
  for (std::size_t s = 0; s < t.cells; ++s) {
    column[s] = cell[t.columnCell[s]][t.columnFloat[s]];
  }
  for (std::size_t s = 0; s < t.cells; ++s) {
    float* record = cell[s];
    const float scaled = updateMeanAndVariance<Fused>(record, column[s], update);
    for (std::uint32_t k = t.pairStart[s]; k < t.pairStart[s + 1]; ++k) {
      record[t.pairFloat[k]] = minusProduct<Fused>(record[t.pairFloat[k]], scaled, column[t.pairOther[k]]);
    }
  }
}

}  // namespace

void genericBandKernel(float* const* records, BandUpdate update, const BandTables& t) {
  genericBandBody<false>(records, update, t);
}

#if defined(__x86_64__) && defined(__GNUC__)
namespace {
__attribute__((target("avx2,fma"))) void genericBandKernelFma(float* const* records, BandUpdate update,
                                                              const BandTables& t) {
  genericBandBody<true>(records, update, t);
}
}  // namespace
#endif

namespace {

// A 3-D stencil known at compile time: |o|² ≤ r2 or |o|₁ ≤ manhattan (StencilShape with R = √r2).
struct Shape {
  int r2 = 0;
  int manhattan = 0;
};

constexpr int absOf(int v) { return v < 0 ? -v : v; }
constexpr bool contains(Shape s, int x, int y, int z) {
  return x * x + y * y + z * z <= s.r2 || absOf(x) + absOf(y) + absOf(z) <= s.manhattan;
}
constexpr int reachOf(Shape s) {
  int e = 0;
  while ((e + 1) * (e + 1) <= s.r2) {
    ++e;
  }
  return std::max(e, s.manhattan);
}
// Lexicographically positive, as isForward.
constexpr bool forward(int x, int y, int z) { return z > 0 || (z == 0 && (y > 0 || (y == 0 && x > 0))); }

struct Sizes {
  std::size_t cells = 0;
  std::size_t forward = 0;
  std::size_t pairs = 0;
};

// Offsets in Stencil's order (x, then y, then z), the forward ones, and the pairs kept by each cell.
template <std::size_t Cells, std::size_t Forward, std::size_t Pairs>
struct CompiledTables {
  std::array<int, Cells> x{}, y{}, z{};
  std::array<std::uint16_t, Cells> columnCell{}, columnFloat{};
  std::array<std::uint32_t, Cells + 1> pairStart{};
  std::array<std::uint16_t, Pairs> pairOther{}, pairFloat{};
  std::array<bool, Cells> rowEnd{};
  std::size_t self = 0;
  Sizes sizes{};
};

template <std::size_t Cells, std::size_t Forward, std::size_t Pairs>
constexpr CompiledTables<Cells, Forward, Pairs> buildTables(Shape shape) {
  CompiledTables<Cells, Forward, Pairs> t;
  std::array<int, Forward> fx{}, fy{}, fz{};
  const int e = reachOf(shape);
  std::size_t c = 0;
  std::size_t f = 0;
  for (int x = -e; x <= e; ++x) {
    for (int y = -e; y <= e; ++y) {
      for (int z = -e; z <= e; ++z) {
        if (!contains(shape, x, y, z)) {
          continue;
        }
        if (c < Cells) {
          t.x[c] = x;
          t.y[c] = y;
          t.z[c] = z;
          if (x == 0 && y == 0 && z == 0) {
            t.self = c;
          }
        }
        ++c;
        if (forward(x, y, z)) {
          if (f < Forward) {
            fx[f] = x;
            fy[f] = y;
            fz[f] = z;
          }
          ++f;
        }
      }
    }
  }
  t.sizes.cells = c;
  t.sizes.forward = f;
  const auto slotOf = [&](int x, int y, int z) {
    for (std::size_t k = 0; k < Forward && k < f; ++k) {
      if (fx[k] == x && fy[k] == y && fz[k] == z) {
        return static_cast<int>(k);
      }
    }
    return -1;
  };
  const auto cellOf = [&](int x, int y, int z) {
    for (std::size_t k = 0; k < Cells && k < c; ++k) {
      if (t.x[k] == x && t.y[k] == y && t.z[k] == z) {
        return static_cast<int>(k);
      }
    }
    return -1;
  };
  std::size_t p = 0;
  for (std::size_t s = 0; s < Cells && s < c; ++s) {
    const int fwd = slotOf(t.x[s], t.y[s], t.z[s]);
    const int bwd = slotOf(-t.x[s], -t.y[s], -t.z[s]);
    t.columnCell[s] = static_cast<std::uint16_t>(fwd >= 0 || bwd < 0 ? t.self : s);
    t.columnFloat[s] = static_cast<std::uint16_t>(fwd >= 0 ? 2 + fwd : (bwd >= 0 ? 2 + bwd : 1));
    t.pairStart[s] = static_cast<std::uint32_t>(p);
    for (std::size_t k = 0; k < Forward && k < f; ++k) {
      const int other = cellOf(t.x[s] + fx[k], t.y[s] + fy[k], t.z[s] + fz[k]);
      if (other >= 0) {
        if (p < Pairs) {
          t.pairOther[p] = static_cast<std::uint16_t>(other);
          t.pairFloat[p] = static_cast<std::uint16_t>(2 + k);
        }
        ++p;
      }
    }
  }
  t.pairStart[Cells] = static_cast<std::uint32_t>(p);
  t.sizes.pairs = p;
  for (std::size_t s = 0; s < Cells && s < c; ++s) {
    t.rowEnd[s] = cellOf(t.x[s] + 1, t.y[s], t.z[s]) < 0;
  }
  return t;
}

// First pass with generous bounds to count, second with the exact sizes.
constexpr Sizes sizesOf(Shape shape) { return buildTables<200, 100, 4000>(shape).sizes; }

template <Shape S>
struct Compiled {
  static constexpr Sizes kSizes = sizesOf(S);
  static constexpr auto kTables = buildTables<kSizes.cells, kSizes.forward, kSizes.pairs>(S);
  static constexpr std::size_t kStride = 2 + kSizes.forward;
};

// Everything below is forced inline, so each kernel is one function compiled for its instruction set.
template <Shape S, bool Fused, std::size_t s>
[[gnu::always_inline]] inline void applyCell(float* record, const float* column, const BandUpdate& u) {
  constexpr auto& t = Compiled<S>::kTables;
  constexpr std::uint32_t first = t.pairStart[s];
  const float scaled = updateMeanAndVariance<Fused>(record, column[s], u);
  [&]<std::size_t... k>(std::index_sequence<k...>) __attribute__((always_inline)) {
    ((record[t.pairFloat[first + k]] =
          minusProduct<Fused>(record[t.pairFloat[first + k]], scaled, column[t.pairOther[first + k]])),
     ...);
  }(std::make_index_sequence<t.pairStart[s + 1] - first>{});
}

template <Shape S, bool Fused>
[[gnu::always_inline]] inline void compiledBandBody(float* const* cell, const BandUpdate& update) {
  using C = Compiled<S>;
  constexpr std::size_t kCells = C::kSizes.cells;
  constexpr auto& t = C::kTables;
  // A copy the compiler can keep in registers: the records are floats too, so through the reference every
  // store would oblige it to load gain, shrink and floor again.
  const BandUpdate u = update;
  float column[kCells];
  [&]<std::size_t... s>(std::index_sequence<s...>) __attribute__((always_inline)) {
    ((column[s] = cell[t.columnCell[s]][t.columnFloat[s]]), ...);
  }(std::make_index_sequence<kCells>{});
  [&]<std::size_t... s>(std::index_sequence<s...>) __attribute__((always_inline)) {
    (applyCell<S, Fused, s>(cell[s], column, u), ...);
  }(std::make_index_sequence<kCells>{});
}

// The x86-64 baseline (SSE2; multiply, then subtract), and the same code for CPUs with AVX2 and FMA, where
// each stored entry is one fused multiply-add: one rounding instead of two, and fewer instructions.
template <Shape S>
void compiledBandKernel(float* const* records, BandUpdate update, const BandTables& /*tables*/) {
  compiledBandBody<S, false>(records, update);
}

#if defined(__x86_64__) && defined(__GNUC__)
template <Shape S>
__attribute__((target("avx2,fma"))) void compiledBandKernelFma(float* const* records,
                                                               BandUpdate update,
                                                               const BandTables& /*tables*/) {
  compiledBandBody<S, true>(records, update);
}
#endif

// genericBandLocate unrolled, with the record size a constant.
template <Shape S>
void compiledBandLocate(float* const* blocks, std::size_t local, const BandTables& tables, float** records) {
  using C = Compiled<S>;
  constexpr std::size_t kCells = C::kSizes.cells;
  const std::uint8_t* block = tables.recordBlock.data() + local * kCells;
  const std::uint16_t* first = tables.recordFloat16.data() + local * kCells;
  [&]<std::size_t... s>(std::index_sequence<s...>) __attribute__((always_inline)) {
    (
        [&] {
          float* record = blocks[block[s]] + first[s];
          records[s] = record;
          __builtin_prefetch(record, 1, 3);
          if constexpr (C::kTables.rowEnd[s]) {
            __builtin_prefetch(record + C::kStride - 1, 1, 3);
          }
        }(),
        ...);
  }(std::make_index_sequence<kCells>{});
}

template <Shape S>
bool matches(const BandTables& r) {
  constexpr auto& t = Compiled<S>::kTables;
  return r.cells == t.sizes.cells && r.stride == Compiled<S>::kStride && r.self == t.self &&
         std::equal(r.columnCell.begin(), r.columnCell.end(), t.columnCell.begin()) &&
         std::equal(r.columnFloat.begin(), r.columnFloat.end(), t.columnFloat.begin()) &&
         r.pairOther.size() == t.sizes.pairs &&
         std::equal(r.pairStart.begin(), r.pairStart.end(), t.pairStart.begin()) &&
         std::equal(r.pairOther.begin(), r.pairOther.end(), t.pairOther.begin()) &&
         std::equal(r.pairFloat.begin(), r.pairFloat.end(), t.pairFloat.begin());
}

template <Shape S>
void tryCompiledLocate(const BandTables& tables, BandLocate& chosen) {
  if (chosen == &genericBandLocate && !tables.recordFloat16.empty() && matches<S>(tables)) {
    chosen = &compiledBandLocate<S>;
  }
}

template <Shape S>
void tryCompiled(const BandTables& tables, bool fma, BandKernel& chosen) {
  if (chosen != genericBandKernelFor(fma) || !matches<S>(tables)) {
    return;
  }
  chosen = &compiledBandKernel<S>;
#if defined(__x86_64__) && defined(__GNUC__)
  if (fma) {
    chosen = &compiledBandKernelFma<S>;
  }
#endif
}

}  // namespace

bool cpuHasFma() {
#if defined(__x86_64__) && defined(__GNUC__)
  // __builtin_cpu_supports also checks that the OS saves the AVX registers.
  return __builtin_cpu_supports("avx2") != 0 && __builtin_cpu_supports("fma") != 0;
#else
  return false;
#endif
}

BandKernel genericBandKernelFor(bool fma) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (fma) {
    return &genericBandKernelFma;
  }
#endif
  static_cast<void>(fma);
  return &genericBandKernel;
}

BandLocate bandLocateFor(const BandTables& tables) {
  BandLocate chosen = &genericBandLocate;
  tryCompiledLocate<Shape{2, 2}>(tables, chosen);
  tryCompiledLocate<Shape{1, 0}>(tables, chosen);
  tryCompiledLocate<Shape{2, 0}>(tables, chosen);
  tryCompiledLocate<Shape{3, 0}>(tables, chosen);
  tryCompiledLocate<Shape{4, 0}>(tables, chosen);
  return chosen;
}

BandKernel bandKernelFor(const BandTables& tables, bool fma) {
  BandKernel chosen = genericBandKernelFor(fma);
  tryCompiled<Shape{2, 2}>(tables, fma, chosen);  // the default: √2 ball + the axial cells at distance 2
  tryCompiled<Shape{1, 0}>(tables, fma, chosen);
  tryCompiled<Shape{2, 0}>(tables, fma, chosen);
  tryCompiled<Shape{3, 0}>(tables, fma, chosen);
  tryCompiled<Shape{4, 0}>(tables, fma, chosen);
  return chosen;
}

}  // namespace ogf::filter
