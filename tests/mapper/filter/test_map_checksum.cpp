// The block checksums computed four at a time equal the one-block function, and a map's checksum is the sum
// of its blocks' one-block checksums whatever mix of known and changed block hashes it starts from.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/map_checksum.hpp"

namespace ogf::filter {
namespace {

TEST(MapChecksum, FourBlocksAtOnceEqualOneAtATime) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> value(-5.0F, 5.0F);
  // Sizes with and without bytes after the last whole 8-byte word.
  for (const std::size_t floats : {std::size_t{0}, std::size_t{1}, std::size_t{768}, std::size_t{769}}) {
    for (const std::size_t markCount : {std::size_t{0}, std::size_t{64}, std::size_t{67}}) {
      std::vector<std::vector<float>> stored(4, std::vector<float>(floats));
      std::vector<std::vector<std::uint8_t>> marks(4, std::vector<std::uint8_t>(markCount));
      std::array<BlockBytes, 4> blocks;
      for (std::size_t j = 0; j < 4; ++j) {
        for (float& f : stored[j]) f = value(rng);
        for (std::uint8_t& m : marks[j]) m = static_cast<std::uint8_t>(rng());
        blocks[j] = {CellKey{static_cast<int>(j) - 2, 7, -3}, stored[j], marks[j]};
      }
      const std::array<std::uint64_t, 4> together = blockChecksums(blocks);
      for (std::size_t j = 0; j < 4; ++j) {
        EXPECT_EQ(together[j], blockChecksum(blocks[j].key, stored[j], marks[j]))
            << floats << " floats, " << markCount << " marks, block " << j;
      }
    }
  }
}

TEST(MapChecksum, FourBlocksOfDifferentSizesEqualOneAtATime) {
  const std::vector<float> a{1.0F, 2.0F, 3.0F};
  const std::vector<float> b{4.0F};
  const std::vector<std::uint8_t> m{1, 2, 3, 4, 5, 6, 7, 8, 9};
  const std::array<BlockBytes, 4> blocks{{{CellKey{0, 0, 0}, a, m}, {CellKey{1, 0, 0}, b, m},
                                          {CellKey{2, 0, 0}, {}, m}, {CellKey{3, 0, 0}, a, {}}}};
  const std::array<std::uint64_t, 4> together = blockChecksums(blocks);
  for (std::size_t j = 0; j < 4; ++j) {
    EXPECT_EQ(together[j], blockChecksum(blocks[j].key, blocks[j].stored, blocks[j].marks)) << "block " << j;
  }
}

TEST(MapChecksum, MapSumIsTheSumOfEachBlocksChecksum) {
  FilterConfig config;
  config.covariance = CovarianceStorage::kCompact;
  auto map = BandedOgf::create(config);
  ASSERT_TRUE(map.ok());
  std::mt19937 rng(9);
  const auto reference = [&] {
    BlockHashSum sum;
    for (const CellKey& key : map->blockKeys()) {
      sum.sum += blockChecksum(key, map->storedValues(key), map->blockMarks(key));
      ++sum.blocks;
    }
    return sum;
  };
  // Batches that change some blocks and leave others: each sum starts from known hashes and a number of
  // changed blocks that is not always a multiple of four.
  for (int round = 0; round < 6; ++round) {
    std::vector<Measurement> batch;
    for (int i = 0; i < 40 + 13 * round; ++i) {
      const CellKey k{static_cast<int>(rng() % 80U) - 40, static_cast<int>(rng() % 80U) - 40,
                      static_cast<int>(rng() % 8U) - 4};
      batch.push_back({k, static_cast<std::int8_t>(rng() % 3U == 0 ? 1 : -1)});
    }
    map->update(batch);
    const BlockHashSum expected = reference();
    const BlockHashSum got = map->blockHashSum();
    EXPECT_EQ(got.blocks, expected.blocks) << "round " << round;
    EXPECT_EQ(got.sum, expected.sum) << "round " << round;
  }
}

}  // namespace
}  // namespace ogf::filter
