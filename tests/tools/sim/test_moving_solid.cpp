// Moving solids: placed along their path at their time, seen by rays fired then, and the cells they swept.
#include <gtest/gtest.h>

#include <cmath>

#include "ogf/sim/ground_truth.hpp"
#include "ogf/sim/moving_solid.hpp"
#include "ogf/sim/world.hpp"

namespace ogf::sim {
namespace {

// A person (cylinder r 0.25 m, 1.75 m high) walking from (0, 0) to (4, 0) at 1 m/s from t = 1 s: gone at 5 s.
MovingSolidSpec walker() {
  MovingSolidSpec spec;
  spec.solid = Solid{Cylinder{{0.0, 0.0}, 0.25, 0.0, 1.75}, 1};
  spec.path.waypoints = {{0.0, 0.0, 0.0}, {4.0, 0.0, 0.0}};
  spec.path.speed = 1.0;
  spec.start_s = 1.0;
  return spec;
}

World worldWithWalker() {
  World w;
  w.materials = {Material{"default", 50, 0}, Material{"person", 30, 0}};
  w.solids = {Solid{HalfSpace{}, 0}};
  w.bounds = Aabb{{-1, -2, -0.4}, {5, 2, 2.4}};
  auto m = MovingSolid::build(walker());
  EXPECT_TRUE(m.ok());
  w.movers.push_back(std::move(*m));
  return w;
}

TEST(MovingSolid, PlacedAlongItsPathOnlyWhileItIsThere) {
  const auto m = MovingSolid::build(walker());
  ASSERT_TRUE(m.ok());
  EXPECT_DOUBLE_EQ(m->startS(), 1.0);
  EXPECT_DOUBLE_EQ(m->endS(), 5.0);
  EXPECT_FALSE(m->placedAt(0.5).has_value());
  EXPECT_FALSE(m->placedAt(5.5).has_value());
  const auto at3 = m->placedAt(3.0);
  ASSERT_TRUE(at3.has_value());
  const auto& c = std::get<Cylinder>(*at3);
  EXPECT_NEAR(c.centre.x(), 2.0, 1e-9);
  EXPECT_NEAR(c.centre.y(), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(c.z_max, 1.75);
}

TEST(MovingSolid, HalfSpacesAndNegativeStartsAreRefused) {
  MovingSolidSpec spec = walker();
  spec.solid.shape = HalfSpace{};
  EXPECT_FALSE(MovingSolid::build(spec).ok());
  spec = walker();
  spec.start_s = -1.0;
  EXPECT_FALSE(MovingSolid::build(spec).ok());
}

TEST(MovingSolid, RaysSeeItOnlyAtTheirTime) {
  const World w = worldWithWalker();
  const Ray across{{2.0, -3.0, 1.0}, {0.0, 1.0, 0.0}};  // horizontal, crossing the path at x = 2
  const auto hit = w.firstHit(across, 0.0, 10.0, 3.0);   // the person stands at x = 2 at t = 3 s
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->range, 2.75, 1e-9);
  EXPECT_EQ(w.materialOf(*hit).name, "person");
  EXPECT_FALSE(w.firstHit(across, 0.0, 10.0, 0.5).has_value());   // not there yet
  EXPECT_FALSE(w.firstHit(across, 0.0, 10.0, 4.5).has_value());   // walked past x = 2
  EXPECT_FALSE(w.firstHit(across, 0.0, 10.0).has_value());        // without a time, only the static world
}

TEST(MovingSolid, SweptCellsFollowThePathAndTheTruthNeverHoldsThePerson) {
  const World w = worldWithWalker();
  const GroundTruth truth = computeGroundTruth(w, 0.2);
  const GroundTruth swept = sweptCells(w, truth, 6.0);
  ASSERT_EQ(swept.cells.size(), truth.cells.size());
  const auto sweptAt = [&](double x, double y, double z) { return *swept.at(cellKeyOf({x, y, z}, 0.2)); };
  const auto truthAt = [&](double x, double y, double z) { return *truth.at(cellKeyOf({x, y, z}, 0.2)); };
  EXPECT_EQ(sweptAt(0.1, 0.1, 1.0), CellClass::Occupied);
  EXPECT_EQ(sweptAt(2.1, -0.1, 1.5), CellClass::Occupied);
  EXPECT_EQ(sweptAt(3.9, 0.1, 0.3), CellClass::Occupied);
  EXPECT_EQ(sweptAt(2.1, 1.1, 1.0), CellClass::Free);  // a metre beside the path
  EXPECT_EQ(sweptAt(2.1, 0.1, 2.1), CellClass::Free);  // above the head
  EXPECT_EQ(sweptAt(4.7, 0.1, 1.0), CellClass::Free);  // beyond the end of the path
  EXPECT_NE(truthAt(2.1, 0.1, 1.0), CellClass::Occupied);  // the truth is the room without the person
}

}  // namespace
}  // namespace ogf::sim
