// ogf-map and ogf-eval read both files a map lives in: the filter's map file and the daemon's snapshot container.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <ogf/filter/map_file.hpp>
#include <ogf/persistence/map_pager.hpp>
#include <ogf/persistence/state_directory.hpp>

#include "ogf/map_formats/map_loader.hpp"

namespace {

namespace fs = std::filesystem;

ogf::filter::BandedOgf smallMap() {
  ogf::filter::FilterConfig cfg;
  cfg.resolution = 0.2;
  auto map = ogf::filter::BandedOgf::create(cfg);
  EXPECT_TRUE(map.ok());
  const std::vector<ogf::filter::Measurement> batch{{{1, 2, 3}, 1}, {{0, 2, 3}, -1}, {{-1, 2, 3}, -1}};
  map->update(batch);
  return std::move(*map);
}

fs::path scratch(const std::string& name) {
  return fs::temp_directory_path() / ("ogf-eval-loader-" + std::to_string(::getpid()) + "-" + name);
}

TEST(MapLoader, ReadsAMapFileAndASnapshotOfTheSameMapAlike) {
  const auto map = smallMap();
  const auto bytes = ogf::filter::encodeMap(map);
  const auto map_path = scratch("map.ogfm");
  const auto snap_path = scratch("snapshot.ogfs");
  ASSERT_TRUE(ogf::filter::saveMapFile(map, map_path).ok());
  const auto snap = ogf::persistence::encodeSnapshot(7, 42, bytes);
  std::ofstream(snap_path, std::ios::binary).write(reinterpret_cast<const char*>(snap.data()), static_cast<std::streamsize>(snap.size()));

  auto a = ogf::map_formats::loadOgfMap(map_path);
  auto b = ogf::map_formats::loadOgfMap(snap_path);
  fs::remove(map_path);
  fs::remove(snap_path);
  ASSERT_TRUE(a.ok()) << a.error().message;
  ASSERT_TRUE(b.ok()) << b.error().message;
  EXPECT_EQ(a->kind, "map file");
  EXPECT_EQ(b->kind, "snapshot");
  EXPECT_EQ(b->seq, 42);
  EXPECT_EQ(a->map.checksum(), map.checksum());
  EXPECT_EQ(b->map.checksum(), map.checksum());
}

TEST(MapLoader, ASnapshotThatNamesPagesIsLoadedWithThemAndRefusedWithoutThem) {
  ogf::filter::FilterConfig cfg;
  cfg.resolution = 0.2;
  auto map = ogf::filter::BandedOgf::create(cfg);
  ASSERT_TRUE(map.ok());
  std::vector<ogf::filter::Measurement> batch;
  for (int x = -100; x <= 100; x += 3) batch.push_back({{x, 2, 3}, x % 2 == 0 ? ogf::Measurement::kOccupied : ogf::Measurement::kFree});
  map->update(batch);
  const auto whole = map->checksum();
  const auto dir = scratch("state");
  fs::remove_all(dir);
  auto pager = ogf::persistence::MapPager::open(dir / "pages");
  ASSERT_TRUE(pager.ok());
  ASSERT_TRUE(pager->sendAway(*map, {0.0, 0.0, 0.0}, 5.0).ok());  // every block beyond 5 m goes out
  ASSERT_GT(pager->counts().regions_out, 1u);
  ASSERT_TRUE(pager->sync().ok());
  const auto snap = ogf::persistence::encodeSnapshot(7, 42, ogf::filter::encodeMap(*map), pager->files());
  std::ofstream(dir / "snapshot.ogfs", std::ios::binary)
      .write(reinterpret_cast<const char*>(snap.data()), static_cast<std::streamsize>(snap.size()));

  auto loaded = ogf::map_formats::loadOgfMap(dir / "snapshot.ogfs");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded->map.checksum(), whole) << "the pages' regions are part of the map";

  fs::remove(dir / "pages" / pager->files().front());
  auto partial = ogf::map_formats::loadOgfMap(dir / "snapshot.ogfs");
  fs::remove_all(dir);
  ASSERT_FALSE(partial.ok()) << "a map with a region missing is never loaded";
  EXPECT_NE(partial.error().message.find(pager->files().front()), std::string::npos) << partial.error().message;
}

TEST(MapLoader, RefusesAFileThatIsNeitherNamingIt) {
  const auto path = scratch("junk.bin");
  std::ofstream(path) << "this is not a map";
  auto r = ogf::map_formats::loadOgfMap(path);
  fs::remove(path);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find(path.string()), std::string::npos) << r.error().message;
}

}  // namespace
