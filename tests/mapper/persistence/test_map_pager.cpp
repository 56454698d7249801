// Paging the far regions of a map to disk: a map mapped with paging is bit-identical to one mapped
// without, whatever the distance, and so is the delta stream when the published cells page with it; memory
// holds only the regions near the sensor; pages are checked when read and damage names the file; snapshots
// name the pages that hold the rest of their map.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/delta/keyframe_writer.hpp"
#include "ogf/delta/map_receiver.hpp"
#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/map_checksum.hpp"
#include "ogf/persistence/map_pager.hpp"
#include "ogf/persistence/page_file.hpp"
#include "ogf/persistence/state_directory.hpp"

namespace {

using namespace ogf;
using namespace ogf::persistence;
namespace fs = std::filesystem;

class MapPagerTest : public ::testing::Test {
 public:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ogf-pager-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A page made by hand, as the only file of the directory; its name.
  std::string writeOnlyPage(const Page& page) const {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const auto bytes = encodePage(page);
    std::ofstream(dir_ / "r0_0_0-1.ogfp", std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    return "r0_0_0-1.ogfp";
  }

  static filter::BandedOgf makeMap(int dimensions, filter::CovarianceStorage storage) {
    filter::FilterConfig c;
    c.dimensions = dimensions;
    c.resolution = 0.1;
    c.covariance = storage;
    auto map = filter::BandedOgf::create(c);
    EXPECT_TRUE(map.ok()) << map.error().message;
    return std::move(*map);
  }

  // A "scan" seen from x = position: free cells along a ray to a wall 3 m ahead, occupied cells on it,
  // and some ground. 3-D keys unless `flat`.
  static std::vector<Measurement> scanAt(double position, bool flat, std::mt19937& rng) {
    std::vector<Measurement> out;
    const int x0 = static_cast<int>(position / 0.1);
    std::uniform_int_distribution<int> jitter(-3, 3);
    for (int ray = -20; ray <= 20; ++ray) {
      const int y = ray * 2 + jitter(rng);
      for (int step = 0; step < 30; ++step) out.push_back({{x0 + step, y, flat ? 0 : 5}, Measurement::kFree});
      out.push_back({{x0 + 30, y, flat ? 0 : 5}, Measurement::kOccupied});
      if (!flat) out.push_back({{x0 + 5, y, -1}, Measurement::kOccupied});
    }
    // One cell per key, as a measurement set holds.
    std::sort(out.begin(), out.end(), [](const Measurement& a, const Measurement& b) { return a.key < b.key; });
    out.erase(std::unique(out.begin(), out.end(),
                          [](const Measurement& a, const Measurement& b) { return a.key == b.key; }),
              out.end());
    return out;
  }
  // Scans 0 .. `steps` m along x, each region farther than `distance` paged out after every scan.
  static void mapWithPaging(filter::BandedOgf& map, MapPager& pager, unsigned seed, int steps, double distance) {
    std::mt19937 rng(seed);
    for (int step = 0; step <= steps; ++step) {
      const auto scan = scanAt(step, map.config().dimensions == 2, rng);
      ASSERT_TRUE(pager.bringIn(map, scan).empty());
      map.update(scan);
      ASSERT_TRUE(pager.sendAway(map, {static_cast<double>(step), 0, 0.5}, distance).ok());
    }
  }

  // Drives out 40 m and back, paging out every region farther than `distance` from the sensor: after every
  // scan the checksum of the paged map (its pages counted) equals the map's without paging, and brought back
  // at the end the two are the same block for block. Returns the most blocks held in memory while paging.
  std::size_t driveOutAndBack(int dimensions, filter::CovarianceStorage storage, double distance) {
    auto plain = makeMap(dimensions, storage);
    auto paged = makeMap(dimensions, storage);
    auto pager = MapPager::open(dir_ / "pages");
    EXPECT_TRUE(pager.ok()) << pager.error().message;
    std::mt19937 rng(7);
    std::size_t most = 0;
    const bool flat = dimensions == 2;
    for (int step = 0; step <= 80; ++step) {
      const double x = step <= 40 ? step : 80 - step;
      const auto scan = scanAt(x, flat, rng);
      plain.update(scan);
      EXPECT_TRUE(pager->bringIn(paged, scan).empty());
      paged.update(scan);
      const auto st = pager->sendAway(paged, {x, 0.0, 0.5}, distance);
      EXPECT_TRUE(st.ok()) << st.error().message;
      EXPECT_EQ(paged.checksum(pager->heldBlocks()), plain.checksum()) << "after scan " << step;
      EXPECT_EQ(paged.allocatedCells() + pager->heldCells(paged), plain.allocatedCells());
      most = std::max(most, paged.blockKeys().size());
    }
    EXPECT_GT(pager->counts().pages_written, 0u);
    EXPECT_GT(pager->counts().pages_read, 0u) << "the way back must bring pages in";
    EXPECT_TRUE(pager->bringInAll(paged).empty());
    EXPECT_EQ(pager->counts().regions_out, 0u);
    EXPECT_EQ(paged.blockKeys(), plain.blockKeys());
    for (const CellKey& key : plain.blockKeys()) {
      const auto a = plain.storedValues(key);
      const auto b = paged.storedValues(key);
      EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "block " << key.x << "," << key.y;
      const auto ma = plain.blockMarks(key);
      const auto mb = paged.blockMarks(key);
      EXPECT_TRUE(std::equal(ma.begin(), ma.end(), mb.begin(), mb.end()));
    }
    EXPECT_EQ(paged.checksum(), plain.checksum());
    return most;
  }
  fs::path dir_;
};

TEST_F(MapPagerTest, PagedMapIsBitIdenticalAndSmallerIn3DCompactStorage) {
  const std::size_t most = driveOutAndBack(3, filter::CovarianceStorage::kCompact, 8.0);
  auto plain = makeMap(3, filter::CovarianceStorage::kCompact);
  std::mt19937 rng(7);
  for (int step = 0; step <= 40; ++step) plain.update(scanAt(step, false, rng));
  EXPECT_LT(most * 2, plain.blockKeys().size()) << "paging must hold less than half of a 40 m drive's blocks";
}

TEST_F(MapPagerTest, PagedMapIsBitIdenticalIn3DBandedStorage) {
  driveOutAndBack(3, filter::CovarianceStorage::kBanded, 8.0);
}

TEST_F(MapPagerTest, PagedMapIsBitIdenticalIn2D) { driveOutAndBack(2, filter::CovarianceStorage::kCompact, 8.0); }

TEST_F(MapPagerTest, PagingCloserThanTheScansReachIsStillExact) {
  // The scans reach 3 m; regions beyond 1 m go out after every scan and come straight back.
  driveOutAndBack(3, filter::CovarianceStorage::kCompact, 1.0);
}

TEST_F(MapPagerTest, PageRoundTripsAndDamageNamesTheFileAndOffset) {
  Page page;
  page.region = {-3, 4, -1};
  page.floats_per_block = 3;
  page.cells_per_block = 2;
  page.blocks.push_back({{-12, 16, -4}, {1.5F, -2.0F, 3.25F}, {0x80, 7}});
  page.blocks.push_back({{-11, 16, -4}, {0.0F, 1.0F, 2.0F}, {0, 0}});
  page.published.push_back({{-96, 128, -30}, 9321, 1, 0.0125F});
  page.published.push_back({{-95, 130, -29}, 120, -1, 3.5e-7F});
  auto bytes = encodePage(page);
  auto back = decodePage(bytes, "p.ogfp");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->region, page.region);
  ASSERT_EQ(back->blocks.size(), 2u);
  EXPECT_EQ(back->blocks[0].key, page.blocks[0].key);
  EXPECT_EQ(back->blocks[0].stored, page.blocks[0].stored);
  EXPECT_EQ(back->blocks[0].marks, page.blocks[0].marks);
  ASSERT_EQ(back->published.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back->published[i].key, page.published[i].key);
    EXPECT_EQ(back->published[i].probability, page.published[i].probability);
    EXPECT_EQ(back->published[i].cell_class, page.published[i].cell_class);
    EXPECT_EQ(back->published[i].variance, page.published[i].variance);
  }
  for (std::size_t i = 0; i < bytes.size(); i += 7) {
    auto damaged = bytes;
    damaged[i] ^= std::byte{0x10};
    const auto r = decodePage(damaged, "p.ogfp");
    ASSERT_FALSE(r.ok()) << "byte " << i;
    EXPECT_NE(r.error().message.find("p.ogfp: offset "), std::string::npos) << r.error().message;
  }
  const auto cut = decodePage(std::span(bytes).first(bytes.size() - 5), "p.ogfp");
  ASSERT_FALSE(cut.ok());
}

