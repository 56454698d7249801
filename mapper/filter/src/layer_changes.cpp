// The cells of a layer whose mean or variance code differ between two copies.
#include "ogf/filter/layer_changes.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace ogf::filter {
namespace {

std::uint64_t layerChangesScalar(const float* meansA, const std::uint16_t* codesA, const float* meansB,
                                 const std::uint16_t* codesB) {
  std::uint64_t changed = 0;
  for (std::size_t j = 0; j < kLayerCells; ++j) {
    const bool differs = !(meansA[j] == meansB[j]) || codesA[j] != codesB[j];
    changed |= static_cast<std::uint64_t>(differs) << j;
  }
  return changed;
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) std::uint64_t layerChangesAvx2(const float* meansA,
                                                               const std::uint16_t* codesA,
                                                               const float* meansB,
                                                               const std::uint16_t* codesB) {
  std::uint64_t changed = 0;
  for (unsigned i = 0; i < kLayerCells / 8; ++i) {
    const __m256 a = _mm256_loadu_ps(meansA + 8 * i);
    const __m256 b = _mm256_loadu_ps(meansB + 8 * i);
    // Not equal, or unordered: the negation of the scalar ==.
    const auto bits = static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_NEQ_UQ)));
    changed |= static_cast<std::uint64_t>(bits) << (8 * i);
  }
  std::uint64_t equalCodes = 0;
  for (unsigned i = 0; i < kLayerCells / 32; ++i) {
    const auto* a = reinterpret_cast<const __m256i*>(codesA + 32 * i);
    const auto* b = reinterpret_cast<const __m256i*>(codesB + 32 * i);
    const __m256i low = _mm256_cmpeq_epi16(_mm256_loadu_si256(a), _mm256_loadu_si256(b));
    const __m256i high = _mm256_cmpeq_epi16(_mm256_loadu_si256(a + 1), _mm256_loadu_si256(b + 1));
    // Each 16-bit all-ones or zero word to one byte; the pack works per 128-bit lane, so the lanes are put
    // back in order (0, 2, 1, 3) before a byte per cell becomes a bit.
    const __m256i bytes = _mm256_permute4x64_epi64(_mm256_packs_epi16(low, high), 0xD8);
    const auto bits = static_cast<std::uint32_t>(_mm256_movemask_epi8(bytes));
    equalCodes |= static_cast<std::uint64_t>(bits) << (32 * i);
  }
  return changed | ~equalCodes;
}
#endif

}  // namespace

LayerChanges layerChangesFor(bool avx2) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (avx2) {
    return layerChangesAvx2;
  }
#endif
  (void)avx2;
  return layerChangesScalar;
}

}  // namespace ogf::filter
