// The compiled band kernels against the generic one: chosen for the stencils they were compiled for, never
// for another, and the same floats bit for bit on random records at every position of a block (banded and
// compact storage); the record
// locators likewise, and a record found across a block face where the offset points.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include "ogf/core/cell_key.hpp"
#include "ogf/filter/band_kernel.hpp"
#include "ogf/filter/stencil.hpp"
#include "ogf/filter/variance_code.hpp"

namespace ogf::filter {
namespace {

// 27 compact blocks (512 means, then 512 variance codes two to a float) of random values: means around 0,
// variance ratios in (0.001, 1].
std::vector<std::vector<float>> randomCompactBlocks(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> mean(-2.0F, 2.0F);
  std::uniform_real_distribution<float> logRatio(-3.0F, 0.0F);
  std::vector<std::vector<float>> blocks(27, std::vector<float>(512 + 256));
  for (auto& block : blocks) {
    auto* codes = reinterpret_cast<std::uint16_t*>(block.data() + 512);
    for (std::size_t l = 0; l < 512; ++l) {
      block[l] = mean(rng);
      codes[l] = encodeVarianceRatio(std::pow(10.0F, logRatio(rng)));
    }
  }
  return blocks;
}

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

// The 3-D stencils a kernel and a locator are compiled for.
std::vector<StencilShape> compiledShapes() {
  return {{std::sqrt(2.0), 2}, {1.0, 0}, {std::sqrt(2.0), 0}, {std::sqrt(3.0), 0}, {2.0, 0}};
}

std::vector<float*> pointers(std::vector<std::vector<float>>& blocks) {
  std::vector<float*> out;
  for (auto& b : blocks) {
    out.push_back(b.data());
  }
  return out;
}

// The records of the stencil cells of position `local`, as the filter passes them to a kernel.
std::vector<float*> records(const std::vector<float*>& blocks, std::size_t local, const BandTables& tables) {
  std::vector<float*> out;
  for (std::size_t s = 0; s < tables.cells; ++s) {
    out.push_back(tables.record(blocks.data(), local, s));
  }
  return out;
}

TEST(BandKernel, CompiledKernelsEqualTheGenericOneBitForBit) {
  for (const StencilShape& shape : compiledShapes()) {
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
        compiled(records(pa, local, tables).data(), u, tables);
        generic(records(pb, local, tables).data(), u, tables);
      }
      for (std::size_t d = 0; d < 27; ++d) {
        EXPECT_EQ(std::memcmp(a[d].data(), b[d].data(), a[d].size() * sizeof(float)), 0)
            << "block " << d << ", R " << shape.radius << ", L " << shape.manhattanRadius << ", fma " << fma;
      }
    }
  }
}

