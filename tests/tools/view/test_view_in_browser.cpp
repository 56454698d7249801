// ogf-view in a real browser (Debian's Chromium, headless, WebGL on SwiftShader): a saved map is drawn, and
// on a live bus the picture follows the deltas. Pixels of the screenshots decide, not the page's word:
// cells are drawn in saturated colours the background, the grid and the panel never have. The screenshots
// stay in build/tests/view-screenshots/ for a person to look at. Skips, saying why, when Chromium cannot
// run here or udpm has no loopback route. The mapper's sources appear as trails in their robot's colour;
// the 2-D navigation grid lies at its floor in its colours, shows over a floor's boxes, and its toggle hides
// it. The panel keeps its layout and its figures whole with a long map path.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <unistd.h>

#include <ogf/filter/map_file.hpp>
#include <ogf/map_delta_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/odometry_t.hpp>

#include <csignal>
#include <array>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <thread>

#include "headless_chromium.hpp"
#include "nav_room.hpp"
#include "ogf/delta/delta_stream.hpp"
#include "ogf/pipeline/published_cells.hpp"
#include "png_image.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/multicast.hpp"
#include "two_robots.hpp"
#include "support/source_status.hpp"
#include "view_process.hpp"

namespace {

namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using ogf::testing::ViewProcess;
using ogf::testing::HeadlessChromium;
using ogf::testing::RgbImage;

constexpr int kWidth = 1000;
constexpr int kHeight = 700;
constexpr int kPanelRight = 280;  // the figures panel covers x < 280

fs::path screenshotDir() {
  fs::path d = fs::path(OGF_SCREENSHOT_DIR);
  fs::create_directories(d);
  return d;
}

// Pixels right of the panel whose colour is saturated: boxes (the grid, the background and the text are grey).
std::size_t cellPixels(const RgbImage& img) {
  std::size_t n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = kPanelRight; x < img.width; ++x) {
      const auto* p = img.at(x, y);
      if (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 60) ++n;
    }
  return n;
}

std::size_t changedPixels(const RgbImage& a, const RgbImage& b) {
  std::size_t n = 0;
  for (int y = 0; y < std::min(a.height, b.height); ++y)
    for (int x = kPanelRight; x < std::min(a.width, b.width); ++x)
      for (int c = 0; c < 3; ++c)
        if (std::abs(int{a.at(x, y)[c]} - int{b.at(x, y)[c]}) > 40) {
          ++n;
          break;
        }
  return n;
}

RgbImage screenshot(HeadlessChromium& browser, const std::string& name) {
  const auto png = browser.screenshotPng();
  EXPECT_FALSE(png.empty()) << "no screenshot";
  const fs::path path = screenshotDir() / name;
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  std::string error;
  auto img = ogf::testing::decodePng(png, error);
  EXPECT_TRUE(img.has_value()) << path << ": " << error;
  return img.value_or(RgbImage{});
}

// A 3 m × 3 m room with 1 m walls at 0.2 m: the walls' cells measured occupied, the inside free; with
// `floor`, the inside's lowest layer (z = 0, 0 to 0.2 m: below the navigation band, which starts 0.25 m
// above the floor) measured occupied, as a lidar sees a floor.
std::vector<ogf::Measurement> room(bool floor = false) {
  std::vector<ogf::Measurement> m;
  for (int x = 0; x < 15; ++x)
    for (int y = 0; y < 15; ++y)
      for (int z = 0; z < 5; ++z) {
        const bool wall = x == 0 || y == 0 || x == 14 || y == 14;
        m.push_back({{x, y, z}, wall || (floor && z == 0) ? ogf::Measurement::kOccupied : ogf::Measurement::kFree});
      }
  return m;
}

std::size_t occupiedCount(const std::vector<ogf::delta::PublishedCell>& cells) {
  return static_cast<std::size_t>(std::count_if(cells.begin(), cells.end(), [](const auto& c) {
    return c.cell_class == ogf::map_delta_t::CLASS_OCCUPIED;
  }));
}

// The room (with its floor: room(true)) saved to `path`; how many cells ogf-view draws as boxes.
std::size_t saveRoom(const fs::path& path, bool floor) {
  ogf::filter::FilterConfig cfg;
  cfg.resolution = 0.2;
  auto map = ogf::filter::BandedOgf::create(cfg);
  EXPECT_TRUE(map.ok());
  if (!map.ok()) return 0;
  const auto batch = room(floor);
  for (int i = 0; i < 3; ++i) map->update(batch);
  EXPECT_TRUE(ogf::filter::saveMapFile(*map, path).ok());
  return occupiedCount(ogf::pipeline::publishedCellsOf(*map));
}

// The value the page's figures panel shows in the row whose name starts with `name` ("" without one).
std::string panelFigure(HeadlessChromium& browser, const std::string& name) {
  return browser.evaluate("[...document.querySelectorAll('#figures tr')].filter(r => r.cells[0].textContent.startsWith('" +
                          name + "')).map(r => r.cells[1].textContent).join('')");
}

