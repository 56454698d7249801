// The OctoMap baseline: OctoMap's own sensor model and threshold, on the cells our keys name.
#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include <unistd.h>

#include "ogf/eval/octomap_baseline.hpp"

namespace {

using ogf::CellKey;
using ogf::Measurement;
using ogf::eval::OctomapBaseline;

TEST(OctomapBaseline, OneHitIsOccupiedAtProbabilityPointSevenAndOneMissFreeAtPointFour) {
  OctomapBaseline tree(0.2);
  const std::vector<Measurement> scan{{{3, -2, 1}, Measurement::kOccupied}, {{2, -2, 1}, Measurement::kFree}};
  tree.insert(scan);
  tree.finish();
  const auto hit = tree.estimate({3, -2, 1});
  EXPECT_EQ(hit.cell_class, 1);
  EXPECT_NEAR(hit.probability, 0.7, 1e-6);
  const auto miss = tree.estimate({2, -2, 1});
  EXPECT_EQ(miss.cell_class, -1);
  EXPECT_NEAR(miss.probability, 0.4, 1e-6);
}

TEST(OctomapBaseline, ACellWithoutANodeIsUnknownAtThePrior) {
  OctomapBaseline tree(0.2);
  tree.insert(std::vector<Measurement>{{{0, 0, 0}, Measurement::kOccupied}});
  tree.finish();
  const auto e = tree.estimate({5, 5, 5});
  EXPECT_EQ(e.cell_class, 0);
  EXPECT_DOUBLE_EQ(e.probability, 0.5);
}

TEST(OctomapBaseline, HitsAndMissesAccumulateAsLogOdds) {
  OctomapBaseline tree(0.2);
  // Hit, miss, miss: logit(0.7) + 2 logit(0.4) = 0.8473 - 0.8109 = 0.0364 > 0: still occupied (p 0.509).
  for (std::int8_t y : {Measurement::kOccupied, Measurement::kFree, Measurement::kFree})
    tree.insert(std::vector<Measurement>{{{1, 1, 1}, y}});
  tree.finish();
  const auto e = tree.estimate({1, 1, 1});
  EXPECT_EQ(e.cell_class, 1);
  EXPECT_NEAR(e.probability, 0.509, 1e-3);
}

TEST(OctomapBaseline, AWrittenTreeLoadsBackWithTheSameClasses) {
  OctomapBaseline tree(0.2);
  tree.insert(std::vector<Measurement>{{{-4, 7, 2}, Measurement::kOccupied}, {{-3, 7, 2}, Measurement::kFree}});
  tree.finish();
  const auto path = std::filesystem::temp_directory_path() / ("ogf-eval-octomap-" + std::to_string(::getpid()) + ".bt");
  ASSERT_TRUE(tree.write(path).ok());
  auto loaded = OctomapBaseline::load(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_DOUBLE_EQ(loaded->resolution(), 0.2);
  EXPECT_EQ(loaded->estimate({-4, 7, 2}).cell_class, 1);
  EXPECT_EQ(loaded->estimate({-3, 7, 2}).cell_class, -1);
  EXPECT_EQ(loaded->estimate({0, 0, 0}).cell_class, 0);
}

}  // namespace
