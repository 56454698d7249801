// The variance of a cell in compact storage (CovarianceStorage::kCompact), kept in 16 bits: its ratio to
// the prior variance, r = Σ_ii / Σ0_ii, which eq. (5) only ever lowers from 1, as a float with the sign
// dropped, 5 exponent bits for [2^-31, 2) and 11 mantissa bits. Rounded to nearest, a stored ratio is within
// a relative 2^-12 (0.024 %) of the computed one at any magnitude; ratios below 2^-31 (4.7e-10, under the
// filter's variance floor of 1e-9) are held at 2^-31.
#pragma once

#include <bit>
#include <cstdint>

namespace ogf::filter {

// Float bits of 2^-31: the smallest ratio kept, code 0.
inline constexpr std::uint32_t kVarianceCodeBase = (127U - 31U) << 23;
inline constexpr float kSmallestVarianceRatio = 4.656612873077393e-10F;  // 2^-31

inline std::uint16_t encodeVarianceRatio(float ratio) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(ratio);
  if (!(ratio >= kSmallestVarianceRatio)) {  // below 2^-31, or NaN
    return 0;
  }
  if (ratio >= 2.0F) {
    return 0xFFFF;
  }
  // Round the 23-bit mantissa to 11 bits (to nearest, ties up); a carry moves into the exponent.
  const std::uint32_t rounded = (bits - kVarianceCodeBase + (1U << 11)) >> 12;
  return static_cast<std::uint16_t>(rounded > 0xFFFFU ? 0xFFFFU : rounded);
}

inline float decodeVarianceRatio(std::uint16_t code) {
  return std::bit_cast<float>((static_cast<std::uint32_t>(code) << 12) + kVarianceCodeBase);
}

}  // namespace ogf::filter
