// The published state of a cell: class thresholds in the latent space, and the tabulated Φ with exact
// fallbacks.
#include "ogf/filter/published_state.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "ogf/filter/band_kernel.hpp"
#include "ogf/filter/cubic_hermite.hpp"
#include "ogf/filter/inverse_mills.hpp"
#include "ogf/filter/occupancy.hpp"

namespace ogf::filter {
namespace {

constexpr double kLow = -9.0;  // Φ(−9)·10000 ≈ 1e-15: quantised to 0 below, to 10000 above +9
constexpr double kHigh = 9.0;
constexpr int kNodesPerUnit = 64;
constexpr double kSpacing = 1.0 / kNodesPerUnit;
constexpr auto kIntervals = static_cast<std::size_t>((kHigh - kLow) * kNodesPerUnit);
// Within this of Φ⁻¹(r) the class is decided by the exact comparison (Φ' ≥ 0.1 there for r in [0.01,
// 0.99]: 1e-9 in m is 1e-10 in Φ, far above the rounding of either computation).
constexpr double kClassBand = 1e-9;
// Within this of a rounding boundary (x.5 in units of 1e-4) the exact Φ decides. The table's error is about
// 1e-10 in Φ, 1e-6 in those units. The vector path computes m/√(1+s) in float: three roundings of at most
// 2^-24 each (1 + s, the root, the quotient) give a relative error below 1.5e-7, so an error in Φ below
// 1.5e-7 · max |z|φ(z) = 3.7e-8, 3.7e-4 in those units.
constexpr double kRoundingBand = 1e-3;
// 1.5·2^52: for |x| < 2^51, x + kRoundingShift is x rounded to the nearest integer, which is then the low
// bits of the sum; the integer parts below are taken so, not by a conversion to an integer and back,
// which would lengthen each cell's chain of dependent instructions.
constexpr double kRoundingShift = 6755399441055744.0;
// Cells per stage of statesOf: the table coordinates of this many cells are computed, then looked up.
constexpr std::size_t kStage = 256;

// The integer nearest x (|x| < 2^51) as x + kRoundingShift.
double shiftedRound(double x) { return x + kRoundingShift; }
std::int64_t integerOf(double shifted) {
  return std::bit_cast<std::int64_t>(shifted) - std::bit_cast<std::int64_t>(kRoundingShift);
}

// Φ⁻¹(p) by bisection on the exact Φ: 200 halvings of [−40, 40] reach the spacing of doubles.
double inverseNormalCdf(double p) {
  double lo = -40.0;
  double hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 0.0; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid == lo || mid == hi) {
      break;
    }
    (normalCdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Φ and φ·spacing at the nodes, built once per process.
struct NormalCdfTable {
  std::array<double, kIntervals + 1> value{};
  std::array<double, kIntervals + 1> slope{};
  NormalCdfTable() {
    for (std::size_t k = 0; k < value.size(); ++k) {
      const double z = kLow + static_cast<double>(k) * kSpacing;
      value[k] = normalCdf(z);
      slope[k] = normalPdf(z) * kSpacing;
    }
  }
};

const NormalCdfTable& normalCdfTable() {
  static const NormalCdfTable table;
  return table;
}

// u: m/√(1+s) in node spacings from the first node.
double tableCoordinate(double mean, double variance) { return (mean / std::sqrt(1.0 + variance) - kLow) * kNodesPerUnit; }

// The state from u by the table (value, slope), and whether it is certainly the exact one: u outside the
// table, near a rounding boundary or within kClassBand of a class threshold (occupiedZ, freeZ) is not.
[[gnu::always_inline]] inline bool tableState(const double* value, const double* slope, double occupiedZ,
                                              double freeZ, double u, double mean, PublishedState& state) {
  // Not negated, so a NaN fails it too; then u is replaced by 0 so the look-up stays in the table.
  const bool inTable = u >= 0.0 && u < static_cast<double>(kIntervals);
  const double v = inTable ? u : 0.0;
  // The node below v: v − ½ rounded (a tie picks either node of an interval's end, both exact there).
  const double nodeShifted = shiftedRound(v - 0.5);
  const double t = v - (nodeShifted - kRoundingShift);
  const double scaled = cubicHermite(value, slope, static_cast<std::size_t>(integerOf(nodeShifted)), t) * 10000.0;
  const double roundedShifted = shiftedRound(scaled);
  // scaled minus its nearest integer, in [−½, ½]: near ±½ scaled is near a rounding boundary.
  const double fraction = scaled - (roundedShifted - kRoundingShift);
  state.quantisedProbability = static_cast<std::uint16_t>(integerOf(roundedShifted));
  state.occupancyClass = static_cast<std::int8_t>(static_cast<int>(mean > occupiedZ) - static_cast<int>(mean < freeZ));
  return inTable & (std::abs(fraction) <= 0.5 - kRoundingBand) & (std::abs(mean - occupiedZ) > kClassBand) &
         (std::abs(mean - freeZ) > kClassBand);
}

#if defined(__x86_64__) && defined(__GNUC__)
// tableState for cells [0, n), eight at a time (n a multiple of 8): m/√(1+s) in one 256-bit vector of
// floats (kRoundingBand allows for its rounding), the rest in two vectors of four doubles, in the scalar
// code's operations and order (no fused multiply-add). The cells it is not certain of go to `unsure`
// (their indices); returns how many. One call for many cells, so the constants are set up once and the
// loop's iterations overlap.
__attribute__((target("avx2"))) std::size_t tableStatesAvx2(const double* value, const double* slope,
                                                            double occupiedZ, double freeZ,
                                                            const float* means, const float* variances,
                                                            PublishedState* state, std::size_t n,
                                                            std::uint32_t* unsure) {
  const __m256 oneFloat = _mm256_set1_ps(1.0F);
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d shift = _mm256_set1_pd(kRoundingShift);
  const __m256d signBit = _mm256_set1_pd(-0.0);
  const __m256d low = _mm256_set1_pd(kLow);
  const __m256d nodesPerUnit = _mm256_set1_pd(static_cast<double>(kNodesPerUnit));
  const __m256d intervals = _mm256_set1_pd(static_cast<double>(kIntervals));
  const __m256d half = _mm256_set1_pd(0.5);
  const __m256d three = _mm256_set1_pd(3.0);
  const __m256d two = _mm256_set1_pd(2.0);
  const __m256d tenThousand = _mm256_set1_pd(10000.0);
  const __m256d oz = _mm256_set1_pd(occupiedZ);
  const __m256d fz = _mm256_set1_pd(freeZ);
  const __m256d classBand = _mm256_set1_pd(kClassBand);
  const __m256d roundingLimit = _mm256_set1_pd(0.5 - kRoundingBand);
  std::size_t unsureCount = 0;
  // Cells [i, i + 4) from their means m and their m/√(1+s) z.
  const auto four = [&](std::size_t i, __m256d m, __m256d z) __attribute__((target("avx2"), always_inline)) {
    const __m256d u = _mm256_mul_pd(_mm256_sub_pd(z, low), nodesPerUnit);
    const __m256d inTable = _mm256_and_pd(_mm256_cmp_pd(u, _mm256_setzero_pd(), _CMP_GE_OQ),
                                          _mm256_cmp_pd(u, intervals, _CMP_LT_OQ));
    const __m256d v = _mm256_and_pd(u, inTable);
    const __m256d nodeShifted = _mm256_add_pd(_mm256_sub_pd(v, half), shift);
    const __m256d t = _mm256_sub_pd(v, _mm256_sub_pd(nodeShifted, shift));
    const __m256i k = _mm256_sub_epi64(_mm256_castpd_si256(nodeShifted), _mm256_castpd_si256(shift));
    // cubicHermite
    const __m256d t2 = _mm256_mul_pd(t, t);
    const __m256d t3 = _mm256_mul_pd(t2, t);
    const __m256d h01 = _mm256_sub_pd(_mm256_mul_pd(three, t2), _mm256_mul_pd(two, t3));
    const __m256d h00 = _mm256_sub_pd(one, h01);
    const __m256d h10 = _mm256_add_pd(_mm256_sub_pd(t3, _mm256_mul_pd(two, t2)), t);
    const __m256d h11 = _mm256_sub_pd(t3, t2);
    // The two nodes of each cell's interval by 128-bit loads (a gather is microcode on some CPUs), then
    // transposed: (value[k], value[k + 1]) of cells 0 and 2, 1 and 3, unpacked into node k and node k + 1.
    alignas(32) std::array<std::int64_t, 4> node{};
    _mm256_store_si256(reinterpret_cast<__m256i*>(node.data()), k);
    const __m256d valuesEven = _mm256_set_m128d(_mm_loadu_pd(value + node[2]), _mm_loadu_pd(value + node[0]));
    const __m256d valuesOdd = _mm256_set_m128d(_mm_loadu_pd(value + node[3]), _mm_loadu_pd(value + node[1]));
    const __m256d slopesEven = _mm256_set_m128d(_mm_loadu_pd(slope + node[2]), _mm_loadu_pd(slope + node[0]));
    const __m256d slopesOdd = _mm256_set_m128d(_mm_loadu_pd(slope + node[3]), _mm_loadu_pd(slope + node[1]));
    const __m256d v0 = _mm256_unpacklo_pd(valuesEven, valuesOdd);
    const __m256d v1 = _mm256_unpackhi_pd(valuesEven, valuesOdd);
    const __m256d d0 = _mm256_unpacklo_pd(slopesEven, slopesOdd);
    const __m256d d1 = _mm256_unpackhi_pd(slopesEven, slopesOdd);
    const __m256d hermite = _mm256_add_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(h00, v0), _mm256_mul_pd(h01, v1)), _mm256_mul_pd(h10, d0)),
        _mm256_mul_pd(h11, d1));
    const __m256d scaled = _mm256_mul_pd(hermite, tenThousand);
    const __m256d roundedShifted = _mm256_add_pd(scaled, shift);
    const __m256d fraction = _mm256_sub_pd(scaled, _mm256_sub_pd(roundedShifted, shift));
    const __m256i q = _mm256_sub_epi64(_mm256_castpd_si256(roundedShifted), _mm256_castpd_si256(shift));
    const int above = _mm256_movemask_pd(_mm256_cmp_pd(m, oz, _CMP_GT_OQ));
    const int below = _mm256_movemask_pd(_mm256_cmp_pd(m, fz, _CMP_LT_OQ));
    const __m256d certain = _mm256_and_pd(
        _mm256_and_pd(inTable, _mm256_cmp_pd(_mm256_andnot_pd(signBit, fraction), roundingLimit, _CMP_LE_OQ)),
        _mm256_and_pd(_mm256_cmp_pd(_mm256_andnot_pd(signBit, _mm256_sub_pd(m, oz)), classBand, _CMP_GT_OQ),
                      _mm256_cmp_pd(_mm256_andnot_pd(signBit, _mm256_sub_pd(m, fz)), classBand, _CMP_GT_OQ)));
    alignas(32) std::array<std::int64_t, 4> quantised{};
    _mm256_store_si256(reinterpret_cast<__m256i*>(quantised.data()), q);
    for (unsigned j = 0; j < 4; ++j) {
      state[i + j].quantisedProbability = static_cast<std::uint16_t>(quantised[j]);
      state[i + j].occupancyClass =
          static_cast<std::int8_t>(static_cast<int>((above >> j) & 1) - ((below >> j) & 1));
    }
    for (unsigned rest = static_cast<unsigned>(~_mm256_movemask_pd(certain)) & 0xFU; rest != 0;
         rest &= rest - 1) {
      unsure[unsureCount++] =
          static_cast<std::uint32_t>(i + static_cast<std::size_t>(std::countr_zero(rest)));
    }
  };
  for (std::size_t i = 0; i + 8 <= n; i += 8) {
    const __m256 m = _mm256_loadu_ps(means + i);
    const __m256 z =
        _mm256_div_ps(m, _mm256_sqrt_ps(_mm256_add_ps(oneFloat, _mm256_loadu_ps(variances + i))));
    four(i, _mm256_cvtps_pd(_mm256_castps256_ps128(m)), _mm256_cvtps_pd(_mm256_castps256_ps128(z)));
    four(i + 4, _mm256_cvtps_pd(_mm256_extractf128_ps(m, 1)), _mm256_cvtps_pd(_mm256_extractf128_ps(z, 1)));
  }
  return unsureCount;
}
#endif

}  // namespace