// Presses `n` and waits until the page's title no longer counts navigation columns (the layer hidden).
void hideNavLayer(HeadlessChromium& browser) {
  browser.evaluate("document.dispatchEvent(new KeyboardEvent('keydown', {key: 'n'}))");
  for (int i = 0; i < 50 && browser.title().find("nav columns") != std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_EQ(browser.title().find("nav columns"), std::string::npos) << browser.title();
}

// The room saved to a file, shown by ogf-view started with `args`, opened at its printed address plus
// `query`; the page's title and the screenshot say whether it was drawn (the boxes, with the navigation
// layer hidden), and the panel shows the room's navigation grid: its 15 × 15 columns known.
void expectSavedRoomDrawn(std::vector<std::string> args, const std::string& query, const std::string& name) {
  HeadlessChromium browser;
  if (auto why = browser.start(kWidth, kHeight)) GTEST_SKIP() << "chromium cannot run here: " << *why;

  const fs::path map_path = fs::temp_directory_path() / ("ogf-view-room-" + std::to_string(::getpid()) + ".ogfm");
  const std::size_t occupied = saveRoom(map_path, false);
  ASSERT_GT(occupied, 100u);

  args.insert(args.end(), {"--map", map_path.string(), "--port", "0"});
  ViewProcess view(args, name);
  const std::string url = view.url();
  ASSERT_FALSE(url.empty());
  ASSERT_TRUE(browser.open(url + query));
  const std::string want = "drawn " + std::to_string(occupied) + " boxes";
  const std::string title = browser.waitForTitle(want, std::chrono::seconds(30));
  fs::remove(map_path);
  if (title.find("no WebGL") != std::string::npos) GTEST_SKIP() << "chromium has no WebGL here: " << title;
  ASSERT_NE(title.find(want), std::string::npos) << "title: " << title << "\n" << view.log();
  EXPECT_NE(browser.waitForTitle("nav columns 225", std::chrono::seconds(10)).find("nav columns 225"), std::string::npos)
      << "the saved map's navigation grid is not drawn: " << browser.title();
  EXPECT_EQ(panelFigure(browser, "nav columns known"), "225");
  EXPECT_EQ(panelFigure(browser, "nav = mapper"), "file");
  hideNavLayer(browser);

  const RgbImage img = screenshot(browser, name + ".png");
  EXPECT_EQ(img.width, kWidth);
  EXPECT_GT(cellPixels(img), 5000u) << "the room's walls are not on the screen (" << screenshotDir() / (name + ".png") << ")";
}

TEST(ViewInBrowser, SavedMapIsDrawn) { expectSavedRoomDrawn({}, "", "saved-map"); }

// The token from a file: the page's address carries it, the libraries and the feed get it from the page.
TEST(ViewInBrowser, SavedMapIsDrawnWhenTheViewAsksForAToken) {
  const fs::path token_file = fs::temp_directory_path() / ("ogf-view-token-" + std::to_string(::getpid()));
  const std::string token = "0123456789abcdef0123456789abcdef";
  std::ofstream(token_file) << token << "\n";
  fs::permissions(token_file, fs::perms::owner_read | fs::perms::owner_write);
  expectSavedRoomDrawn({"--token", token_file.string()}, "?token=" + token, "saved-map-token");
  fs::remove(token_file);
}

TEST(ViewInBrowser, LiveDeltasChangeThePicture) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  HeadlessChromium browser;
  if (auto why = browser.start(kWidth, kHeight)) GTEST_SKIP() << "chromium cannot run here: " << *why;

  const std::string bus = ogf::testing::loopbackUdpmUrl(23);
  lcm::LCM lcm(bus);
  ASSERT_TRUE(lcm.good());
  ViewProcess view({"--lcm-url", bus, "--port", "0", "--rate", "5"}, "live");
  const std::string url = view.url();
  ASSERT_FALSE(url.empty());

  // The mapper's side: the room as update 1, then a block of cells in the middle of it as update 2.
  ogf::delta::DeltaStream stream({0.2, 23, ogf::messages::kMaxDeltaCellsPerMessage});
  std::vector<ogf::delta::PublishedCell> walls;
  for (const auto& m : room())
    walls.push_back({m.key, static_cast<std::int16_t>(m.y == ogf::Measurement::kOccupied ? 9000 : 1000),
                     m.y == ogf::Measurement::kOccupied ? ogf::map_delta_t::CLASS_OCCUPIED : ogf::map_delta_t::CLASS_FREE,
                     0.3f});
  stream.update(1, walls);
  const std::size_t wall_cells = stream.map().size() - 13 * 13 * 5;
  const auto publish = [&](const std::vector<ogf::map_delta_t>& msgs) {
    for (const auto& m : msgs) lcm.publish("OGF_MAP_DELTA", &m);
  };

  ASSERT_TRUE(browser.open(url));
  // ogf-view asks for a keyframe at start; answering every half second covers a request sent before
  // this side listened.
  const std::string want1 = "drawn " + std::to_string(wall_cells) + " boxes, seq 1";
  std::string title;
  for (int i = 0; i < 60 && title.find(want1) == std::string::npos; ++i) {
    publish(stream.keyframe(2));
    title = browser.waitForTitle(want1, std::chrono::milliseconds(500));
  }
  if (title.find("no WebGL") != std::string::npos) GTEST_SKIP() << "chromium has no WebGL here: " << title;
  ASSERT_NE(title.find(want1), std::string::npos) << "title: " << title << "\n" << view.log();
  const RgbImage before = screenshot(browser, "live-before.png");
  ASSERT_GT(cellPixels(before), 5000u);

  std::vector<ogf::delta::PublishedCell> block;
  for (int x = 5; x < 10; ++x)
    for (int y = 5; y < 10; ++y)
      for (int z = 0; z < 8; ++z) block.push_back({{x, y, z}, 9500, ogf::map_delta_t::CLASS_OCCUPIED, 0.05f});
  publish(stream.update(3, block));
  ogf::odometry_t pose{};
  pose.utime = 3;
  pose.orientation[0] = 1.0;
  for (int i = 0; i < 20; ++i) {
    pose.position[0] = 0.5 + 0.1 * i;
    pose.position[1] = 1.5;
    lcm.publish("POSE", &pose);
    ++pose.utime;
  }
  const std::string want2 = "drawn " + std::to_string(wall_cells + block.size()) + " boxes, seq 2";
  title = browser.waitForTitle(want2, std::chrono::seconds(5));
  if (title.find(want2) == std::string::npos) {  // a datagram lost on loopback: the keyframe holds it too
    publish(stream.keyframe(4));
    title = browser.waitForTitle(want2, std::chrono::seconds(20));
  }
  ASSERT_NE(title.find(want2), std::string::npos) << "title: " << title << "\n" << view.log();
  const RgbImage after = screenshot(browser, "live-after.png");
  EXPECT_GT(changedPixels(before, after), 2000u) << "the block did not change the picture";
  EXPECT_GT(cellPixels(after), cellPixels(before));
}

