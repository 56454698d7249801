// ogf-map's picture as a user gets it: the README's headline command, as written (no --png-zmin/--png-zmax),
// on the real capture draws the walls (occupied pixels in occupancy.png), logs the band it chose and why, and
// names the calibration file it decoded with; without --calib it names the built-in table instead.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

#include "run_program.hpp"
#include "scratch_dir.hpp"
#include "support/shared_data.hpp"
#include "tools/view/png_image.hpp"

namespace {

using ogf::testing::runProgram;

constexpr std::uint8_t kOccupiedGrey = 25;  // map_io's occupied colour, (25, 25, 25)

std::size_t occupiedPixels(const std::filesystem::path& png) {
  std::ifstream in(png, std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::string error;
  const auto image = ogf::testing::decodePng(bytes, error);
  EXPECT_TRUE(image.has_value()) << png << ": " << error;
  if (!image) return 0;
  std::size_t n = 0;
  for (int y = 0; y < image->height; ++y) {
    for (int x = 0; x < image->width; ++x) {
      const std::uint8_t* p = image->at(x, y);
      n += (p[0] == kOccupiedGrey && p[1] == kOccupiedGrey && p[2] == kOccupiedGrey) ? 1U : 0U;
    }
  }
  return n;
}

// The capture's picture drawn over z -0.5 to 1.3 m (--png-zmin -0.5 --png-zmax 1.3, set by hand to where its
// walls are) holds 18799 occupied pixels, the legend's swatch (484) among them; a picture of the walls holds
// at least three quarters of that. A band above the walls or below the floor holds the swatch alone.
constexpr std::size_t kWallPixels = 14100;

TEST(OgfMapPicture, TheReadmeHeadlineCommandDrawsTheWallsAndSaysWhichBandAndCalibration) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  OGF_REQUIRE_SHARED_FILE(calib, "data/real/calib/VLP-16.xml");
  ogf::testing::ScratchDir dir;
  const auto run = runProgram(
      {OGF_MAP_BINARY, "--pcap", pcap.string(), "--calib", calib.string(), "--static", "--resolution", "0.1",
       "--out", (dir / "map.ogfm").string(), "--png", (dir / "png").string() + "/"},
      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_GE(occupiedPixels(dir / "png" / "occupancy.png"), kWallPixels) << run.output;
  std::smatch band;
  ASSERT_TRUE(std::regex_search(
      run.output, band,
      std::regex(
          R"(z (-?[0-9.]+) to (-?[0-9.]+) m \(the walls' band chosen from the map: floor at -?[0-9.]+ m)")))
      << run.output;
  // The capture's floor lies 1.6 m below the sensor, its ceiling 1.4 m above (test_wall_band.cpp).
  EXPECT_GE(std::stod(band[1]), -1.6) << run.output;
  EXPECT_LE(std::stod(band[2]), 1.4) << run.output;
  EXPECT_NE(run.output.find("calibration: " + calib.string() + " (--calib)"), std::string::npos)
      << run.output;

  const auto nominal = runProgram({OGF_MAP_BINARY, "--pcap", pcap.string(), "--static", "--resolution", "0.2",
                                   "--out", (dir / "nominal.ogfm").string()},
                                  dir.path());
  ASSERT_EQ(nominal.exit_code, 0) << nominal.output;
  EXPECT_NE(nominal.output.find("calibration: the nominal VLP-16 table, built in (no --calib;"),
            std::string::npos)
      << nominal.output;
}

}  // namespace