PublishedStateRule::PublishedStateRule(double occupiedThreshold, double freeThreshold)
    : PublishedStateRule(occupiedThreshold, freeThreshold, cpuHasFma()) {}

PublishedStateRule::PublishedStateRule(double occupiedThreshold, double freeThreshold, bool avx2)
    : occupiedThreshold_(occupiedThreshold), freeThreshold_(freeThreshold),
      occupiedZ_(inverseNormalCdf(occupiedThreshold)), freeZ_(inverseNormalCdf(freeThreshold)),
      value_(normalCdfTable().value.data()), slope_(normalCdfTable().slope.data()), avx2_(avx2 && cpuHasFma()) {}

std::int8_t PublishedStateRule::occupancyClass(double mean) const { return stateOf(mean, 0.0).occupancyClass; }

std::uint16_t PublishedStateRule::quantisedProbability(double mean, double variance) const {
  return stateOf(mean, variance).quantisedProbability;
}

PublishedState PublishedStateRule::stateOf(double mean, double variance) const {
  PublishedState state;
  return tableState(value_, slope_, occupiedZ_, freeZ_, tableCoordinate(mean, variance), mean, state) ? state : exactStateOf(mean, variance);
}

void PublishedStateRule::statesOf(std::span<const float> means, std::span<const float> variances,
                                  std::span<PublishedState> out) const {
  std::size_t done = 0;
#if defined(__x86_64__) && defined(__GNUC__)
  if (avx2_) {
    std::array<std::uint32_t, kStage> unsure{};
    for (; done + 8 <= means.size(); done += kStage) {
      const std::size_t n = std::min(kStage, means.size() - done) / 8 * 8;
      const float* m = means.data() + done;
      const float* s = variances.data() + done;
      PublishedState* state = out.data() + done;
      const std::size_t count =
          tableStatesAvx2(value_, slope_, occupiedZ_, freeZ_, m, s, state, n, unsure.data());
      for (std::size_t j = 0; j < count; ++j) {
        state[unsure[j]] = exactStateOf(static_cast<double>(m[unsure[j]]), static_cast<double>(s[unsure[j]]));
      }
      if (n < kStage) {
        done += n;
        break;
      }
    }
  }
#endif
  std::array<double, kStage> u{};
  std::array<bool, kStage> exact{};
  for (std::size_t begin = done; begin < means.size(); begin += kStage) {
    const std::size_t n = std::min(kStage, means.size() - begin);
    const float* m = means.data() + begin;
    const float* s = variances.data() + begin;
    PublishedState* state = out.data() + begin;
    for (std::size_t i = 0; i < n; ++i) {
      u[i] = tableCoordinate(static_cast<double>(m[i]), static_cast<double>(s[i]));
    }
    bool anyExact = false;
    for (std::size_t i = 0; i < n; ++i) {
      exact[i] = !tableState(value_, slope_, occupiedZ_, freeZ_, u[i], static_cast<double>(m[i]), state[i]);
      anyExact |= exact[i];
    }
    if (anyExact) {
      for (std::size_t i = 0; i < n; ++i) {
        if (exact[i]) {
          state[i] = exactStateOf(static_cast<double>(m[i]), static_cast<double>(s[i]));
        }
      }
    }
  }
}

PublishedState PublishedStateRule::exactStateOf(double mean, double variance) const {
  return {quantiseProbability(predictiveProbability(mean, variance)),
          filter::occupancyClass(mean, occupiedThreshold_, freeThreshold_)};
}

}  // namespace ogf::filter
