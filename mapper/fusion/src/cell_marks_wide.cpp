// CellMarks::markQueuedAvx512: the queued rays traversed eight at a time, one per lane of 512-bit vectors,
// marking into the dense box.
//
// Each lane runs RayIterator's traversal (Amanatides & Woo with the tie rule of ray_caster.hpp) in the
// same double operations, so it visits the same cells as CellMarks' hashed traversal: at each step the axes
// whose next crossing is the smallest step, the upward ones alone when both directions tie. A lane whose ray
// has crossed its last boundary takes another queued ray, until the queue is empty. Each step marks the
// current cell of every active lane: the box's word index and bit follow from the cell by arithmetic in
// the vector, and each lane ORs its bit into its word.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <ogf/fusion/cell_marks.hpp>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace ogf::fusion {

#if defined(__x86_64__) && defined(__GNUC__)

// GCC 12's AVX-512 headers start some intrinsics from _mm512_undefined_*, which -Wmaybe-uninitialized
// reports once they are inlined (GCC bug 105593, fixed in GCC 13).
#if !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace {

// One axis of the eight lanes: RayIterator's cell_, step_, next_, delta_ and left_ for that axis.
struct LaneAxis {
  __m512i cell;
  __m512i step;
  __m512d next;
  __m512d delta;
  __m512i left;
  __mmask8 up;  // lanes stepping up this axis
};

}  // namespace