// Pixels right of the panel that differ between `before` and `after` and, in `after`, have the colour
// `rgb` (each channel within 50): what a trail drawn in that colour added to the picture.
std::size_t addedPixelsOf(const RgbImage& before, const RgbImage& after, std::array<int, 3> rgb) {
  std::size_t n = 0;
  for (int y = 0; y < std::min(before.height, after.height); ++y)
    for (int x = kPanelRight; x < std::min(before.width, after.width); ++x) {
      const auto* a = after.at(x, y);
      const auto* b = before.at(x, y);
      bool changed = false, colour = true;
      for (int c = 0; c < 3; ++c) {
        changed = changed || std::abs(int{a[c]} - int{b[c]}) > 40;
        colour = colour && std::abs(int{a[c]} - rgb[static_cast<std::size_t>(c)]) <= 50;
      }
      if (changed && colour) ++n;
    }
  return n;
}

// One source of the mapper's status: `robot`/`name`, its trail a straight line of 8 points from `from`
// to `to` above the room's walls.
ogf::source_status_t sourceWithTrail(const std::string& robot, const std::string& name, std::array<float, 2> from,
                                     std::array<float, 2> to, std::int64_t mapped) {
  std::vector<std::array<float, 3>> trail;
  for (int i = 0; i < 8; ++i) {
    const float t = static_cast<float>(i) / 7.0f;
    trail.push_back({from[0] + t * (to[0] - from[0]), from[1] + t * (to[1] - from[1]), 1.4f});
  }
  auto s = ogf::testing::sourceStatus(robot, name, trail);
  s.scans_in = mapped + 2;
  s.scans_mapped = mapped;
  s.scans_dropped_no_pose = 2;
  return s;
}

// Two robots' sources in the mapper's status: each trail is drawn in its robot's colour (the page's first
// two, #00e5ff and #ffea00) over the map, and the panel names each as robot/sensor with its counts.
TEST(ViewInBrowser, SourceTrailsAreDrawnInTheirRobotsColourAndListedByName) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  HeadlessChromium browser;
  if (auto why = browser.start(kWidth, kHeight)) GTEST_SKIP() << "chromium cannot run here: " << *why;

  const std::string bus = ogf::testing::loopbackUdpmUrl(24);
  lcm::LCM lcm(bus);
  ASSERT_TRUE(lcm.good());
  ViewProcess view({"--lcm-url", bus, "--port", "0", "--rate", "5"}, "sources");
  const std::string url = view.url();
  ASSERT_FALSE(url.empty());

  ogf::delta::DeltaStream stream({0.2, 24, ogf::messages::kMaxDeltaCellsPerMessage});
  std::vector<ogf::delta::PublishedCell> walls;
  for (const auto& m : room())
    if (m.y == ogf::Measurement::kOccupied) walls.push_back({m.key, 9000, ogf::map_delta_t::CLASS_OCCUPIED, 0.3f});
  stream.update(1, walls);
  const std::string want_map = "drawn " + std::to_string(walls.size()) + " boxes, seq 1";
  ASSERT_TRUE(browser.open(url));
  std::string title;
  for (int i = 0; i < 60 && title.find(want_map) == std::string::npos; ++i) {
    for (const auto& m : stream.keyframe(2)) lcm.publish("OGF_MAP_DELTA", &m);
    title = browser.waitForTitle(want_map, std::chrono::milliseconds(500));
  }
  if (title.find("no WebGL") != std::string::npos) GTEST_SKIP() << "chromium has no WebGL here: " << title;
  ASSERT_NE(title.find(want_map), std::string::npos) << "title: " << title << "\n" << view.log();
  const RgbImage before = screenshot(browser, "sources-before.png");

  ogf::mapper_status_t status{};
  status.sources = {sourceWithTrail("r1", "front", {0.4f, 0.6f}, {2.6f, 0.6f}, 40),
                    sourceWithTrail("r2", "rear", {0.4f, 2.4f}, {2.6f, 2.4f}, 25)};
  status.num_sources = 2;
  const std::string want_trails = "source trails 2";
  for (int i = 0; i < 40 && title.find(want_trails) == std::string::npos; ++i) {
    ++status.utime;
    lcm.publish("OGF_MAPPER_STATUS", &status);
    title = browser.waitForTitle(want_trails, std::chrono::milliseconds(500));
  }
  ASSERT_NE(title.find(want_trails), std::string::npos) << "title: " << title << "\n" << view.log();
  const RgbImage after = screenshot(browser, "sources-after.png");
  EXPECT_GT(addedPixelsOf(before, after, {0x00, 0xe5, 0xff}), 60u) << "r1's trail is not drawn in cyan (sources-after.png)";
  EXPECT_GT(addedPixelsOf(before, after, {0xff, 0xea, 0x00}), 60u) << "r2's trail is not drawn in yellow (sources-after.png)";

  const std::string panel = browser.evaluate("document.getElementById('sources').innerText");
  EXPECT_NE(panel.find("r1/front"), std::string::npos) << panel;
  EXPECT_NE(panel.find("r2/rear"), std::string::npos) << panel;
  EXPECT_NE(panel.find("40 of 42"), std::string::npos) << panel;
  EXPECT_NE(panel.find("25 of 27"), std::string::npos) << panel;
}

