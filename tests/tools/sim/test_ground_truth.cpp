// Ground truth: cells classified by the CellKey convention, and truth.grid written and read back.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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

TEST(SimGroundTruth, AFaceRoundedJustBelowACellBoundaryStaysASurface) {
  // The lab's north wall: centre y 8.1, size 0.2, so it starts at 8.1 - 0.1 = 7.999999999999999. Its face
  // is the surface of cell j = 40 ([8.0, 8.2)), not the wall's inside, and cell 39 is open air.
  World w;
  w.materials = {Material{"default", 50, 0}};
  w.solids = {Solid{HalfSpace{}, 0}, Solid{Box{{5.0, 8.1, 1.5}, {10.4, 0.2, 3.0}, 0.0}, 0},
              Solid{Box{{10.1, 4.0, 1.5}, {0.2, 8.0, 3.0}, 0.0}, 0}};
  w.bounds = Aabb{{-0.4, -0.4, -0.4}, {10.4, 8.4, 3.4}};
  const GroundTruth t = computeGroundTruth(w, 0.2);
  EXPECT_EQ(t.at({25, 40, 5}), CellClass::Occupied);
  EXPECT_EQ(t.at({25, 39, 5}), CellClass::Free);
  EXPECT_EQ(t.at({50, 20, 5}), CellClass::Occupied);  // the east wall, x from 10.1 - 0.1
  EXPECT_EQ(t.at({49, 20, 5}), CellClass::Free);
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
