// The compiled band kernels against the generic one: chosen for the stencils they were compiled for, never
// for another, and the same floats bit for bit on random records at every position of a block.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "ogf/filter/band_kernel.hpp"
#include "ogf/filter/stencil.hpp"

namespace ogf::filter {
namespace {

// 27 blocks of random records (means around 0, positive variances, small covariances).
std::vector<std::vector<float>> randomBlocks(const BandTables& tables, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(-0.5F, 0.5F);
  std::vector<std::vector<float>> blocks(27, std::vector<float>(512 * tables.stride));
  for (auto& block : blocks) {
    for (std::size_t i = 0; i < block.size(); ++i) {
      block[i] = i % tables.stride == 1 ? 1.0F + value(rng) : value(rng);
    }
  }
  return blocks;
}

std::vector<float*> pointers(std::vector<std::vector<float>>& blocks) {
  std::vector<float*> out;
  for (auto& b : blocks) {
    out.push_back(b.data());
  }
  return out;
}

TEST(BandKernel, CompiledKernelsEqualTheGenericOneBitForBit) {
  const StencilShape shapes[] = {{std::sqrt(2.0), 2}, {1.0, 0}, {std::sqrt(2.0), 0}, {std::sqrt(3.0), 0}, {2.0, 0}};
  for (const StencilShape& shape : shapes) {
    const Stencil stencil(3, shape);
    const BandTables tables(stencil, 3);
    // The baseline arithmetic, and the fused one where this CPU has FMA.
    for (const bool fma : {false, cpuHasFma()}) {
      const BandKernel compiled = bandKernelFor(tables, fma);
      const BandKernel generic = genericBandKernelFor(fma);
      EXPECT_NE(compiled, generic) << "R " << shape.radius << ", L " << shape.manhattanRadius;
      auto a = randomBlocks(tables, 7);
      auto b = a;
      const std::vector<float*> pa = pointers(a);
      const std::vector<float*> pb = pointers(b);
      std::mt19937 rng(3);
      std::uniform_real_distribution<float> gain(-0.5F, 0.5F);
      std::uniform_real_distribution<float> shrink(0.0F, 0.3F);
      for (std::size_t local = 0; local < 512; ++local) {
        const BandUpdate u{gain(rng), shrink(rng), 1e-9F};
        compiled(pa.data(), local, u, tables);
        generic(pb.data(), local, u, tables);
      }
      for (std::size_t d = 0; d < 27; ++d) {
        EXPECT_EQ(std::memcmp(a[d].data(), b[d].data(), a[d].size() * sizeof(float)), 0)
            << "block " << d << ", R " << shape.radius << ", L " << shape.manhattanRadius << ", fma " << fma;
      }
    }
  }
}

TEST(BandKernel, OtherStencilsUseTheGenericKernel) {
  // A 3-D stencil nothing was compiled for, and the default shape in 2-D (a disc, other tables).
  for (const bool fma : {false, cpuHasFma()}) {
    EXPECT_EQ(bandKernelFor(BandTables(Stencil(3, {std::sqrt(5.0), 0}), 3), fma), genericBandKernelFor(fma));
    EXPECT_EQ(bandKernelFor(BandTables(Stencil(2, {std::sqrt(2.0), 2}), 2), fma), genericBandKernelFor(fma));
  }
  EXPECT_EQ(genericBandKernelFor(false), &genericBandKernel);
}

}  // namespace
}  // namespace ogf::filter