// A real ogf-mapper mapping two robots (sensor front on r1, rear on r2, each robot with its own odometry,
// 20 m apart): the page draws both trails and lists both sources with what the mapper counted.
TEST(ViewInBrowser, ARealMappersTwoRobotsAreDrawnAsTwoTrailsAndListedWithTheirCounts) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  HeadlessChromium browser;
  if (auto why = browser.start(kWidth, kHeight)) GTEST_SKIP() << "chromium cannot run here: " << *why;

  const std::string bus = ogf::testing::loopbackUdpmUrl(26);
  const fs::path config = fs::temp_directory_path() / ("ogf-view-two-robots-" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(config) << "status_interval_s: 0.1\n" << ogf::testing::kTwoRobotsSources;
  using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;
  Mapper mapper({std::string(OGF_BIN_DIR) + "/ogf-mapper", "--lcm-url", bus, "--config", config.string(), "--in-memory"},
                (screenshotDir() / "two-robots-mapper.log").string(), bus, ogf::testing::kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(std::chrono::seconds(10)));
  ViewProcess view({"--lcm-url", bus, "--port", "0", "--rate", "5"}, "two-robots");
  const std::string url = view.url();
  ASSERT_FALSE(url.empty());

  constexpr int kSteps = 15;
  lcm::LCM lcm(bus);
  ogf::testing::feedTwoRobots(lcm, mapper, kSteps, 20.0);
  const auto done = mapper.waitForStatus([](const ogf::mapper_status_t& s) { return s.scans_mapped == 2 * kSteps; },
                                         std::chrono::seconds(30));
  fs::remove(config);
  ASSERT_TRUE(done) << mapper.log();

  ASSERT_TRUE(browser.open(url));
  const std::string title = browser.waitForTitle("source trails 2", std::chrono::seconds(30));
  if (title.find("no WebGL") != std::string::npos) GTEST_SKIP() << "chromium has no WebGL here: " << title;
  ASSERT_NE(title.find("source trails 2"), std::string::npos) << "title: " << title << "\n" << view.log();
  const RgbImage img = screenshot(browser, "two-robots.png");
  EXPECT_GT(cellPixels(img), 2000u) << "the map is not on the screen";
  const std::string panel = browser.evaluate("document.getElementById('sources').innerText");
  EXPECT_NE(panel.find("r1/front"), std::string::npos) << panel;
  EXPECT_NE(panel.find("r2/rear"), std::string::npos) << panel;
  const std::string mapped = std::to_string(kSteps) + " of " + std::to_string(kSteps);
  ASSERT_NE(panel.find(mapped), std::string::npos) << "each source should show " << mapped << " scans mapped: " << panel;
  EXPECT_NE(panel.rfind(mapped), panel.find(mapped)) << "each source should show " << mapped << " scans mapped: " << panel;
  EXPECT_TRUE(mapper.stop());
}

// Where pixels of one colour class lie right of the panel: how many, and their bounding box.
struct PixelClass {
  std::size_t count = 0;
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};

template <class Is>
PixelClass pixelsWhere(const RgbImage& img, Is is) {
  PixelClass c;
  for (int y = 0; y < img.height; ++y)
    for (int x = kPanelRight; x < img.width; ++x) {
      const auto* p = img.at(x, y);
      if (!is(int{p[0]}, int{p[1]}, int{p[2]})) continue;
      ++c.count;
      c.x0 = std::min(c.x0, x), c.y0 = std::min(c.y0, y), c.x1 = std::max(c.x1, x), c.y1 = std::max(c.y1, y);
    }
  return c;
}
// The page's occupied columns: dark red (red well above green and blue). Nothing else on this page is.
PixelClass occupiedColumnPixels(const RgbImage& img) {
  return pixelsWhere(img, [](int r, int g, int b) { return r >= 70 && r >= 3 * g && r >= 3 * b; });
}
// The page's free columns: light grey (the background, the 1 m grid and the axes are dark or saturated).
PixelClass freeColumnPixels(const RgbImage& img) {
  return pixelsWhere(img, [](int r, int g, int b) {
    return std::min({r, g, b}) >= 150 && std::max({r, g, b}) - std::min({r, g, b}) <= 40;
  });
}