TEST(BandKernel, CompactKernelsEqualTheGenericOneBitForBit) {
  // The stencils with a kernel compiled for their size in compact storage, the √2 ball (19 cells) and the
  // ball with the six axial cells at distance 2 (25), in the baseline and (where this CPU has AVX2) in 8-wide
  // vectors with the cells past the last full vector one by one, against the one for any size.
  for (const auto& [shape, size] :
       {std::pair{StencilShape{std::sqrt(2.0), 0}, 19U}, std::pair{StencilShape{std::sqrt(2.0), 2}, 25U}}) {
    BandTables tables(Stencil(3, shape), 3, CovarianceStorage::kCompact);
    ASSERT_EQ(tables.cells, size);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0F, 1.0F);
    tables.priorVariance = 0.6F;
    for (std::size_t s = 0; s < tables.cells; ++s) {
      tables.correlation.push_back(s == tables.self ? tables.priorVariance : 0.3F * unit(rng));
    }
    for (const bool avx2 : {false, cpuHasFma()}) {
      const BandKernel compiled = compactBandKernelFor(tables, avx2);
      EXPECT_NE(compiled, &compactBandKernel) << size << " cells, avx2 " << avx2;
      auto a = randomCompactBlocks(9);
      auto b = a;
      const std::vector<float*> pa = pointers(a);
      const std::vector<float*> pb = pointers(b);
      std::vector<float*> ra(2 * tables.cells);
      std::vector<float*> rb(2 * tables.cells);
      for (int pass = 0; pass < 3; ++pass) {  // later passes reach variances the earlier ones lowered
        for (std::size_t local = 0; local < 512; ++local) {
          const BandUpdate u{2.0F * unit(rng) - 1.0F, 0.9F * unit(rng), 0.6F * 1e-9F};
          compactBandLocate(pa.data(), local, tables, ra.data());
          compactBandLocate(pb.data(), local, tables, rb.data());
          compiled(ra.data(), u, tables);
          compactBandKernel(rb.data(), u, tables);
        }
      }
      for (std::size_t d = 0; d < 27; ++d) {
        EXPECT_EQ(std::memcmp(a[d].data(), b[d].data(), a[d].size() * sizeof(float)), 0)
            << "block " << d << ", " << size << " cells, avx2 " << avx2;
      }
      EXPECT_NE(std::memcmp(a[13].data(), randomCompactBlocks(9)[13].data(), a[13].size() * sizeof(float)),
                0);
    }
  }
  // Another size takes the kernel for any size.
  EXPECT_EQ(compactBandKernelFor(BandTables(Stencil(3, {1.0, 0}), 3, CovarianceStorage::kCompact), true),
            &compactBandKernel);
}

TEST(BandKernel, CompiledLocatorsFindTheRecordsTheGenericOneFinds) {
  for (const StencilShape& shape : compiledShapes()) {
    const BandTables tables(Stencil(3, shape), 3);
    const BandLocate compiled = bandLocateFor(tables);
    EXPECT_NE(compiled, &genericBandLocate) << "R " << shape.radius << ", L " << shape.manhattanRadius;
    auto blocks = randomBlocks(tables, 5);
    const std::vector<float*> p = pointers(blocks);
    std::vector<float*> a(tables.cells);
    std::vector<float*> b(tables.cells);
    for (std::size_t local = 0; local < 512; ++local) {
      compiled(p.data(), local, tables, a.data());
      genericBandLocate(p.data(), local, tables, b.data());
      ASSERT_EQ(a, b) << "position " << local << ", R " << shape.radius << ", L " << shape.manhattanRadius;
      ASSERT_EQ(a, records(p, local, tables));
    }
  }
  // A stencil nothing was compiled for.
  EXPECT_EQ(bandLocateFor(BandTables(Stencil(3, {std::sqrt(5.0), 0}), 3)), &genericBandLocate);
}

TEST(BandKernel, RecordsOfAPositionAreWhereTheOffsetsPoint) {
  // Position (7, 0, 7) of the centre block: the cell one step along +x is (0, 0, 7) of the block at dx = +1,
  // one step along −y is (7, 7, 7) of the block at dy = −1.
  const Stencil stencil(3, {1.0, 0});
  const BandTables tables(stencil, 3);
  std::vector<std::vector<float>> blocks(27, std::vector<float>(512 * tables.stride));
  const std::vector<float*> p = pointers(blocks);
  const std::size_t local = 7 + 64 * 7;
  int checked = 0;
  for (std::size_t s = 0; s < tables.cells; ++s) {
    const CellKey o = stencil.offsets()[s];
    float* expected = nullptr;
    if (o == CellKey{1, 0, 0}) {
      expected = p[14] + (0 + 64 * 7) * tables.stride;
    } else if (o == CellKey{0, -1, 0}) {
      expected = p[10] + (7 + 8 * 7 + 64 * 7) * tables.stride;
    } else if (o == CellKey{0, 0, 0}) {
      expected = p[13] + local * tables.stride;
    } else {
      continue;
    }
    EXPECT_EQ(tables.record(p.data(), local, s), expected) << o.x << "," << o.y << "," << o.z;
    ++checked;
  }
  EXPECT_EQ(checked, 3);
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