TEST_F(MapPagerTest, PageOfTheFirstVersionIsRead) {
  // Version 1 ended with the blocks: no published cells' count.
  Page page;
  page.region = {1, 2, 3};
  page.floats_per_block = 1;
  page.cells_per_block = 1;
  page.blocks.push_back({{4, 8, 12}, {0.5F}, {3}});
  auto bytes = encodePage(page);
  bytes.resize(bytes.size() - 8 - 4);
  bytes[8] = std::byte{1};
  filter::MapChecksum sum;
  sum.add(bytes);
  for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<std::byte>((sum.value() >> (8 * i)) & 0xFFU));
  const auto back = decodePage(bytes, "v1.ogfp");
  ASSERT_TRUE(back.ok()) << back.error().message;
  ASSERT_EQ(back->blocks.size(), 1u);
  EXPECT_EQ(back->blocks[0].stored, page.blocks[0].stored);
  EXPECT_TRUE(back->published.empty());
  EXPECT_FALSE(back->has_published) << "a version 1 page says nothing of the published cells";
  bytes[8] = std::byte{3};
  EXPECT_FALSE(decodePage(bytes, "v1.ogfp").ok());
}

// The daemon's delta stream beside the map: the published cells of a region go to its page and come back
// with it. Out 40 m and back, paging beyond 8 m: every scan's delta messages (cells, checksum) equal those
// of a stream whose map is never paged, and so does a keyframe taken out there with the paged-out cells read
// from their pages; the published map in memory stays below half of the whole. With `restart`, the paged
// side restarts out there as the daemon does: the map in memory, a new pager adopting the pages, a
// published map of the cells in memory holding those of the pages (holdPublished), and drives back so.
void publishedCellsPageWithTheirRegions(const fs::path& dir, bool restart) {
  class Collect : public filter::ChangeSink {
   public:
    void cellChanged(const filter::CellChange& c) override {
      cells.push_back({c.key, static_cast<std::int16_t>(c.quantisedProbability), c.occupancyClass, c.variance});
    }
    std::vector<delta::PublishedCell> cells;
  };
  const auto sameMessages = [](const std::vector<ogf::map_delta_t>& a, const std::vector<ogf::map_delta_t>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (a[i].map_checksum != b[i].map_checksum || a[i].seq != b[i].seq || a[i].num_cells != b[i].num_cells ||
          a[i].key_x != b[i].key_x || a[i].key_y != b[i].key_y || a[i].key_z != b[i].key_z ||
          a[i].probability != b[i].probability || a[i].cell_class != b[i].cell_class ||
          a[i].variance != b[i].variance)
        return false;
    }
    return true;
  };
  filter::FilterConfig config;
  config.resolution = 0.1;
  config.covariance = filter::CovarianceStorage::kCompact;
  auto plain = filter::BandedOgf::create(config);
  auto paged = filter::BandedOgf::create(config);
  ASSERT_TRUE(plain.ok() && paged.ok());
  delta::DeltaStream plainStream({0.1, 7, 500});
  auto pagedStream = std::make_unique<delta::DeltaStream>(delta::DeltaStreamConfig{0.1, 7, 500});
  auto pager = MapPager::open(dir / "pages");
  ASSERT_TRUE(pager.ok());
  std::mt19937 rng(9);
  std::size_t mostResident = 0;
  for (int step = 0; step <= 80; ++step) {
    const double x = step <= 40 ? step : 80 - step;
    const auto scan = MapPagerTest::scanAt(x, false, rng);
    Collect a;
    plain->update(scan, &a);
    const auto expected = plainStream.update(step, a.cells);
    ASSERT_TRUE(pager->bringIn(*paged, scan, &pagedStream->map()).empty());
    Collect b;
    paged->update(scan, &b);
    const auto got = pagedStream->update(step, b.cells);
    ASSERT_TRUE(pager->sendAway(*paged, {x, 0.0, 0.5}, 8.0, &pagedStream->map()).ok());
    ASSERT_TRUE(sameMessages(expected, got)) << "scan " << step;
    EXPECT_EQ(pagedStream->map().size(), plainStream.map().size());
    EXPECT_EQ(pagedStream->map().checksum(), plainStream.map().checksum());
    mostResident = std::max(mostResident, pagedStream->map().size() - pagedStream->map().held().cells);
    if (step == 40 && restart) {
      auto map = filter::BandedOgf::create(config);
      ASSERT_TRUE(map.ok());
      for (const CellKey& key : paged->blockKeys())
        ASSERT_TRUE(map->restoreStoredBlock(key, paged->storedValues(key), paged->blockMarks(key)).ok());
      auto adopted = MapPager::open(dir / "pages");
      ASSERT_TRUE(adopted.ok());
      ASSERT_TRUE(adopted->adopt(pager->files(), *map).empty());
      ASSERT_TRUE(adopted->bringInUnpublished(*map).empty());
      EXPECT_EQ(map->blockKeys(), paged->blockKeys()) << "every page holds its published cells: none comes back";
      auto stream = std::make_unique<delta::DeltaStream>(delta::DeltaStreamConfig{0.1, 7, 500});
      stream->reset(pagedStream->map().sortedCells(), pagedStream->seq());
      adopted->holdPublished(stream->map());
      EXPECT_EQ(stream->map().size(), plainStream.map().size());
      EXPECT_EQ(stream->map().checksum(), plainStream.map().checksum());
      paged = std::move(map);
      pager = std::move(adopted);
      pagedStream = std::move(stream);
    }
    if (step == 40) {
      // The keyframe as ogf-mapper sends it: the cells in memory, then each held page's cells as read.
      delta::KeyframeWriter writer(*pagedStream, 1);
      std::vector<ogf::map_delta_t> parts;
      writer.add(pagedStream->map().sortedCells(), parts);
      std::size_t fromPages = 0;
      for (const auto& page : pager->heldPublishedPages()) {
        auto cells = MapPager::publishedCellsOf(page);
        ASSERT_TRUE(cells.ok()) << cells.error().message;
        fromPages += cells->size();
        writer.add(*cells, parts);
      }
      writer.finish(parts);
      EXPECT_EQ(fromPages, pagedStream->map().held().cells);
      EXPECT_GT(fromPages, 0u);
      EXPECT_EQ(writer.missing() + writer.surplus(), 0u);
      delta::MapReceiver client;
      for (const auto& m : parts) client.accept(m);
      ASSERT_EQ(client.keyframesApplied(), 1u);
      EXPECT_TRUE(client.consistent());
      const auto rebuilt = client.map().sortedCells();
      const auto want = plainStream.map().sortedCells();
      ASSERT_EQ(rebuilt.size(), want.size());
      for (std::size_t i = 0; i < rebuilt.size(); ++i) {
        ASSERT_EQ(rebuilt[i].key, want[i].key);
        ASSERT_FALSE(rebuilt[i].visiblyDiffers(want[i]));
      }
    }
  }
  EXPECT_LT(mostResident * 2, plainStream.map().size()) << "the published map must page with the filter's";
  EXPECT_TRUE(pager->bringInAll(*paged, &pagedStream->map()).empty());
  EXPECT_EQ(pagedStream->map().held().cells, 0u);
  EXPECT_EQ(paged->checksum(), plain->checksum());
  const auto all = pagedStream->map().sortedCells();
  const auto expected = plainStream.map().sortedCells();
  ASSERT_EQ(all.size(), expected.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    ASSERT_EQ(all[i].key, expected[i].key);
    ASSERT_FALSE(all[i].visiblyDiffers(expected[i]));
    ASSERT_EQ(all[i].variance, expected[i].variance);
  }
}

