// The relations file (8 fields, comments, errors naming the line) and the metric on cases computed by hand:
// the T1^-1 T2 convention in a rotated frame, component-wise deltas, angle wrap-around, sample standard
// deviation, nearest-stamp matching within the tolerance (mit-csail prints 5 decimals) and unmatched stamps.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "ogf/slam_io/relations.hpp"

namespace {

using namespace ogf::slam_io;

constexpr double kPi = std::numbers::pi;
constexpr double kRadToDeg = 180.0 / kPi;

TEST(ReadRelations, ParsesRealLinesAndSkipsComments) {
  std::istringstream in(
      "# t1 t2 x y z roll pitch yaw\n"
      "976052905.167303 976052911.885496 -0.056990 -0.128430 0.000000 0.000000 0.000000 -1.682210\n"
      "\n"
      "90.239599 90.719599 0.422330 -0.000750 0.000000 0.000000 0.000000 0.017260\r\n");
  const auto relations = readRelations(in, "intel.relations");
  ASSERT_TRUE(relations.ok()) << relations.error().message;
  ASSERT_EQ(relations->size(), 2u);
  const Relation& r = (*relations)[0];
  EXPECT_DOUBLE_EQ(r.t1, 976052905.167303);
  EXPECT_DOUBLE_EQ(r.t2, 976052911.885496);
  EXPECT_DOUBLE_EQ(r.motion.x, -0.05699);
  EXPECT_DOUBLE_EQ(r.motion.y, -0.12843);
  EXPECT_DOUBLE_EQ(r.motion.theta, -1.68221);
  EXPECT_EQ(r.line, 2u);
  EXPECT_EQ((*relations)[1].line, 4u);
}

TEST(ReadRelations, ErrorsNameTheSourceAndLine) {
  const auto fails = [](const std::string& text) {
    std::istringstream in(text);
    const auto r = readRelations(in, "x.relations");
    return r.ok() ? std::string() : r.error().message;
  };
  const std::string good = "1 2 0 0 0 0 0 0\n";
  EXPECT_NE(fails(good + "1 2 0 0 0 0 0\n").find("x.relations:2:"), std::string::npos);
  EXPECT_NE(fails(good + good + "1 2 0 zero 0 0 0 0\n").find("x.relations:3:"), std::string::npos);
  EXPECT_NE(fails("1 2 0 0 0.5 0 0 0\n").find("x.relations:1:"), std::string::npos);  // not planar
  EXPECT_EQ(fails(good), "");
}

std::vector<StampedPose> twoPoses(Pose2 a, Pose2 b) { return {{0.0, a}, {1.0, b}}; }

TEST(EvaluateRelations, AnExactTrajectoryScoresZero) {
  const auto m = evaluateRelations(twoPoses({0, 0, 0}, {1, 0, kPi / 2}), {{0.0, 1.0, {1, 0, kPi / 2}, 1}});
  EXPECT_EQ(m.translation.count, 1u);
  EXPECT_NEAR(m.translation.mean, 0.0, 1e-12);
  EXPECT_NEAR(m.rotation_deg.mean, 0.0, 1e-12);
  EXPECT_EQ(m.unmatched, 0u);
}

TEST(EvaluateRelations, MotionIsTakenInTheFrameOfTheFirstPose) {
  // The robot at (1, 2) facing +y moves 1 m forward to (1, 3): in its own frame that is (1, 0, 0).
  // Against a reference of (0, 1, 0): dx = 1, dy = -1, so sqrt(2). (The world-frame difference would be 0.)
  const auto m = evaluateRelations(twoPoses({1, 2, kPi / 2}, {1, 3, kPi / 2}), {{0.0, 1.0, {0, 1, 0}, 1}});
  EXPECT_NEAR(m.translation.mean, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(m.rotation_deg.mean, 0.0, 1e-12);
}

TEST(EvaluateRelations, DeltasAreComponentWiseInMetresAndDegrees) {
  // Estimated (1, 0, pi/2), reference (1, 0.5, pi/2 - 0.1): 0.5 m and 0.1 rad = 5.7296 degrees.
  const auto m =
      evaluateRelations(twoPoses({0, 0, 0}, {1, 0, kPi / 2}), {{0.0, 1.0, {1, 0.5, kPi / 2 - 0.1}, 1}});
  EXPECT_NEAR(m.translation.mean, 0.5, 1e-12);
  EXPECT_NEAR(m.rotation_deg.mean, 0.1 * kRadToDeg, 1e-9);
  EXPECT_NEAR(m.rotation_deg.mean, 5.729578, 1e-6);
}

TEST(EvaluateRelations, AngleDifferencesWrapAroundPi) {
  // Estimated yaw pi - 0.05, reference -pi + 0.05: 0.1 rad apart, not 2 pi - 0.1.
  const auto m =
      evaluateRelations(twoPoses({0, 0, 0}, {0, 0, kPi - 0.05}), {{0.0, 1.0, {0, 0, -kPi + 0.05}, 1}});
  EXPECT_NEAR(m.rotation_deg.mean, 0.1 * kRadToDeg, 1e-9);
}

TEST(EvaluateRelations, StatisticsAreMeanSampleStdAndMax) {
  // Three relations on a straight line x = t with errors 0, 0.5 and 2 m.
  const std::vector<StampedPose> line = {{0, {0, 0, 0}}, {1, {1, 0, 0}}, {2, {2, 0, 0}}, {3, {3, 0, 0}}};
  const std::vector<Relation> relations = {
      {0, 1, {1, 0, 0}, 1}, {1, 2, {1.5, 0, 0}, 2}, {0, 3, {1, 0, 0}, 3}};
  const auto m = evaluateRelations(line, relations);
  EXPECT_EQ(m.translation.count, 3u);
  EXPECT_NEAR(m.translation.mean, 2.5 / 3.0, 1e-12);
  // Sample variance: ((5/6)^2 + (1/3)^2 + (7/6)^2) / 2 = (25 + 4 + 49) / 72 = 78 / 72.
  EXPECT_NEAR(m.translation.std, std::sqrt(78.0 / 72.0), 1e-12);
  EXPECT_NEAR(m.translation.max, 2.0, 1e-12);
  EXPECT_NEAR(m.rotation_deg.max, 0.0, 1e-12);
  // Squared errors 0, 0.25, 4: mean 4.25 / 3, sample variance ((17/12)^2 + (7/6)^2 + (31/12)^2) / 2.
  EXPECT_NEAR(m.translation_squared.mean, 4.25 / 3.0, 1e-12);
  EXPECT_NEAR(m.translation_squared.std, std::sqrt((289.0 + 196.0 + 961.0) / 144.0 / 2.0), 1e-12);
  EXPECT_NEAR(m.translation_squared.max, 4.0, 1e-12);
}

TEST(EvaluateRelations, StampsMatchTheNearestPoseWithinTheTolerance) {
  // Laser stamps with 6 decimals; relations printed with 5 (as mit-csail's) still match.
  const std::vector<StampedPose> poses = {
      {976052905.167303, {0, 0, 0}}, {976052905.367303, {5, 5, 0}}, {976052911.885496, {1, 0, 0}}};
  const std::vector<Relation> relations = {
      {976052905.16730, 976052911.88550, {1, 0, 0}, 1},  // matches the first and third pose: error 0
      {976052905.16730, 976052912.5, {1, 0, 0}, 2},      // 0.61 s from any pose: unmatched
  };
  const auto m = evaluateRelations(poses, relations, 0.1);
  EXPECT_EQ(m.unmatched, 1u);
  EXPECT_EQ(m.translation.count, 1u);
  EXPECT_NEAR(m.translation.mean, 0.0, 1e-12);
  // A tolerance wide enough takes the nearest pose for the far stamp.
  EXPECT_EQ(evaluateRelations(poses, relations, 1.0).unmatched, 0u);
}

TEST(EvaluateRelations, NoPosesMeansEveryRelationIsUnmatched) {
  const auto m = evaluateRelations({}, {{0, 1, {1, 0, 0}, 1}});
  EXPECT_EQ(m.unmatched, 1u);
  EXPECT_EQ(m.translation.count, 0u);
}

}  // namespace
