// Ray–solid intersection checked against brute-force marching along the ray with `contains`.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ogf/sim/intersect.hpp"
#include "ogf/sim/random.hpp"

namespace ogf::sim {
namespace {

constexpr double kStep = 1e-3;
constexpr double kMaxT = 12.0;

// First t > 0 at which the marched ray is inside the shape; negative when never.
double marchEntry(const Shape& shape, const Ray& ray) {
  for (double t = kStep; t < kMaxT; t += kStep) {
    if (contains(shape, ray.at(t))) return t;
  }
  return -1.0;
}

// From anywhere in an 8 x 8 x 6 m box, half aimed near the shapes (all within ~1.5 m of the origin) so
// most meet them, half in any direction.
Ray randomRay(Random& rng, int i) {
  Eigen::Vector3d o{rng.uniform() * 8 - 4, rng.uniform() * 8 - 4, rng.uniform() * 6 - 2};
  Eigen::Vector3d d{rng.normal(), rng.normal(), rng.normal()};
  if (i % 2 == 0) d = Eigen::Vector3d{rng.uniform() * 3 - 1.5, rng.uniform() * 3 - 1.5, rng.uniform() * 3 - 1.5} - o;
  return Ray{o, d.normalized()};
}

void expectMatchesMarching(const Shape& shape, std::uint64_t seed) {
  Random rng(seed);
  int compared = 0;
  for (int i = 0; i < 400; ++i) {
    const Ray ray = randomRay(rng, i);
    if (contains(shape, ray.origin)) {
      const auto c = intersect(shape, ray);
      ASSERT_TRUE(c.has_value()) << "origin inside but no crossing";
      EXPECT_LE(c->t_enter, 1e-9);
      EXPECT_GE(c->t_exit, -1e-9);
      continue;
    }
    const auto c = intersect(shape, ray);
    const double marched = marchEntry(shape, ray);
    if (c && c->t_enter > 0.0 && c->t_enter < kMaxT - 0.1 && c->t_exit - c->t_enter > 0.01) {
      EXPECT_NEAR(c->t_enter, marched, 2 * kStep) << "ray " << i;
      // The entering normal points against the ray.
      EXPECT_LT(c->normal.dot(ray.direction), 1e-9) << "ray " << i;
      EXPECT_NEAR(c->normal.norm(), 1.0, 1e-9);
      ++compared;
    } else if (!c || c->t_exit < 0.0) {
      EXPECT_LT(marched, 0.0) << "marching found a hit the analytic test missed, ray " << i;
    }
  }
  EXPECT_GT(compared, 50) << "too few rays met the shape to test anything";
}

TEST(SimIntersect, AxisAlignedBoxEntryMatchesMarching) {
  expectMatchesMarching(Box{{0.5, -0.3, 0.2}, {2.0, 1.0, 1.5}, 0.0}, 1);
}

TEST(SimIntersect, YawedBoxEntryMatchesMarching) {
  expectMatchesMarching(Box{{-0.5, 0.4, 0.0}, {2.5, 0.8, 1.2}, 0.6}, 2);
}

TEST(SimIntersect, VerticalCylinderEntryMatchesMarching) {
  expectMatchesMarching(Cylinder{{0.3, -0.2}, 1.1, -0.5, 1.5}, 3);
}

TEST(SimIntersect, HalfSpaceEntryMatchesMarching) {
  expectMatchesMarching(HalfSpace{Eigen::Vector3d{0.2, -0.3, 1.0}.normalized(), -0.5}, 4);
}

TEST(SimIntersect, GroundHitFromOneMetreAtFifteenDegreesDown) {
  const Ray ray{{0, 0, 1}, Eigen::Vector3d{std::cos(0.2618), 0, -std::sin(0.2618)}};
  const auto c = intersect(HalfSpace{}, ray);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->t_enter, 1.0 / std::sin(0.2618), 1e-12);
  EXPECT_EQ(c->normal, Eigen::Vector3d::UnitZ());
}

TEST(SimIntersect, RayParallelToCylinderAxisOutsideMisses) {
  EXPECT_FALSE(intersect(Cylinder{{0, 0}, 1.0, 0.0, 2.0}, Ray{{2, 0, 5}, {0, 0, -1}}));
  const auto c = intersect(Cylinder{{0, 0}, 1.0, 0.0, 2.0}, Ray{{0.5, 0, 5}, {0, 0, -1}});
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->t_enter, 3.0, 1e-12);  // through the top cap
  EXPECT_EQ(c->normal, Eigen::Vector3d::UnitZ());
}

}  // namespace
}  // namespace ogf::sim
