// The map file round-trips bit for bit, is written atomically, and refuses truncated or corrupted bytes
// with an error naming the field, never half-loading.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/map_checksum.hpp"
#include "ogf/filter/map_file.hpp"

namespace ogf::filter {
namespace {

BandedOgf sampleMap(int dimensions) {
  FilterConfig config;
  config.dimensions = dimensions;
  auto map = BandedOgf::create(config);
  EXPECT_TRUE(map.ok());
  std::mt19937 rng(5);
  std::set<CellKey> seen;
  std::vector<Measurement> batch;
  while (batch.size() < 400) {
    const CellKey k{static_cast<int>(rng() % 30U) - 15, static_cast<int>(rng() % 30U) - 15,
                    dimensions == 3 ? static_cast<int>(rng() % 6U) - 3 : 0};
    if (seen.insert(k).second) {
      batch.push_back({k, static_cast<std::int8_t>(k.x > 3 ? 1 : -1)});
    }
  }
  map->update(batch);
  return std::move(map).value();
}

std::filesystem::path tempPath(const char* name) {
  return std::filesystem::temp_directory_path() / (std::string(name) + "-" + std::to_string(::getpid()));
}

TEST(MapFile, RoundTripIsBitIdenticalIn2DAnd3D) {
  for (int dims : {2, 3}) {
    const BandedOgf map = sampleMap(dims);
    const auto path = tempPath("ogf-map-roundtrip");
    ASSERT_TRUE(saveMapFile(map, path).ok());
    const auto loaded = loadMapFile(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->checksum(), map.checksum());
    EXPECT_EQ(loaded->blockKeys(), map.blockKeys());
    EXPECT_EQ(*loaded->config().taperSupport, *map.config().taperSupport);
    // No temporary file left behind.
    for (const auto& entry : std::filesystem::directory_iterator(path.parent_path())) {
      EXPECT_EQ(entry.path().string().find(path.filename().string() + ".tmp"), std::string::npos);
    }
    std::filesystem::remove(path);
  }
}

TEST(MapFile, LoadedMapKeepsFilteringLikeTheOriginal) {
  BandedOgf map = sampleMap(3);
  auto loaded = decodeMap(encodeMap(map));
  ASSERT_TRUE(loaded.ok());
  const std::vector<Measurement> more = {{{1, 1, 1}, 1}, {{2, 1, 1}, -1}, {{40, 0, 0}, 1}};
  map.update(more);
  loaded->update(more);
  EXPECT_EQ(loaded->checksum(), map.checksum());
}

TEST(MapFile, EveryTruncationIsRefused) {
  const std::vector<std::uint8_t> bytes = encodeMap(sampleMap(2));
  for (std::size_t len = 0; len < bytes.size(); len += 1 + len / 7) {
    const auto r = decodeMap(std::span<const std::uint8_t>(bytes.data(), len), "cut.map");
    ASSERT_FALSE(r.ok()) << "accepted " << len << " of " << bytes.size() << " bytes";
    EXPECT_NE(r.error().message.find("cut.map: offset"), std::string::npos) << r.error().message;
  }
}

TEST(MapFile, FlippedBitsAreRefusedWithTheFieldNamed) {
  const std::vector<std::uint8_t> bytes = encodeMap(sampleMap(3));
  std::mt19937 rng(9);
  for (int trial = 0; trial < 60; ++trial) {
    std::vector<std::uint8_t> bad = bytes;
    const std::size_t at = rng() % bad.size();
    bad[at] ^= static_cast<std::uint8_t>(1U << (rng() % 8U));
    const auto r = decodeMap(bad, "bad.map");
    ASSERT_FALSE(r.ok()) << "accepted a flip at byte " << at;
  }
  std::vector<std::uint8_t> magic = bytes;
  magic[0] = 'X';
  EXPECT_NE(decodeMap(magic).error().message.find("magic"), std::string::npos);
  std::vector<std::uint8_t> payload = bytes;
  payload.back() ^= 1U;
  EXPECT_NE(decodeMap(payload).error().message.find("payload checksum"), std::string::npos);
  std::vector<std::uint8_t> trailing = bytes;
  trailing.push_back(0);
  EXPECT_NE(decodeMap(trailing).error().message.find("trailing"), std::string::npos);
}

TEST(MapFile, MissingFileIsAnErrorNamingThePath) {
  const auto r = loadMapFile("/nonexistent/dir/x.map");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("/nonexistent/dir/x.map"), std::string::npos);
}

TEST(MapFile, SaveIntoAMissingDirectoryFailsCleanly) {
  const auto st = saveMapFile(sampleMap(2), "/nonexistent/dir/x.map");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("/nonexistent/dir/x.map"), std::string::npos);
}

}  // namespace
}  // namespace ogf::filter

