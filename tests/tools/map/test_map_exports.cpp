// The exports on a tiny known scene (a sensor facing a wall): the CSV has the exact header and one row per
// allocated cell at cell centres; the PLY header parses, announces exactly the occupied cells and the body
// has that many records; the OctoMap tree reads back with liboctomap and agrees with the OGF's classes;
// the PNG views have the map's extent.
#include <gtest/gtest.h>

#include <octomap/OcTree.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "ogf/map_formats/cell_csv.hpp"
#include "ogf/map_formats/cell_ply.hpp"
#include "ogf/map_formats/map_cells.hpp"
#include "ogf/map_formats/octomap_export.hpp"
#include "ogf/map_io/offline_mapping.hpp"
#include "ogf/map_io/topdown_png.hpp"
#include "scratch_dir.hpp"
#include "support/file_text.hpp"
#include "synthetic_scan.hpp"
#include "wall_mapping.hpp"

namespace {

using namespace ogf;

map_formats::MapCells wallMap() { return map_formats::collectCells(ogf::testing::wallMapping().mapper().filter()); }

TEST(CellCsv, HeaderIsExactAndEveryAllocatedCellIsARowAtItsCentre) {
  ogf::testing::ScratchDir dir;
  const auto cells = wallMap();
  ASSERT_GT(cells.occupiedCount(), 0u);
  ASSERT_TRUE(map_formats::writeCellCsv(cells, dir / "m.csv").ok());
  std::istringstream in(ogf::testing::fileText(dir / "m.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "x,y,z,p,class,variance");
  std::size_t rows = 0, occupied = 0, wall = 0;
  while (std::getline(in, line)) {
    double x, y, z, p, var;
    int cls;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%d,%lf", &x, &y, &z, &p, &cls, &var), 6) << line;
    // A centre is an odd multiple of half a cell.
    EXPECT_NEAR(std::fmod(std::abs(x) / 0.1, 2.0), 1.0, 1e-3) << line;
    EXPECT_GE(p, 0.0);
    EXPECT_LE(p, 1.0);
    EXPECT_TRUE(cls == -1 || cls == 0 || cls == 1);
    if (cls == 1) {
      ++occupied;
      // The wall's cells, or the cells right behind them that the filter's correlations fill in.
      EXPECT_TRUE(std::abs(x - 4.1) < 1e-3 || std::abs(x - 4.3) < 1e-3) << "an occupied cell away from the wall: " << line;
      wall += std::abs(x - 4.1) < 1e-3 ? 1U : 0U;
    }
    ++rows;
  }
  EXPECT_EQ(rows, cells.cells.size());
  EXPECT_EQ(occupied, cells.occupiedCount());
  EXPECT_GT(wall, occupied / 2) << "most occupied cells are the wall's";
}

TEST(OccupiedPly, HeaderParsesAndVertexCountEqualsOccupiedCells) {
  ogf::testing::ScratchDir dir;
  const auto cells = wallMap();
  ASSERT_TRUE(map_formats::writeOccupiedPly(cells, dir / "m.ply").ok());
  const std::string bytes = ogf::testing::fileText(dir / "m.ply");
  const std::size_t end = bytes.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  std::istringstream header(bytes.substr(0, end));
  std::string line, format;
  std::size_t vertices = 0;
  std::vector<std::string> properties;
  while (std::getline(header, line)) {
    std::istringstream w(line);
    std::string key;
    w >> key;
    if (key == "format") w >> format;
    if (key == "element") {
      std::string name;
      w >> name >> vertices;
      EXPECT_EQ(name, "vertex");
    }
    if (key == "property") {
      std::string type, name;
      w >> type >> name;
      EXPECT_EQ(type, "float");
      properties.push_back(name);
    }
  }
  EXPECT_EQ(format, "binary_little_endian");
  EXPECT_EQ(properties, (std::vector<std::string>{"x", "y", "z", "p", "variance"}));
  EXPECT_EQ(vertices, cells.occupiedCount());
  const std::size_t body = bytes.size() - (end + std::strlen("end_header\n"));
  ASSERT_EQ(body, vertices * 5 * sizeof(float));
  float first[5];
  std::memcpy(first, bytes.data() + end + std::strlen("end_header\n"), sizeof first);
  EXPECT_NEAR(first[0], 4.1f, 1e-3f);
  EXPECT_GT(first[3], 0.65f);
  EXPECT_GT(first[4], 0.0f);
}

TEST(OctomapExport, TreeReadsBackWithLiboctomapAndKeepsTheClasses) {
  ogf::testing::ScratchDir dir;
  const auto cells = wallMap();
  const auto counts = map_formats::writeOctomapBinary(cells, dir / "m.bt");
  ASSERT_TRUE(counts.ok()) << counts.error().message;
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary((dir / "m.bt").string()));
  EXPECT_DOUBLE_EQ(tree.getResolution(), 0.2);
  std::int64_t occupied_leaves = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
    if (tree.isNodeOccupied(*it)) ++occupied_leaves;
  EXPECT_GT(counts->occupied, 0);
  for (const auto& c : cells.cells) {
    if (c.cell_class == 0) continue;
    const Eigen::Vector3d p = cellCentre(c.key, cells.resolution);
    const octomap::OcTreeNode* node = tree.search(p.x(), p.y(), p.z());
    ASSERT_NE(node, nullptr) << p.transpose();
    EXPECT_EQ(tree.isNodeOccupied(node), c.cell_class > 0) << p.transpose();
  }
  EXPECT_GT(occupied_leaves, 0);
}

TEST(TopDownPng, BothViewsAreWrittenAsPngsOfTheMapExtent) {
  ogf::testing::ScratchDir dir;
  const auto cells = wallMap();
  const auto size = map_io::writeTopDownPngs(cells, {-0.5, 0.5}, dir / "png");
  ASSERT_TRUE(size.ok()) << size.error().message;
  // The fan spans x from the sensor to the wall (about 4 m = 20+ cells) and y about ±2.4 m.
  EXPECT_GE(size->width, 20);
  EXPECT_GE(size->height, 20);
  for (const char* name : {"occupancy.png", "entropy.png"}) {
    const std::string bytes = ogf::testing::fileText(dir / "png" / name);
    ASSERT_GE(bytes.size(), 24u) << name;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << name;
    // IHDR: width and height, big-endian, at bytes 16 and 20. The long side is at least 800 pixels.
    const auto be32 = [&](std::size_t at) {
      return (std::uint32_t{static_cast<unsigned char>(bytes[at])} << 24) |
             (std::uint32_t{static_cast<unsigned char>(bytes[at + 1])} << 16) |
             (std::uint32_t{static_cast<unsigned char>(bytes[at + 2])} << 8) |
             std::uint32_t{static_cast<unsigned char>(bytes[at + 3])};
    };
    EXPECT_GE(std::max(be32(16), be32(20)), 800u) << name;
  }
  EXPECT_FALSE(map_io::writeTopDownPngs(cells, {50.0, 60.0}, dir / "png2").ok());
}

}  // namespace
