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

BandedOgf sampleMap(int dimensions, CovarianceStorage storage = CovarianceStorage::kBanded) {
  FilterConfig config;
  config.dimensions = dimensions;
  config.covariance = storage;
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

TEST(MapFile, RoundTripIsBitIdenticalIn2DAnd3DForBothStorages) {
  for (const CovarianceStorage storage : {CovarianceStorage::kBanded, CovarianceStorage::kCompact})
  for (int dims : {2, 3}) {
    const BandedOgf map = sampleMap(dims, storage);
    EXPECT_EQ(map.config().covariance, storage);
    const auto path = tempPath("ogf-map-roundtrip");
    ASSERT_TRUE(saveMapFile(map, path).ok());
    const auto loaded = loadMapFile(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->checksum(), map.checksum());
    EXPECT_EQ(loaded->blockKeys(), map.blockKeys());
    EXPECT_EQ(*loaded->config().taperSupport, *map.config().taperSupport);
    EXPECT_EQ(loaded->config().covariance, storage);
    // No temporary file left behind.
    for (const auto& entry : std::filesystem::directory_iterator(path.parent_path())) {
      EXPECT_EQ(entry.path().string().find(path.filename().string() + ".tmp"), std::string::npos);
    }
    std::filesystem::remove(path);
  }
}

TEST(MapFile, LoadedMapKeepsFilteringLikeTheOriginal) {
  for (const CovarianceStorage storage : {CovarianceStorage::kBanded, CovarianceStorage::kCompact}) {
    BandedOgf map = sampleMap(3, storage);
    auto loaded = decodeMap(encodeMap(map));
    ASSERT_TRUE(loaded.ok());
    const std::vector<Measurement> more = {{{1, 1, 1}, 1}, {{2, 1, 1}, -1}, {{40, 0, 0}, 1}};
    map.update(more);
    loaded->update(more);
    EXPECT_EQ(loaded->checksum(), map.checksum()) << toString(storage);
  }
}

// encodedMapBytes (what an export's free-space check asks for) is exactly what encodeMap writes.
TEST(MapFile, EncodedMapBytesIsTheEncodingsSize) {
  for (const CovarianceStorage storage : {CovarianceStorage::kBanded, CovarianceStorage::kCompact})
    for (int dims : {2, 3}) {
      const BandedOgf map = sampleMap(dims, storage);
      EXPECT_EQ(encodedMapBytes(map, map.allocatedCells()), encodeMap(map).size()) << toString(storage) << " " << dims << "-D";
    }
}

// A compact map file holds a mean and a variance per cell: about a ninth of a banded one's blocks.
TEST(MapFile, CompactFilesHoldMeanAndVarianceOnly) {
  const BandedOgf banded = sampleMap(3, CovarianceStorage::kBanded);
  const BandedOgf compact = sampleMap(3, CovarianceStorage::kCompact);
  ASSERT_EQ(banded.blockKeys(), compact.blockKeys());
  const auto perBlock = [](const BandedOgf& m) {
    return static_cast<double>(encodeMap(m).size() - kMapFilePayloadAt) / static_cast<double>(m.blockKeys().size());
  };
  EXPECT_EQ(compact.floatsPerBlock(), 2U * compact.cellsPerBlock());
  EXPECT_NEAR(perBlock(compact), 12.0 + 512.0 * (2 * 4 + 1), 0.5);
  EXPECT_LT(perBlock(compact) * 5.0, perBlock(banded));
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
// The bytes an older version would have written for `map`: version 2 lacks the occupied priority and the
// release count (8 bytes at [96, 104)) and every block's cell marks; version 1 also the free clamp (8 bytes
// at [88, 96)).
std::vector<std::uint8_t> olderVersion(const BandedOgf& map, std::uint32_t version) {
  std::vector<std::uint8_t> bytes = encodeMap(map);
  constexpr std::size_t kVersionAt = 8;
  std::memcpy(bytes.data() + kVersionAt, &version, sizeof version);
  const std::size_t floatBytes = map.floatsPerBlock() * sizeof(float);
  std::vector<std::uint8_t> payload;
  for (std::size_t at = kMapFilePayloadAt; at < bytes.size(); at += 12 + floatBytes + map.cellsPerBlock()) {
    payload.insert(payload.end(), bytes.begin() + static_cast<std::ptrdiff_t>(at),
                   bytes.begin() + static_cast<std::ptrdiff_t>(at + 12 + floatBytes));
  }
  bytes.resize(kMapFilePayloadAt);
  bytes.insert(bytes.end(), payload.begin(), payload.end());
  MapChecksum payloadSum;
  payloadSum.add(std::as_bytes(std::span(payload)));
  const std::uint64_t p = payloadSum.value();
  std::memcpy(bytes.data() + kMapFilePayloadChecksumAt, &p, sizeof p);
  std::size_t removed = 8;
  bytes.erase(bytes.begin() + 96, bytes.begin() + 104);
  if (version == 1) {
    bytes.erase(bytes.begin() + 88, bytes.begin() + 96);
    removed += 8;
  }
  const std::size_t headerChecksumAt = kMapFileHeaderChecksumAt - removed;
  MapChecksum header;
  header.add(std::as_bytes(std::span(bytes).first(headerChecksumAt)));
  const std::uint64_t h = header.value();
  std::memcpy(bytes.data() + headerChecksumAt, &h, sizeof h);
  return bytes;
}

TEST(MapFile, VersionOneAndTwoFilesAreReadWithoutCellMarks) {
  const BandedOgf map = sampleMap(3);
  for (const std::uint32_t version : {1U, 2U}) {
    const auto loaded = decodeMap(olderVersion(map, version));
    ASSERT_TRUE(loaded.ok()) << "version " << version << ": " << loaded.error().message;
    EXPECT_EQ(loaded->config().freeClampZ, version == 1 ? 0.0 : map.config().freeClampZ);
    EXPECT_EQ(loaded->config().clampZ, map.config().clampZ);
    // Maps of those versions filtered every measurement.
    EXPECT_EQ(loaded->config().occupiedPriority, OccupiedPriority::kScan);
    EXPECT_EQ(loaded->blockKeys(), map.blockKeys());
    for (const CellKey& key : map.blockKeys()) {
      const auto a = map.blockValues(key);
      const auto b = loaded->blockValues(key);
      ASSERT_EQ(a.size(), b.size());
      EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
      for (const std::uint8_t mark : loaded->blockMarks(key)) {
        ASSERT_EQ(mark, 0);
      }
    }
  }
}

TEST(MapFile, CellMarksRoundTripAndAnUnknownVersionIsRefused) {
  const BandedOgf map = sampleMap(3);
  std::size_t hits = 0;
  for (const CellKey& key : map.blockKeys()) {
    for (const std::uint8_t mark : map.blockMarks(key)) {
      hits += (mark & CellMark::kHit) != 0 ? 1 : 0;
    }
  }
  ASSERT_GT(hits, 0U);  // the sample measures cells occupied
  std::vector<std::uint8_t> bytes = encodeMap(map);
  const auto loaded = decodeMap(bytes);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  for (const CellKey& key : map.blockKeys()) {
    const auto a = map.blockMarks(key);
    const auto b = loaded->blockMarks(key);
    ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end()));
  }
  const std::uint32_t four = kMapFileVersion + 1;
  std::memcpy(bytes.data() + 8, &four, sizeof four);
  const auto refused = decodeMap(bytes);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("version"), std::string::npos) << refused.error().message;
}

}  // namespace
}  // namespace ogf::filter
