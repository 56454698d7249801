// Ground truth: cells classified by the CellKey convention, and truth.grid written and read back.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>

#include "ogf/sim/ground_truth.hpp"
#include "ogf/sim/scene.hpp"
#include "sim_test_paths.hpp"

namespace ogf::sim {
namespace {

// Ground at z = 0 and a 1 m cube on it at x, y in [1, 2]; grid [0, 3) x [0, 3) x [-0.4, 2).
World groundAndCube() {
  World w;
  w.materials = {Material{"default", 50, 0}};
  w.solids = {Solid{HalfSpace{}, 0}, Solid{Box{{1.5, 1.5, 0.5}, {1.0, 1.0, 1.0}, 0.0}, 0}};
  w.bounds = Aabb{{0, 0, -0.4}, {3, 3, 2}};
  return w;
}

std::string tempPath(const std::string& name) {
  return test::scratchPath(name).string();
}

TEST(SimGroundTruth, GridCoversBoundsWithCellKeyConvention) {
  const GroundTruth t = computeGroundTruth(groundAndCube(), 0.2);
  EXPECT_EQ(t.min_key, (CellKey{0, 0, -2}));
  EXPECT_EQ(t.size, (std::array<std::int32_t, 3>{15, 15, 12}));
  EXPECT_EQ(t.cells.size(), 15u * 15u * 12u);
  EXPECT_FALSE(t.at({15, 0, 0}).has_value());
  EXPECT_FALSE(t.at({0, 0, -3}).has_value());
}

TEST(SimGroundTruth, SurfaceOnACellBoundaryBelongsToTheCellAboveIt) {
  const GroundTruth t = computeGroundTruth(groundAndCube(), 0.2);
  // The ground plane z = 0 lies in cells k = 0 ([0, 0.2)), as floor(0 / 0.2) = 0 puts a point on it.
  EXPECT_EQ(t.at({0, 0, 0}), CellClass::Occupied);
  EXPECT_EQ(t.at({0, 0, -1}), CellClass::Unobservable);
  EXPECT_EQ(t.at({0, 0, 1}), CellClass::Free);
  // The cube's faces x = 1 (cell i = 5) and x = 2 (cell i = 10); inside between.
  EXPECT_EQ(t.at({5, 7, 2}), CellClass::Occupied);
  EXPECT_EQ(t.at({6, 7, 2}), CellClass::Unobservable);
  EXPECT_EQ(t.at({9, 7, 2}), CellClass::Unobservable);
  EXPECT_EQ(t.at({10, 7, 2}), CellClass::Occupied);
  EXPECT_EQ(t.at({4, 7, 2}), CellClass::Free);
  EXPECT_EQ(t.at({11, 7, 2}), CellClass::Free);
  // Its top z = 1 is in k = 5.
  EXPECT_EQ(t.at({7, 7, 5}), CellClass::Occupied);
  EXPECT_EQ(t.at({7, 7, 6}), CellClass::Free);
}

TEST(SimGroundTruth, FacesRoundedNextToACellBoundaryLieOnIt) {
  // The lab's north and east walls: centre 8.1 (10.1), size 0.2, so they span 7.999999999999999 ..
  // 8.2 in floating point. Both faces lie on cell boundaries: the lower face in cell 40 ([8.0, 8.2)), the
  // upper one in cell 41 ([8.2, 8.4)), as floor(p / r) puts a return on each; cell 39 is open air.
  World w;
  w.materials = {Material{"default", 50, 0}};
  w.solids = {Solid{HalfSpace{}, 0}, Solid{Box{{5.0, 8.1, 1.5}, {10.4, 0.2, 3.0}, 0.0}, 0},
              Solid{Box{{10.1, 4.0, 1.5}, {0.2, 8.0, 3.0}, 0.0}, 0}};
  w.bounds = Aabb{{-0.4, -0.4, -0.4}, {10.4, 8.4, 3.4}};
  const GroundTruth t = computeGroundTruth(w, 0.2);
  EXPECT_EQ(t.at({25, 39, 5}), CellClass::Free);
  EXPECT_EQ(t.at({25, 40, 5}), CellClass::Occupied);
  EXPECT_EQ(t.at({25, 41, 5}), CellClass::Occupied);
  EXPECT_EQ(t.at({49, 20, 5}), CellClass::Free);
  EXPECT_EQ(t.at({50, 20, 5}), CellClass::Occupied);
  EXPECT_EQ(t.at({51, 20, 5}), CellClass::Occupied);
}

// The occupied cells a line parallel to `axis` crosses, as keys along that axis, within [from, to] metres.
std::vector<std::int32_t> occupiedAlong(const GroundTruth& t, int axis, const Eigen::Vector3d& through, double from,
                                        double to) {
  std::vector<std::int32_t> keys;
  const double r = t.resolution;
  CellKey k = cellKeyOf(through, r);
  for (auto i = static_cast<std::int32_t>(std::floor(from / r)); i <= static_cast<std::int32_t>(std::floor(to / r));
       ++i) {
    (axis == 0 ? k.x : k.y) = i;
    if (t.at(k) == CellClass::Occupied) keys.push_back(i);
  }
  return keys;
}

TEST(SimGroundTruth, AllFourLabWallsHaveOneOccupiedCellPerFace) {
  // Each 0.2 m wall of the lab has its two faces on cell boundaries at every resolution that divides
  // 0.2; a line at 1.1 m height crossing it meets exactly the two cells floor(face / r), for all four walls.
  const auto scene = presetScene("lab");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  for (const double r : {0.2, 0.1, 0.05}) {
    SCOPED_TRACE(r);
    const GroundTruth t = computeGroundTruth(scene->world, r, {Eigen::Vector3d{3.5, 3.5, 1.0}});
    const auto face = [r](double metres) { return static_cast<std::int32_t>(std::lround(metres / r)); };
    // South wall y in [-0.2, 0], north [8.0, 8.2]: crossed at x = 3.33 (clear of furniture at 1.1 m).
    EXPECT_EQ(occupiedAlong(t, 1, {3.33, 0, 1.1}, -0.4, 0.3), (std::vector<std::int32_t>{face(-0.2), face(0.0)}));
    EXPECT_EQ(occupiedAlong(t, 1, {3.33, 0, 1.1}, 7.7, 8.39), (std::vector<std::int32_t>{face(8.0), face(8.2)}));
    // West x in [-0.2, 0], east [10.0, 10.2]: crossed at y = 2.33.
    EXPECT_EQ(occupiedAlong(t, 0, {0, 2.33, 1.1}, -0.4, 0.3), (std::vector<std::int32_t>{face(-0.2), face(0.0)}));
    EXPECT_EQ(occupiedAlong(t, 0, {0, 2.33, 1.1}, 9.7, 10.39), (std::vector<std::int32_t>{face(10.0), face(10.2)}));
  }
}

TEST(SimGroundTruth, AxisAlignedBoxesOccupyExactlyTheCellsOfTheirBoundaryPoints) {
  // Boxes whose faces are exact binary fractions, on and off cell boundaries, at every quarter-turn yaw:
  // the occupied cells are exactly the cells floor(p / r) of points p sampled on their faces (a lattice of
  // step r / 8, which puts a sample in every cell a face crosses), and every other cell of theirs is inside.
  const double r = 0.25;
  const std::vector<Box> boxes = {
      Box{{1.0, 1.0, 1.0}, {1.0, 0.5, 1.5}, 0.0},                      // every face on a boundary
      Box{{1.0625, 0.90625, 1.0}, {0.875, 0.6875, 0.3125}, 0.0},        // no face on one
      Box{{1.0, 1.125, 0.75}, {1.5, 0.25, 0.5}, std::numbers::pi / 2},  // a quarter turn swaps x and y
      Box{{1.125, 1.0, 0.875}, {0.5, 1.25, 0.75}, -std::numbers::pi},
  };
  for (std::size_t n = 0; n < boxes.size(); ++n) {
    SCOPED_TRACE(n);
    const Box& box = boxes[n];
    World w;
    w.materials = {Material{}};
    w.solids = {Solid{box, 0}};
    w.bounds = Aabb{{0, 0, 0}, {2.5, 2.5, 2.5}};
    const GroundTruth t = computeGroundTruth(w, r);
    const bool swapped = std::abs(std::remainder(box.yaw, std::numbers::pi)) > 1e-9;
    const Eigen::Vector3d half{0.5 * (swapped ? box.size.y() : box.size.x()),
                               0.5 * (swapped ? box.size.x() : box.size.y()), 0.5 * box.size.z()};
    const Eigen::Vector3d lo = box.centre - half;
    const Eigen::Vector3d hi = box.centre + half;
    std::set<CellKey> expected;
    const double step = r / 8;
    const Eigen::Vector3d steps = (hi - lo) / step;
    const auto last = [&](int a) { return static_cast<int>(std::lround(steps[a])); };
    for (int a = 0; a <= last(0); ++a) {
      for (int b = 0; b <= last(1); ++b) {
        for (int c = 0; c <= last(2); ++c) {
          if (a != 0 && a != last(0) && b != 0 && b != last(1) && c != 0 && c != last(2)) continue;
          expected.insert(cellKeyOf(lo + Eigen::Vector3d{a * step, b * step, c * step}, r));
        }
      }
    }
    std::set<CellKey> occupied;
    for (std::size_t i = 0; i < t.cells.size(); ++i) {
      if (t.cells[i] == static_cast<std::uint8_t>(CellClass::Occupied)) occupied.insert(t.keyOf(i));
    }
    EXPECT_EQ(occupied, expected);
    for (std::size_t i = 0; i < t.cells.size(); ++i) {
      const CellKey k = t.keyOf(i);
      const Eigen::Vector3d centre = (Eigen::Vector3d{k.x + 0.5, k.y + 0.5, k.z + 0.5}) * r;
      const bool within = (centre.array() > lo.array()).all() && (centre.array() < hi.array()).all();
      if (t.cells[i] == static_cast<std::uint8_t>(CellClass::Unobservable)) {
        EXPECT_TRUE(within) << k.x << " " << k.y << " " << k.z;
      } else if (t.cells[i] == static_cast<std::uint8_t>(CellClass::Free)) {
        EXPECT_FALSE(within) << k.x << " " << k.y << " " << k.z;
      }
    }
  }
}

TEST(SimGroundTruth, EveryReturnOnAYawedBoxOrACylinderLandsInAnOccupiedCell) {
  // Points on the faces of a yawed box and on a cylinder, put into cells as returns are (floor(p / r)). The
  // box's top and bottom lie off cell boundaries: a point computed on a face that lies on one may round
  // to either side of it, which is what kOnCellBoundary settles.
  World w;
  w.materials = {Material{}};
  const Box box{{1.0, 1.0, 0.73}, {1.4, 0.6, 1.0}, 0.5};
  const Cylinder cyl{{2.6, 1.2}, 0.45, 0.1, 1.3};
  w.solids = {Solid{box, 0}, Solid{cyl, 0}};
  w.bounds = Aabb{{0, 0, 0}, {3.4, 2.4, 1.6}};
  const double r = 0.1;
  const GroundTruth t = computeGroundTruth(w, r);
  std::size_t checked = 0;
  const double c = std::cos(box.yaw);
  const double s = std::sin(box.yaw);
  for (double u = -0.5; u <= 0.5; u += 1.0 / 64) {
    for (double v = -0.5; v <= 0.5; v += 1.0 / 64) {
      // Each of the six faces at local coordinates (u, v) across it.
      const std::array<Eigen::Vector3d, 6> local = {
          Eigen::Vector3d{-0.5, u, v}, Eigen::Vector3d{0.5, u, v}, Eigen::Vector3d{u, -0.5, v},
          Eigen::Vector3d{u, 0.5, v}, Eigen::Vector3d{u, v, -0.5}, Eigen::Vector3d{u, v, 0.5}};
      for (const auto& l : local) {
        const Eigen::Vector3d q = l.cwiseProduct(box.size);
        const Eigen::Vector3d p = box.centre + Eigen::Vector3d{c * q.x() - s * q.y(), s * q.x() + c * q.y(), q.z()};
        EXPECT_EQ(t.at(cellKeyOf(p, r)), CellClass::Occupied) << p.transpose();
        ++checked;
      }
      const double angle = (u + 0.5) * 2 * std::numbers::pi;
      const Eigen::Vector3d side{cyl.centre.x() + cyl.radius * std::cos(angle), cyl.centre.y() + cyl.radius * std::sin(angle),
                                 cyl.z_min + (v + 0.5) * (cyl.z_max - cyl.z_min)};
      EXPECT_EQ(t.at(cellKeyOf(side, r)), CellClass::Occupied) << side.transpose();
      ++checked;
    }
  }
  EXPECT_GT(checked, 20000u);
}

TEST(SimGroundTruth, YawedBoxAndCylinderCellsAgreeWithPointSampling) {
  World w;
  w.materials = {Material{}};
  w.solids = {Solid{Box{{1.0, 1.0, 0.7}, {1.4, 0.6, 1.0}, 0.5}, 0}, Solid{Cylinder{{2.6, 1.2}, 0.45, 0.1, 1.3}, 0}};
  w.bounds = Aabb{{0, 0, 0}, {3.4, 2.4, 1.6}};
  const double r = 0.1;
  const GroundTruth t = computeGroundTruth(w, r);
  // Sample each cell on a 5x5x5 lattice: all samples inside a solid → never free; samples both inside and
  // outside → occupied (the surface passes through); no sample inside → not unobservable.
  for (std::size_t idx = 0; idx < t.cells.size(); ++idx) {
    const CellKey k = t.keyOf(idx);
    int inside = 0;
    for (int a = 0; a < 5; ++a) {
      for (int b = 0; b < 5; ++b) {
        for (int c = 0; c < 5; ++c) {
          const Eigen::Vector3d p{(k.x + (a + 0.5) / 5) * r, (k.y + (b + 0.5) / 5) * r, (k.z + (c + 0.5) / 5) * r};
          bool in = false;
          for (const auto& s : w.solids) in = in || contains(s.shape, p);
          inside += in ? 1 : 0;
        }
      }
    }
    const auto cls = static_cast<CellClass>(t.cells[idx]);
    if (inside > 0 && inside < 125) {
      EXPECT_EQ(cls, CellClass::Occupied) << k.x << " " << k.y << " " << k.z;
    }
    if (inside > 0) {
      EXPECT_NE(cls, CellClass::Free) << k.x << " " << k.y << " " << k.z;
    } else {
      EXPECT_NE(cls, CellClass::Unobservable) << k.x << " " << k.y << " " << k.z;
    }
  }
  EXPECT_GT(t.count(CellClass::Unobservable), 100u);
  EXPECT_GT(t.count(CellClass::Occupied), 100u);
}

TEST(SimGroundTruth, AirBehindTheWallsIsUnobservableOnceTheSensorSeedsTheRoom) {
  const auto scene = presetScene("lab");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const CellKey outside_west_wall{-2, 20, 5};  // x in [-0.4, -0.2): beyond the wall at [-0.2, 0)
  const CellKey in_the_room{15, 15, 5};
  const GroundTruth unseeded = computeGroundTruth(scene->world, 0.2);
  EXPECT_EQ(unseeded.at(outside_west_wall), CellClass::Free);
  const GroundTruth seeded = computeGroundTruth(scene->world, 0.2, {Eigen::Vector3d{3.5, 3.5, 1.0}});
  EXPECT_EQ(seeded.at(outside_west_wall), CellClass::Unobservable);
  EXPECT_EQ(seeded.at(in_the_room), CellClass::Free);
  // Only air changes: every occupied cell stays occupied.
  EXPECT_EQ(seeded.count(CellClass::Occupied), unseeded.count(CellClass::Occupied));
  EXPECT_LT(seeded.count(CellClass::Free), unseeded.count(CellClass::Free));
}

TEST(SimGroundTruth, FileRoundTripsExactly) {
  const GroundTruth t = computeGroundTruth(groundAndCube(), 0.2);
  const std::string path = tempPath("roundtrip.grid");
  ASSERT_TRUE(writeGroundTruth(path, t).ok());
  const auto back = readGroundTruth(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->resolution, t.resolution);
  EXPECT_EQ(back->min_key, t.min_key);
  EXPECT_EQ(back->size, t.size);
  EXPECT_EQ(back->cells, t.cells);
  std::filesystem::remove(path);
}

TEST(SimGroundTruth, CorruptedOrTruncatedFileIsRefused) {
  const GroundTruth t = computeGroundTruth(groundAndCube(), 0.2);
  const std::string path = tempPath("corrupt.grid");
  ASSERT_TRUE(writeGroundTruth(path, t).ok());
  const auto size = std::filesystem::file_size(path);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    const auto at = static_cast<std::streamoff>(size - 10);
    f.seekg(at);
    char c = 0;
    f.get(c);
    f.seekp(at);
    f.put(static_cast<char>(c ^ 1));  // another valid class, so only the checksum can tell
  }
  auto bad = readGroundTruth(path);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("checksum"), std::string::npos) << bad.error().message;
  std::filesystem::resize_file(path, size - 100);
  bad = readGroundTruth(path);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("cells expected"), std::string::npos) << bad.error().message;
  std::filesystem::remove(path);
}

TEST(SimGroundTruth, HeaderWithoutSizeNamesTheField) {
  const std::string path = tempPath("nosize.grid");
  {
    std::ofstream f(path);
    f << "OGF-TRUTH 1\nresolution 0.2\nmin_key 0 0 0\nfnv1a64 0\ndata\n";
  }
  const auto bad = readGroundTruth(path);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("size: missing"), std::string::npos) << bad.error().message;
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ogf::sim