// The page's free columns at any cost, from light grey (cost 0) to slate (cost 100), through the layer's
// opacity: each channel 70 or more and within 45 of the others. The background and the 1 m grid are
// darker, the boxes saturated (the floor's, dark blue, too).
PixelClass freeColumnPixelsAtAnyCost(const RgbImage& img) {
  return pixelsWhere(img, [](int r, int g, int b) {
    return std::min({r, g, b}) >= 70 && std::max({r, g, b}) - std::min({r, g, b}) <= 45;
  });
}

// The title once the page drew the grid with `columns` known columns and showed nav seq `seq` in its
// figures, publishing `msgs` every half second until then (a datagram may be lost on loopback).
std::string waitForGrid(HeadlessChromium& browser, lcm::LCM& lcm, const std::vector<ogf::nav_grid_t>& msgs,
                        std::size_t columns, int seq) {
  const std::string want = "nav columns " + std::to_string(columns);
  std::string title;
  for (int i = 0; i < 60; ++i) {
    ogf::testing::publishAll(lcm, "OGF_NAV_GRID", msgs);
    title = browser.waitForTitle(want, std::chrono::milliseconds(500));
    if (title.find(want) == std::string::npos) continue;
    if (panelFigure(browser, "nav seq") == std::to_string(seq)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  return title;
}

// The grid of a room published as ogf-mapper publishes it (NavStream over a NavProjection, real udpm): the
// view asks for a keyframe on OGF_NAV_REQUEST at start; the page lays the grid flat at its floor, the walls'
// columns dark red around the light free floor; an update (a table in the room) adds dark red inside; the
// `n` key hides the layer (its pixels vanish) and the checkbox brings it back. The panel shows the grid's
// figures.
TEST(ViewInBrowser, NavGridIsDrawnInItsColoursWhereItsColumnsAreAndItsToggleHidesIt) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  HeadlessChromium browser;
  if (auto why = browser.start(kWidth, kHeight)) GTEST_SKIP() << "chromium cannot run here: " << *why;

  const std::string bus = ogf::testing::loopbackUdpmUrl(32);
  lcm::LCM lcm(bus);
  ASSERT_TRUE(lcm.good());
  struct Requests {
    std::vector<ogf::map_request_t> seen;
    void on(const lcm::ReceiveBuffer*, const std::string&, const ogf::map_request_t* m) { seen.push_back(*m); }
  } requests;
  lcm.subscribe("OGF_NAV_REQUEST", &Requests::on, &requests);
  ViewProcess view({"--lcm-url", bus, "--port", "0", "--rate", "5"}, "nav");
  const std::string url = view.url();
  ASSERT_FALSE(url.empty());
  for (int i = 0; i < 40 && requests.seen.empty(); ++i) lcm.handleTimeout(100);  // at start, then every second
  ASSERT_FALSE(requests.seen.empty()) << "ogf-view asked for no navigation keyframe\n" << view.log();
  EXPECT_EQ(requests.seen.front().last_seq, -1);
  EXPECT_NE(requests.seen.front().requester.find("ogf-view"), std::string::npos) << requests.seen.front().requester;

  ogf::testing::NavRoom room;
  const std::size_t columns = room.knownColumns();
  ASSERT_EQ(columns, static_cast<std::size_t>(ogf::testing::NavRoom::kSide * ogf::testing::NavRoom::kSide));
  ASSERT_TRUE(browser.open(url));
  std::string title = waitForGrid(browser, lcm, room.keyframe(1), columns, 0);
  if (title.find("no WebGL") != std::string::npos) GTEST_SKIP() << "chromium has no WebGL here: " << title;
  ASSERT_NE(title.find("nav columns " + std::to_string(columns)), std::string::npos) << "title: " << title << "\n" << view.log();
  EXPECT_EQ(panelFigure(browser, "nav columns known"), std::to_string(columns));
  EXPECT_EQ(panelFigure(browser, "nav = mapper"), "yes");
  EXPECT_EQ(panelFigure(browser, "nav malformed"), "0");

  const RgbImage on = screenshot(browser, "nav-on.png");
  const PixelClass walls = occupiedColumnPixels(on), floor = freeColumnPixels(on);
  EXPECT_GT(walls.count, 2000u) << "the walls' columns are not dark red (nav-on.png)";
  EXPECT_GT(floor.count, 10000u) << "the free floor is not light (nav-on.png)";
  // The walls surround the floor.
  EXPECT_LT(walls.x0, floor.x0);
  EXPECT_GT(walls.x1, floor.x1);
  EXPECT_LT(walls.y0, floor.y0);
  EXPECT_GT(walls.y1, floor.y1);

  // A table in the middle of the room: one changed tile, dark red where the floor was light.
  const auto update = room.addObstacle(6, 9, 6, 9, 2);
  title = waitForGrid(browser, lcm, update, columns, 1);
  const RgbImage table = screenshot(browser, "nav-table.png");
  const PixelClass walls_and_table = occupiedColumnPixels(table);
  EXPECT_GT(walls_and_table.count, walls.count + 500) << "the table is not drawn (nav-table.png)";
  EXPECT_LT(freeColumnPixels(table).count, floor.count - 500);
  EXPECT_EQ(panelFigure(browser, "nav seq"), "1");

  // `n` hides the layer, the checkbox shows it again.
  hideNavLayer(browser);
  if (HasFatalFailure()) return;
  EXPECT_EQ(browser.evaluate("String(document.getElementById('nav-on').checked)"), "false");
  const RgbImage off = screenshot(browser, "nav-off.png");
  // What stays red is the x axis (1 m, red).
  EXPECT_LT(occupiedColumnPixels(off).count, walls.count / 50) << "dark red stays with the layer hidden (nav-off.png)";
  EXPECT_LT(freeColumnPixels(off).count, floor.count / 50) << "light pixels stay with the layer hidden (nav-off.png)";

  browser.evaluate("document.getElementById('nav-on').click()");
  title = browser.waitForTitle("nav columns " + std::to_string(columns), std::chrono::seconds(10));
  ASSERT_NE(title.find("nav columns"), std::string::npos) << title;
  const RgbImage again = screenshot(browser, "nav-on-again.png");
  EXPECT_GT(occupiedColumnPixels(again).count, walls.count);
}

// ogf-view showing the map file `path` (the room: its boxes and its grid's 225 columns) in `browser`, the
// panel's figures filled in; nullptr when it is not drawn (the test failed, saying why), or when the browser
// has no WebGL (`no_webgl` set to its title, for the test to skip).
std::unique_ptr<ViewProcess> showRoomFile(HeadlessChromium& browser, const fs::path& path, std::size_t boxes,
                                          const std::string& name, std::string& no_webgl) {
  auto view = std::make_unique<ViewProcess>(std::vector<std::string>{"--map", path.string(), "--port", "0"}, name);
  const std::string url = view->url();
  if (url.empty() || !browser.open(url)) {
    ADD_FAILURE() << "ogf-view serves no page for " << path;
    return nullptr;
  }
  const std::string want = "drawn " + std::to_string(boxes) + " boxes";
  std::string title = browser.waitForTitle(want, std::chrono::seconds(30));
  if (title.find("no WebGL") != std::string::npos) {
    no_webgl = title;
    return nullptr;
  }
  if (title.find(want) == std::string::npos) {
    ADD_FAILURE() << "title: " << title << "\n" << view->log();
    return nullptr;
  }
  title = browser.waitForTitle("nav columns 225", std::chrono::seconds(10));
  if (title.find("nav columns 225") == std::string::npos) {
    ADD_FAILURE() << "the map's navigation grid is not drawn: " << title;
    return nullptr;
  }
  for (int i = 0; i < 100 && panelFigure(browser, "occupied") != std::to_string(boxes); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(panelFigure(browser, "occupied"), std::to_string(boxes));
  return view;
}

// One row of the figures panel as laid out: its name, its value, where the value's text lies (pixels),
// whether the value's cell clips it and whether the text ends inside the panel's visible part.
struct PanelRow {
  std::string name, value;
  int text_left = 0, text_right = 0;
  bool whole = false, inside = false;
};
struct PanelLayout {
  int scroll_width = 0, client_width = 0;  // the panel's: wider content means a horizontal scroll bar
  std::string source;                      // the text the panel shows as the map's source
  bool source_inside = false;              // the source's text ends inside the panel's visible part
  std::vector<PanelRow> rows;
  const PanelRow* row(const std::string& name) const {
    for (const auto& r : rows)
      if (r.name == name) return &r;
    return nullptr;
  }
};

std::vector<std::string> split(const std::string& s, char by) {
  std::vector<std::string> out;
  std::string::size_type from = 0;
  while (true) {
    const auto at = s.find(by, from);
    out.push_back(s.substr(from, at == std::string::npos ? std::string::npos : at - from));
    if (at == std::string::npos) return out;
    from = at + 1;
  }
}

// The panel as the browser laid it out (the page's DOM, read with Runtime.evaluate): fields separated by
// '|', rows by '^' (neither occurs in the figures or in this test's paths).
PanelLayout panelLayout(HeadlessChromium& browser) {
  const std::string js =
      "(() => { const p = document.getElementById('panel'), pr = p.getBoundingClientRect();"
      "  const visible = pr.left + p.clientLeft + p.clientWidth;"
      "  const textBox = el => { const r = document.createRange(); r.selectNodeContents(el); return r.getBoundingClientRect(); };"
      "  const src = document.getElementById('source');"
      "  const head = [p.scrollWidth, p.clientWidth, src ? src.textContent : '',"
      "                src && textBox(src).right <= visible + 0.5 ? 1 : 0].join('|');"
      "  const rows = [...document.querySelectorAll('#figures tr')].filter(r => r.cells.length === 2).map(r => {"
      "    const v = r.cells[1], b = textBox(v);"
      "    return [r.cells[0].textContent, v.textContent, Math.round(b.left), Math.round(b.right),"
      "            v.scrollWidth <= v.clientWidth ? 1 : 0, b.right <= visible + 0.5 ? 1 : 0].join('|'); });"
      "  return [head, ...rows].join('^'); })()";
  PanelLayout layout;
  const auto rows = split(browser.evaluate(js), '^');
  const auto head = split(rows.front(), '|');
  if (head.size() != 4) {
    ADD_FAILURE() << "the page did not say how its panel is laid out";
    return layout;
  }
  layout.scroll_width = std::stoi(head[0]);
  layout.client_width = std::stoi(head[1]);
  layout.source = head[2];
  layout.source_inside = head[3] == "1";
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto f = split(rows[i], '|');
    if (f.size() != 6) continue;
    layout.rows.push_back({f[0], f[1], std::stoi(f[2]), std::stoi(f[3]), f[4] == "1", f[5] == "1"});
  }
  return layout;
}

// The room's map saved under a short path and under a long one (a directory name of 90 characters
// without a place to break a line, as out/ directories of a deep checkout): with the long path the
// panel keeps the layout it has with the short one. The map's figures read the same at the same place,
// every value's text ends inside the panel, the panel does not scroll sideways, and the panel shows
// the whole long path.
TEST(ViewInBrowser, ThePanelKeepsItsLayoutAndItsFiguresWholeWithALongMapPath) {
  HeadlessChromium browser;
  if (auto why = browser.start(kWidth, kHeight)) GTEST_SKIP() << "chromium cannot run here: " << *why;
  const std::string pid = std::to_string(::getpid());
  const fs::path short_path = fs::temp_directory_path() / ("r" + pid + ".ogfm");
  const fs::path long_dir = fs::temp_directory_path() /
                            ("ogf_view_panel_test_with_a_directory_name_as_long_as_those_of_a_deep_checkout_" + pid) /
                            "out";
  fs::create_directories(long_dir);
  const fs::path long_path = long_dir / "map.ogfm";
  const std::size_t boxes = saveRoom(short_path, false);
  ASSERT_GT(boxes, 100u);
  fs::copy_file(short_path, long_path, fs::copy_options::overwrite_existing);

  // ogf-view reads the file at start: the files can go whatever the test finds.
  struct Remove {
    std::vector<fs::path> paths;
    ~Remove() {
      std::error_code ec;
      for (const auto& p : paths) fs::remove_all(p, ec);
    }
  } remove{{short_path, long_dir.parent_path()}};
  PanelLayout short_layout, long_layout;
  {
    std::string no_webgl;
    auto view = showRoomFile(browser, short_path, boxes, "panel-short-path", no_webgl);
    if (!no_webgl.empty()) GTEST_SKIP() << "chromium has no WebGL here: " << no_webgl;
    if (!view) return;
    short_layout = panelLayout(browser);
    screenshot(browser, "panel-short-path.png");
  }
  {
    std::string no_webgl;
    auto view = showRoomFile(browser, long_path, boxes, "panel-long-path", no_webgl);
    if (!view) return;
    long_layout = panelLayout(browser);
    screenshot(browser, "panel-long-path.png");
  }
  for (const auto* layout : {&short_layout, &long_layout}) {
    const std::string which = layout == &short_layout ? "short path: " : "long path: ";
    EXPECT_LE(layout->scroll_width, layout->client_width) << which << "the panel scrolls sideways";
    EXPECT_GT(layout->rows.size(), 10u) << which << "the panel has too few figures";
    for (const auto& r : layout->rows) {
      EXPECT_TRUE(r.whole) << which << "'" << r.name << "' clips its value " << r.value;
      EXPECT_TRUE(r.inside) << which << "'" << r.name << "' shows its value " << r.value
                            << " beyond the panel's visible edge (text ends at x = " << r.text_right << ")";
    }
    EXPECT_TRUE(layout->source_inside) << which << "the map's path runs beyond the panel";
  }
  EXPECT_NE(short_layout.source.find(short_path.string()), std::string::npos) << short_layout.source;
  EXPECT_NE(long_layout.source.find(long_path.string()), std::string::npos)
      << "the panel does not show the whole path: " << long_layout.source;
  // The map's own figures: the same values at the same place across the panel with either path.
  for (const std::string name : {"seq", "cells", "occupied", "boxes drawn", "nav columns known", "nav seq",
                                 "gaps / keyframes", "malformed messages"}) {
    const PanelRow* s = short_layout.row(name);
    const PanelRow* l = long_layout.row(name);
    ASSERT_NE(s, nullptr) << "short path: no row '" << name << "'";
    ASSERT_NE(l, nullptr) << "long path: no row '" << name << "'";
    EXPECT_EQ(l->value, s->value) << name;
    EXPECT_NEAR(l->text_left, s->text_left, 1) << name << ": its value moved across the panel with the long path";
    EXPECT_NEAR(l->text_right, s->text_right, 1) << name << ": its value moved across the panel with the long path";
  }
}

// The room with its floor measured occupied (the floor's boxes, z = 0 to 0.2 m, lie where the grid is
// drawn): with the grid's layer on, the grid shows as much of its light free floor as in the same room
// without a floor, whose camera and grid are the same; the floor's boxes come back when the layer is off.
// The page hides the boxes below the band over the grid's known columns while the layer is on (the panel
// says how many: the floor's 169 and the walls' lowest 56). Measured in this test's screenshots (1000 × 557
// drawn): the room without a floor shows about 27 500 of the grid's free pixels, the room with its floor
// as many when the floor's boxes are hidden, and 19 when they are drawn where the grid is (it lies 1 cm
// above the floor, inside the boxes' height). More than 90 % of the reference is asked for.
TEST(ViewInBrowser, NavGridIsVisibleOverTheFloorsBoxes) {
  HeadlessChromium browser;
  if (auto why = browser.start(kWidth, kHeight)) GTEST_SKIP() << "chromium cannot run here: " << *why;
  const std::string pid = std::to_string(::getpid());
  const fs::path bare_path = fs::temp_directory_path() / ("ogf-view-room-" + pid + ".ogfm");
  const fs::path floor_path = fs::temp_directory_path() / ("ogf-view-room-floor-" + pid + ".ogfm");
  const std::size_t bare_boxes = saveRoom(bare_path, false), floor_boxes = saveRoom(floor_path, true);
  struct Remove {
    std::vector<fs::path> paths;
    ~Remove() {
      std::error_code ec;
      for (const auto& p : paths) fs::remove(p, ec);
    }
  } remove{{bare_path, floor_path}};
  ASSERT_EQ(floor_boxes, bare_boxes + 13 * 13) << "the floor inside the walls is not occupied";

  std::size_t bare_grid = 0;
  {
    std::string no_webgl;
    auto view = showRoomFile(browser, bare_path, bare_boxes, "grid-no-floor", no_webgl);
    if (!no_webgl.empty()) GTEST_SKIP() << "chromium has no WebGL here: " << no_webgl;
    if (!view) return;
    bare_grid = freeColumnPixelsAtAnyCost(screenshot(browser, "grid-no-floor.png")).count;
  }
  ASSERT_GT(bare_grid, 10000u) << "the grid of the room without a floor is not drawn (grid-no-floor.png)";

  std::string no_webgl;
  auto view = showRoomFile(browser, floor_path, floor_boxes, "grid-over-floor", no_webgl);
  if (!view) return;
  EXPECT_EQ(panelFigure(browser, "boxes under the grid"), "225 hidden");
  EXPECT_NE(browser.title().find("hidden under the grid 225"), std::string::npos) << browser.title();
  const RgbImage on = screenshot(browser, "grid-over-floor.png");
  const std::size_t floor_grid = freeColumnPixelsAtAnyCost(on).count;
  EXPECT_GT(floor_grid, bare_grid * 9 / 10) << "the grid is hidden under the floor's boxes: " << floor_grid
                                            << " light grid pixels, " << bare_grid
                                            << " without a floor (grid-over-floor.png, grid-no-floor.png)";
  hideNavLayer(browser);
  if (HasFatalFailure()) return;
  EXPECT_EQ(panelFigure(browser, "boxes under the grid"), "225 shown");
  const RgbImage off = screenshot(browser, "grid-over-floor-off.png");
  EXPECT_LT(freeColumnPixelsAtAnyCost(off).count, bare_grid / 50) << "light pixels stay with the layer hidden";
  EXPECT_GT(cellPixels(off), cellPixels(on) + 10000) << "the floor's boxes are not drawn with the layer hidden "
                                                        "(grid-over-floor-off.png)";
}

TEST(ViewProgram, ExitCodesSayUsageOrFailure) {
  const std::string exe = std::string(OGF_BIN_DIR) + "/ogf-view";
  const auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), exe);
    const std::string log = (fs::temp_directory_path() / ("ogf-view-rc-" + std::to_string(::getpid()))).string();
    ChildProcess p(args, log);
    const auto rc = p.wait(std::chrono::seconds(20));
    fs::remove(log);
    return rc.value_or(-1000);
  };
  EXPECT_EQ(run({"--help"}), 0);
  EXPECT_EQ(run({"--no-such-flag"}), 2);
  EXPECT_EQ(run({"--port", "70000"}), 2);
  EXPECT_EQ(run({"--map", "/nonexistent.ogfm"}), 2);
  const fs::path block = fs::temp_directory_path() / ("ogf-view-rc-block-" + std::to_string(::getpid()) + ".ogfm");
  ogf::testing::writeBlockMap(block, 4, 4, 4);
  EXPECT_EQ(run({"--map", block.string(), "--port", "0", "--nav-min-height", "2", "--nav-max-height", "1"}), 2)
      << "a navigation band with no layer is a usage error";
  fs::remove(block);
  EXPECT_EQ(run({"--three-dir", "/nonexistent", "--port", "0"}), 1);
  EXPECT_EQ(run({"--bind", "not-an-address", "--port", "0", "--lcm-url", "memq://"}), 1);
  const fs::path short_token = fs::temp_directory_path() / ("ogf-view-short-token-" + std::to_string(::getpid()));
  std::ofstream(short_token) << "abc\n";
  EXPECT_EQ(run({"--token", short_token.string(), "--port", "0", "--lcm-url", "memq://"}), 2);
  fs::remove(short_token);
}

}  // namespace
