// On the real benchmark logs: a FLASER record's second triple is raw odometry, so scoring the input logs
// themselves must give the raw-odometry figures of docs/test-data.md §3.1 (computed with metricEvaluator's
// definition, §3.4) to the printed precision, with every relation stamp matched.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "ogf/slam_io/laser_trajectory.hpp"
#include "ogf/slam_io/relations.hpp"
#include "support/shared_data.hpp"

namespace {

using namespace ogf::slam_io;

struct RawOdometryCase {
  const char* name;
  double mean;  // metres, two decimals as printed
  double std;
  std::size_t relations;
};

class RawOdometryScores : public ::testing::TestWithParam<RawOdometryCase> {};

TEST_P(RawOdometryScores, ReproduceTheFiguresInSources) {
  const RawOdometryCase c = GetParam();
  const std::string log_name = std::string("data/slam/") + c.name + ".clf";
  const std::string relations_name = std::string("data/slam/") + c.name + ".relations";
  OGF_REQUIRE_SHARED_FILE(log_path, log_name);
  OGF_REQUIRE_SHARED_FILE(relations_path, relations_name);

  std::ifstream log(log_path);
  const LaserTrajectory trajectory = readLaserTrajectory(log, log_path.string());
  EXPECT_TRUE(trajectory.malformed.empty()) << trajectory.malformed.front().message;
  ASSERT_FALSE(trajectory.poses.empty());

  std::ifstream rel(relations_path);
  const auto relations = readRelations(rel, relations_path.string());
  ASSERT_TRUE(relations.ok()) << relations.error().message;
  EXPECT_EQ(relations->size(), c.relations);

  const RelationMetric m = evaluateRelations(trajectory.poses, *relations);
  EXPECT_EQ(m.unmatched, 0u);
  EXPECT_EQ(m.translation.count, c.relations);
  EXPECT_NEAR(m.translation.mean, c.mean, 0.005) << c.name;
  EXPECT_NEAR(m.translation.std, c.std, 0.005) << c.name;
}

INSTANTIATE_TEST_SUITE_P(Benchmark, RawOdometryScores,
                         ::testing::Values(RawOdometryCase{"intel", 7.37, 14.35, 2984},
                                           RawOdometryCase{"aces", 0.55, 2.68, 1279},
                                           RawOdometryCase{"fr079", 6.50, 13.67, 1685}),
                         [](const auto& test_case) { return std::string(test_case.param.name); });

}  // namespace