__attribute__((target("avx512f"))) void CellMarks::markQueuedAvx512() {
  const std::size_t rays = rays_.size();
  const RayIterator* ray = rays_.data();

  const __m512i zero = _mm512_setzero_si512();
  const __m512i one = _mm512_set1_epi64(1);
  const __m512i seven = _mm512_set1_epi64(7);
  const __m512d never = _mm512_set1_pd(std::numeric_limits<double>::infinity());

  LaneAxis ax{zero, zero, never, never, zero, 0};
  LaneAxis ay = ax;
  LaneAxis az = ax;
  __m512i crossings = zero;
  __mmask8 active = 0;

  // The box: word of a cell = 16·brick + local x, brick = ((x/8 − lo.x)·size.y + y/8 − lo.y)·size.z +
  // z/8 − lo.z with the cell taken relative to the box's first cell, so all is non-negative and small.
  const __m512i firstX = _mm512_set1_epi64(std::int64_t{box_.lo.x} * 8);
  const __m512i firstY = _mm512_set1_epi64(std::int64_t{box_.lo.y} * 8);
  const __m512i firstZ = _mm512_set1_epi64(std::int64_t{box_.lo.z} * 8);
  const __m512i sizeY = _mm512_set1_epi64(box_.size.y);
  const __m512i sizeZ = _mm512_set1_epi64(box_.size.z);
  const std::int64_t bricks = std::int64_t{box_.size.x} * box_.size.y * box_.size.z;
  const __m512i sinkWord = _mm512_set1_epi64(bricks * static_cast<std::int64_t>(kBoxWordsPerBrick));
  std::uint64_t* const words = box_.words.data();

  // Lane l takes the rays of the l-th eighth of the queue: neighbouring rays cross the same cells, and in
  // neighbouring lanes they would OR into the same words one after another, each waiting on the last.
  std::array<std::size_t, 8> from{};
  std::array<std::size_t, 8> to{};
  for (std::size_t lane = 0; lane < 8; ++lane) {
    from[lane] = rays * lane / 8;
    to[lane] = rays * (lane + 1) / 8;
  }
  // Loads the next ray of each lane of `lanes` that has one left; a lane whose eighth is done takes the
  // last ray of the eighth with the most left.
  const auto take = [&](unsigned lanes) __attribute__((target("avx512f"), always_inline)) {
    for (; lanes != 0; lanes &= lanes - 1) {
      const auto lane = static_cast<unsigned>(std::countr_zero(lanes));
      std::size_t index = 0;
      if (from[lane] < to[lane]) {
        index = from[lane]++;
      } else {
        std::size_t most = 0;
        for (std::size_t other = 1; other < 8; ++other) {
          if (to[other] - from[other] > to[most] - from[most]) most = other;
        }
        if (from[most] == to[most]) continue;  // the queue is empty: the lane stays inactive
        index = --to[most];
      }
      const RayIterator& r = ray[index];
      const auto k = static_cast<__mmask8>(1U << lane);
      const auto load = [&](LaneAxis & a, std::size_t i) __attribute__((target("avx512f"), always_inline)) {
        a.cell = _mm512_mask_set1_epi64(a.cell, k, r.cell_[i]);
        a.step = _mm512_mask_set1_epi64(a.step, k, r.step_[i]);
        a.next = _mm512_mask_mov_pd(a.next, k, _mm512_set1_pd(r.next_[i]));
        a.delta = _mm512_mask_mov_pd(a.delta, k, _mm512_set1_pd(r.delta_[i]));
        a.left = _mm512_mask_set1_epi64(a.left, k, r.left_[i]);
        a.up = static_cast<__mmask8>(r.step_[i] > 0 ? a.up | k : a.up & ~k);
      };
      load(ax, 0);
      load(ay, 1);
      load(az, 2);
      crossings = _mm512_mask_set1_epi64(crossings, k, r.crossings_left_);
      active = static_cast<__mmask8>(active | k);
    }
  };

  take(0xFFU);
  while (active != 0) {
    // Mark the current cell of each active lane; inactive lanes OR 0 into the spare brick.
    const __m512i x = _mm512_sub_epi64(ax.cell, firstX);
    const __m512i y = _mm512_sub_epi64(ay.cell, firstY);
    const __m512i z = _mm512_sub_epi64(az.cell, firstZ);
    const __m512i brick = _mm512_add_epi64(
        _mm512_mul_epu32(
            _mm512_add_epi64(_mm512_mul_epu32(_mm512_srli_epi64(x, 3), sizeY), _mm512_srli_epi64(y, 3)),
            sizeZ),
        _mm512_srli_epi64(z, 3));
    const __m512i word = _mm512_mask_mov_epi64(
        sinkWord, active, _mm512_add_epi64(_mm512_slli_epi64(brick, 4), _mm512_and_si512(x, seven)));
    const __m512i shift =
        _mm512_or_si512(_mm512_slli_epi64(_mm512_and_si512(y, seven), 3), _mm512_and_si512(z, seven));
    const __m512i bit = _mm512_maskz_sllv_epi64(active, one, shift);
    alignas(64) std::uint64_t index[8];
    alignas(64) std::uint64_t bits[8];
    _mm512_store_si512(index, word);
    _mm512_store_si512(bits, bit);
    for (std::size_t lane = 0; lane < 8; ++lane) words[index[lane]] |= bits[lane];

    // One step of each active lane: the axes whose next crossing is the smallest step. Where two tie in
    // some lane (rare: exact only for exact inputs), RayIterator::tiedAxes picks which; otherwise the
    // comparisons give the steps directly, which keeps a lane's chain from one step to the next short.
    const __m512d t = _mm512_min_pd(az.next, _mm512_min_pd(ay.next, ax.next));
    __mmask8 stepX = _mm512_mask_cmp_pd_mask(active, ax.next, t, _CMP_LE_OQ);
    __mmask8 stepY = _mm512_mask_cmp_pd_mask(active, ay.next, t, _CMP_LE_OQ);
    __mmask8 stepZ = _mm512_mask_cmp_pd_mask(active, az.next, t, _CMP_LE_OQ);
    if (((stepX & stepY) | (stepX & stepZ) | (stepY & stepZ)) != 0) {
      const auto upX = static_cast<unsigned>(stepX & ax.up);
      const auto upY = static_cast<unsigned>(stepY & ay.up);
      const auto upZ = static_cast<unsigned>(stepZ & az.up);
      const unsigned anyUp = upX | upY | upZ;
      stepX = static_cast<__mmask8>(upX | (stepX & ~anyUp));
      stepY = static_cast<__mmask8>(upY | (stepY & ~anyUp));
      stepZ = static_cast<__mmask8>(upZ | (stepZ & ~anyUp));
    }
    const auto advance = [&](LaneAxis & a, __mmask8 steps) __attribute__((target("avx512f"), always_inline)) {
      a.cell = _mm512_mask_add_epi64(a.cell, steps, a.cell, a.step);
      a.left = _mm512_mask_sub_epi64(a.left, steps, a.left, one);
      crossings = _mm512_mask_sub_epi64(crossings, steps, crossings, one);
      a.next = _mm512_mask_add_pd(a.next, steps, a.next, a.delta);
      a.next = _mm512_mask_mov_pd(a.next, _mm512_mask_cmpeq_epi64_mask(steps, a.left, zero), never);
    };
    advance(ax, stepX);
    advance(ay, stepY);
    advance(az, stepZ);
    const auto done = static_cast<__mmask8>(_mm512_mask_cmpeq_epi64_mask(active, crossings, zero));
    if (done != 0) {
      active = static_cast<__mmask8>(active & ~done);
      take(done);
    }
  }
}

#if !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#else

void CellMarks::markQueuedAvx512() {}  // never called: without AVX-512 CellMarks keeps hashed bricks

#endif

}  // namespace ogf::fusion
