// The change detection's comparison of one layer: both paths against a cell-by-cell reading.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <ogf/filter/band_kernel.hpp>
#include <ogf/filter/layer_changes.hpp>
#include <random>

namespace ogf::filter {
namespace {

TEST(LayerChanges, BothPathsFindExactlyTheCellsWhoseMeanOrCodeDiffers) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pick(0, 7);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const bool avx2 : {true, false}) {
    if (avx2 && !cpuHasFma()) {
      continue;  // this CPU runs the cell-by-cell path only
    }
    const LayerChanges changes = layerChangesFor(avx2);
    for (int round = 0; round < 200; ++round) {
      std::array<float, kLayerCells> meansA{};
      std::array<float, kLayerCells> meansB{};
      std::array<std::uint16_t, kLayerCells> codesA{};
      std::array<std::uint16_t, kLayerCells> codesB{};
      std::uint64_t expected = 0;
      for (std::size_t j = 0; j < kLayerCells; ++j) {
        meansA[j] = static_cast<float>(j) * 0.25F - 3.0F;
        meansB[j] = meansA[j];
        codesA[j] = static_cast<std::uint16_t>(40000 + j);
        codesB[j] = codesA[j];
        bool differs = false;
        switch (pick(rng)) {
          case 0:  // the mean moved by one step of the float
            meansB[j] = std::nextafter(meansA[j], std::numeric_limits<float>::infinity());
            differs = true;
            break;
          case 1:  // the code alone, in its high byte
            codesB[j] = static_cast<std::uint16_t>(codesA[j] ^ 0x8000U);
            differs = true;
            break;
          case 2:  // the code alone, in its low bit
            codesB[j] = static_cast<std::uint16_t>(codesA[j] ^ 1U);
            differs = true;
            break;
          case 3:  // +0 and −0 are the same mean
            meansA[j] = 0.0F;
            meansB[j] = -0.0F;
            break;
          case 4:  // a NaN never equals itself
            meansA[j] = nan;
            meansB[j] = nan;
            differs = true;
            break;
          default:
            break;
        }
        expected |= static_cast<std::uint64_t>(differs) << j;
      }
      ASSERT_EQ(changes(meansA.data(), codesA.data(), meansB.data(), codesB.data()), expected)
          << (avx2 ? "AVX2 path" : "cell-by-cell path") << ", round " << round;
    }
  }
}

}  // namespace
}  // namespace ogf::filter