TEST_F(MapPagerTest, PublishedCellsPageWithTheirRegionsAndTheDeltaStreamIsUnchanged) {
  publishedCellsPageWithTheirRegions(dir_, false);
}

TEST_F(MapPagerTest, RestartHoldsThePublishedCellsOfItsPagesWithoutReadingThemBack) {
  publishedCellsPageWithTheirRegions(dir_, true);
}

TEST_F(MapPagerTest, DamagedPageLosesOnlyItsRegionAndSaysWhich) {
  auto map = makeMap(3, filter::CovarianceStorage::kCompact);
  auto pager = MapPager::open(dir_);
  ASSERT_TRUE(pager.ok());
  mapWithPaging(map, *pager, 3, 20, 5.0);
  const auto files = pager->files();
  ASSERT_GE(files.size(), 2u);
  {
    std::fstream f(dir_ / files.front(), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put('\x5A');
  }
  const std::size_t out = pager->counts().regions_out;
  const auto damage = pager->bringInAll(map);
  ASSERT_EQ(damage.size(), 1u);
  EXPECT_EQ(damage[0].file, dir_ / files.front());
  EXPECT_NE(damage[0].reason.find(files.front()), std::string::npos) << damage[0].reason;
  EXPECT_NE(damage[0].reason.find("checksum"), std::string::npos) << damage[0].reason;
  EXPECT_EQ(pager->counts().regions_out, 0u);
  EXPECT_EQ(pager->counts().pages_read, out - 1);
}

TEST_F(MapPagerTest, AdoptedPagesComeBackAndCollectKeepsWhatASnapshotNames) {
  auto map = makeMap(3, filter::CovarianceStorage::kCompact);
  auto pager = MapPager::open(dir_);
  ASSERT_TRUE(pager.ok());
  mapWithPaging(map, *pager, 5, 20, 5.0);
  ASSERT_TRUE(pager->sync().ok());
  const auto names = pager->files();
  const auto whole = map.checksum(pager->heldBlocks());
  // A restart: the resident blocks from a map file (here: copied), the rest from the pages a snapshot names.
  auto restored = makeMap(3, filter::CovarianceStorage::kCompact);
  for (const CellKey& key : map.blockKeys())
    ASSERT_TRUE(restored.restoreStoredBlock(key, map.storedValues(key), map.blockMarks(key)).ok());
  auto again = MapPager::open(dir_);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(again->adopt(names, restored).empty());
  EXPECT_EQ(restored.checksum(again->heldBlocks()), whole);
  // A stray file from a run that crashed before its snapshot, and the pages the snapshot names.
  { std::ofstream(dir_ / "r9_9_9-999999.ogfp") << "torn"; }
  EXPECT_EQ(again->collect(names), 1u);
  EXPECT_FALSE(fs::exists(dir_ / "r9_9_9-999999.ogfp"));
  EXPECT_TRUE(again->bringInAll(restored).empty());
  EXPECT_EQ(restored.checksum(), whole);
  // Back in memory and named by no snapshot: collected.
  EXPECT_EQ(again->collect({}), names.size());
  EXPECT_TRUE(fs::is_empty(dir_));
}

// The flush of a snapshot in two steps: the pages written since the last one and still out are named once,
// flushed on any thread, and named again after a failed flush.
TEST_F(MapPagerTest, UnsyncedPagesAreNamedOnceAndAgainAfterAFailedFlush) {
  auto map = makeMap(3, filter::CovarianceStorage::kCompact);
  auto pager = MapPager::open(dir_);
  ASSERT_TRUE(pager.ok());
  mapWithPaging(map, *pager, 5, 20, 5.0);
  const auto names = pager->files();
  ASSERT_FALSE(names.empty());
  auto flush = pager->takeUnsynced();
  EXPECT_EQ(flush.dir, dir_);
  auto taken = flush.names;
  std::sort(taken.begin(), taken.end());
  EXPECT_EQ(taken, names) << "every page out was written since the pager opened";
  EXPECT_TRUE(pager->takeUnsynced().names.empty()) << "named once";
  // A flush that fails (a page gone) is an error naming it; given back, the next flush names them again.
  fs::rename(dir_ / names.front(), dir_ / "aside");
  const auto failed = MapPager::flushPages(flush);
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(failed.error().message.find(names.front()), std::string::npos) << failed.error().message;
  fs::rename(dir_ / "aside", dir_ / names.front());
  pager->giveBackUnsynced(flush);
  auto again = pager->takeUnsynced();
  std::sort(again.names.begin(), again.names.end());
  EXPECT_EQ(again.names, names);
  EXPECT_TRUE(MapPager::flushPages(again).ok());
  EXPECT_TRUE(pager->sync().ok());
  EXPECT_TRUE(pager->bringInAll(map).empty());
  mapWithPaging(map, *pager, 5, 20, 5.0);
  EXPECT_FALSE(pager->takeUnsynced().names.empty()) << "pages written again after coming back";
}

TEST_F(MapPagerTest, PagesOfAnotherLayoutAreRefused) {
  auto banded = makeMap(3, filter::CovarianceStorage::kBanded);
  auto pager = MapPager::open(dir_);
  mapWithPaging(banded, *pager, 1, 12, 3.0);
  ASSERT_TRUE(pager->sync().ok());
  auto compact = makeMap(3, filter::CovarianceStorage::kCompact);
  auto other = MapPager::open(dir_);
  const auto damage = other->adopt(pager->files(), compact);
  ASSERT_EQ(damage.size(), pager->files().size());
  EXPECT_NE(damage[0].reason.find("the map stores"), std::string::npos) << damage[0].reason;
}

TEST_F(MapPagerTest, PageWhoseBlockLiesOutsideItsRegionIsRefused) {
  auto map = makeMap(3, filter::CovarianceStorage::kCompact);
  Page page;
  page.region = {0, 0, 0};
  page.floats_per_block = static_cast<std::uint32_t>(map.storedFloatsPerBlock());
  page.cells_per_block = static_cast<std::uint32_t>(map.cellsPerBlock());
  page.blocks.push_back({{4, 0, 0}, std::vector<float>(page.floats_per_block), std::vector<std::uint8_t>(page.cells_per_block)});
  const std::vector<std::string> names = {writeOnlyPage(page)};
  auto pager = MapPager::open(dir_);
  const auto damage = pager->adopt(names, map);
  ASSERT_EQ(damage.size(), 1u);
  EXPECT_NE(damage[0].reason.find("block 4,0,0 lies outside the page's region"), std::string::npos)
      << damage[0].reason;
  EXPECT_EQ(pager->counts().regions_out, 0u);
}

TEST_F(MapPagerTest, PageWhosePublishedCellsCannotBeHeldIsRefused) {
  auto map = makeMap(3, filter::CovarianceStorage::kCompact);
  const std::int32_t side = 8 << MapPager::kRegionShift;  // cells per region side
  const delta::PublishedCell inside{{1, 2, side - 1}, 2500, 1, 0.5f};
  struct Case {
    std::vector<delta::PublishedCell> cells;
    std::string reason;  // "" when the page is to be adopted
  };
  const std::vector<Case> cases = {
      {{inside}, ""},
      {{inside, {{side, 0, 0}, 2500, 1, 0.5f}}, "published cell " + std::to_string(side) + ",0,0 lies outside"},
      {{inside, {{-1, 0, 0}, 2500, 1, 0.5f}}, "published cell -1,0,0 lies outside"},
      {{inside, inside}, "is named twice"},
      {{{{3, 3, 3}, 2500, 5, 0.5f}}, "has class 5 and probability 2500"},
      {{{{3, 3, 3}, 10001, 1, 0.5f}}, "has class 1 and probability 10001"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    Page page;
    page.region = {0, 0, 0};
    page.floats_per_block = static_cast<std::uint32_t>(map.storedFloatsPerBlock());
    page.cells_per_block = static_cast<std::uint32_t>(map.cellsPerBlock());
    page.has_published = true;
    page.published = cases[i].cells;
    const std::vector<std::string> names = {writeOnlyPage(page)};
    auto pager = MapPager::open(dir_);
    const auto damage = pager->adopt(names, map);
    if (cases[i].reason.empty()) {
      EXPECT_TRUE(damage.empty()) << "case " << i << ": " << damage.front().reason;
      EXPECT_EQ(pager->counts().regions_out, 1u) << "case " << i;
      continue;
    }
    ASSERT_EQ(damage.size(), 1u) << "case " << i;
    EXPECT_NE(damage[0].reason.find(cases[i].reason), std::string::npos) << "case " << i << ": " << damage[0].reason;
    EXPECT_NE(damage[0].reason.find("r0_0_0-1.ogfp"), std::string::npos) << damage[0].reason;
    EXPECT_EQ(pager->counts().regions_out, 0u) << "case " << i;
  }
}

TEST_F(MapPagerTest, SnapshotNamesItsPagesAndRecoveryGivesThemBack) {
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd.ok());
    ASSERT_TRUE(sd->recover(5).ok());
    const std::vector<std::uint8_t> map = {1, 2, 3};
    const std::vector<std::string> pages = {"r0_0_0-1.ogfp", "r-1_2_0-7.ogfp"};
    ASSERT_TRUE(sd->snapshot(4, map, pages).ok());
    EXPECT_EQ(sd->referencedPages(), pages);
    ASSERT_TRUE(sd->snapshot(5, map, std::vector<std::string>{"r3_0_0-9.ogfp"}).ok());
    const std::vector<std::string> both = {"r3_0_0-9.ogfp", "r0_0_0-1.ogfp", "r-1_2_0-7.ogfp"};
    EXPECT_EQ(sd->referencedPages(), both) << "the previous snapshot's pages are kept too";
  }
  auto sd = StateDirectory::open(dir_);
  auto r = sd->recover(1);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->snapshot_seq, 5);
  EXPECT_EQ(r->pages, std::vector<std::string>{"r3_0_0-9.ogfp"});
  // A snapshot without pages is the container's first version, which older readers read.
  const auto plain = encodeSnapshot(1, 2, std::vector<std::uint8_t>{9});
  EXPECT_EQ(static_cast<int>(plain[8]), 1);
  const auto named = encodeSnapshot(1, 2, std::vector<std::uint8_t>{9}, std::vector<std::string>{"a.ogfp"});
  EXPECT_EQ(static_cast<int>(named[8]), 2);
  for (std::size_t i = 0; i < named.size(); ++i) {
    auto damaged = named;
    damaged[i] ^= std::byte{0x01};
    EXPECT_FALSE(decodeSnapshot(damaged, "s").ok()) << "byte " << i;
  }
}

}  // namespace