namespace ogf::filter {
namespace {

TEST(MapFile, LayoutConstantsMatchTheEncoder) {
  const std::vector<std::uint8_t> bytes = encodeMap(sampleMap(2));
  const auto sum = [](std::span<const std::uint8_t> b) {
    MapChecksum c;
    c.add(std::as_bytes(b));
    return c.value();
  };
  std::uint64_t payload = 0;
  std::uint64_t header = 0;
  std::memcpy(&payload, bytes.data() + kMapFilePayloadChecksumAt, 8);
  std::memcpy(&header, bytes.data() + kMapFileHeaderChecksumAt, 8);
  EXPECT_EQ(payload, sum(std::span(bytes).subspan(kMapFilePayloadAt)));
  EXPECT_EQ(header, sum(std::span(bytes).first(kMapFileHeaderChecksumAt)));
}

}  // namespace
}  // namespace ogf::filter

namespace ogf::filter {
namespace {

TEST(MapFile, ClampsRoundTrip) {
  FilterConfig config;
  config.clampZ = 2.5;
  config.freeClampZ = 1.25;
  auto map = BandedOgf::create(config);
  ASSERT_TRUE(map.ok());
  map->update(std::vector<Measurement>{{{0, 0, 0}, 1}});
  const auto loaded = decodeMap(encodeMap(*map));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded->config().clampZ, 2.5);
  EXPECT_EQ(loaded->config().freeClampZ, 1.25);
}

// A version 1 file (written before the free clamp existed): the same header without its 8 bytes, both
// checksums recomputed. It loads, its free measurements keep using clampZ (freeClampZ 0), and its blocks
// are the same.
TEST(MapFile, VersionOneFilesAreStillRead) {
  const BandedOgf map = sampleMap(3);
  std::vector<std::uint8_t> bytes = encodeMap(map);
  constexpr std::size_t kVersionAt = 8;
  constexpr std::size_t kFreeClampAt = 88;  // after the clamp at [80, 88)
  const std::uint32_t one = 1;
  std::memcpy(bytes.data() + kVersionAt, &one, sizeof one);
  bytes.erase(bytes.begin() + kFreeClampAt, bytes.begin() + kFreeClampAt + 8);
  MapChecksum header;
  header.add(std::as_bytes(std::span(bytes).first(kMapFileHeaderChecksumAt - 8)));
  const std::uint64_t sum = header.value();
  std::memcpy(bytes.data() + kMapFileHeaderChecksumAt - 8, &sum, sizeof sum);

  const auto loaded = decodeMap(bytes);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded->config().freeClampZ, 0.0);
  EXPECT_EQ(loaded->config().clampZ, map.config().clampZ);
  EXPECT_EQ(loaded->blockKeys(), map.blockKeys());
  for (const CellKey& key : map.blockKeys()) {
    const auto a = map.blockValues(key);
    const auto b = loaded->blockValues(key);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
  }
  // An unknown version is refused, naming the field.
  const std::uint32_t three = 3;
  std::memcpy(bytes.data() + kVersionAt, &three, sizeof three);
  const auto refused = decodeMap(bytes);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("version"), std::string::npos) << refused.error().message;
}

}  // namespace
}  // namespace ogf::filter
