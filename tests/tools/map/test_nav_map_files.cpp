// The navigation grid's files on a grid made by hand: the PGM's header, its rows from north to south, the
// pixel of each class and cost in each mode, the YAML's fields, and the errors that name the file.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "ogf/map_formats/nav_map_files.hpp"
#include "scratch_dir.hpp"
#include "support/file_text.hpp"

namespace {

using namespace ogf;
namespace nav = navigation;

// 3 columns x 2 rows from column (-2, 5): the south row free, occupied, unknown; the north row all occupied.
nav::NavGrid handGrid() {
  nav::NavGrid g;
  g.resolution = 0.1;
  g.origin = {-2, 5};
  g.width = 3;
  g.height = 2;
  g.cost = {10, 90, nav::kUnknownCost, 80, 80, 100};
  g.column_class = {nav::kClassFree, nav::kClassOccupied, nav::kClassUnknown,
                    nav::kClassOccupied, nav::kClassOccupied, nav::kClassOccupied};
  return g;
}

TEST(NavMapFiles, ThePgmRunsFromNorthToSouthAndTheYamlPlacesItsLowerLeftCorner) {
  ogf::testing::ScratchDir dir;
  auto files = map_formats::writeNavMap(handGrid(), dir / "nav", map_formats::NavImageMode::kTrinary);
  ASSERT_TRUE(files.ok()) << files.error().message;
  EXPECT_EQ(files->free, 1u);
  EXPECT_EQ(files->occupied, 4u);
  EXPECT_EQ(files->unknown, 1u);
  const std::string pgm = ogf::testing::fileText(dir / "nav" / "map.pgm");
  ASSERT_EQ(pgm.rfind("P5\n", 0), 0u);
  const auto body = pgm.substr(pgm.size() - 6);
  EXPECT_NE(pgm.find("\n3 2\n255\n"), std::string::npos);
  // First the north row (all occupied), then the south row: free, occupied, unknown.
  const std::string want{'\0', '\0', '\0', static_cast<char>(254), '\0', static_cast<char>(205)};
  EXPECT_EQ(body, want);
  const std::string yaml = ogf::testing::fileText(dir / "nav" / "map.yaml");
  EXPECT_NE(yaml.find("image: map.pgm\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("mode: trinary\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("resolution: 0.1\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("origin: [-0.2, 0.5, 0.0]\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("negate: 0\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("occupied_thresh: 0.65\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("free_thresh: 0.196\n"), std::string::npos) << yaml;
}

TEST(NavMapFiles, ScaleModeWritesTheCostAndTrinaryTheClass) {
  using map_formats::navPixel;
  using map_formats::NavImageMode;
  EXPECT_EQ(navPixel({10, nav::kClassFree}, NavImageMode::kTrinary), 254);
  EXPECT_EQ(navPixel({70, nav::kClassOccupied}, NavImageMode::kTrinary), 0);
  EXPECT_EQ(navPixel({}, NavImageMode::kTrinary), 205);
  EXPECT_EQ(navPixel({0, nav::kClassFree}, NavImageMode::kScale), 255);
  EXPECT_EQ(navPixel({100, nav::kClassOccupied}, NavImageMode::kScale), 0);
  EXPECT_EQ(navPixel({50, nav::kClassFree}, NavImageMode::kScale), 127);  // 255 - round(127.5), a half rounded up
  EXPECT_EQ(navPixel({1, nav::kClassFree}, NavImageMode::kScale), 252);   // 255 - round(2.55)
  EXPECT_EQ(navPixel({}, NavImageMode::kScale), 205);
  EXPECT_TRUE(map_formats::parseNavImageMode("scale").ok());
  EXPECT_FALSE(map_formats::parseNavImageMode("raw").ok());
}

TEST(NavMapFiles, ErrorsNameTheFolder) {
  ogf::testing::ScratchDir dir;
  nav::NavGrid empty;
  auto none = map_formats::writeNavMap(empty, dir / "empty", map_formats::NavImageMode::kTrinary);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("empty"), std::string::npos) << none.error().message;
  EXPECT_NE(none.error().message.find("nothing to draw"), std::string::npos) << none.error().message;
  std::ofstream(dir / "file") << "x";
  auto blocked = map_formats::writeNavMap(handGrid(), dir / "file" / "nav", map_formats::NavImageMode::kTrinary);
  ASSERT_FALSE(blocked.ok());
  EXPECT_NE(blocked.error().message.find("file/nav"), std::string::npos) << blocked.error().message;
}

}  // namespace
