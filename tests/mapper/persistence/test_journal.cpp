// The journal keeps every flushed record and, after a crash mid-write, every whole record before the torn
// tail; a resumed journal continues right after the last whole record.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <fstream>
#include <iterator>
#include <random>

#include "ogf/common/crc32.hpp"
#include "ogf/common/little_endian.hpp"
#include "ogf/persistence/journal.hpp"
#include "ogf/persistence/measurement_coding.hpp"

namespace {

using namespace ogf::persistence;
namespace fs = std::filesystem;

class JournalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ogf-journal-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::vector<ogf::Measurement> randomSet(std::mt19937& rng, int n) {
    std::uniform_int_distribution<int> c(-100000, 100000);
    std::vector<ogf::Measurement> out;
    for (int i = 0; i < n; ++i) out.push_back({{c(rng), c(rng), c(rng)}, static_cast<std::int8_t>(i % 3 == 0 ? 1 : -1)});
    return out;
  }
  // A journal header written by hand, for journals of older versions.
  static std::vector<std::byte> header(std::uint32_t version, std::int64_t map_id, std::int64_t base_seq) {
    std::vector<std::byte> file;
    for (char c : std::string("OGFJRNL1")) file.push_back(static_cast<std::byte>(c));
    ogf::putLittleEndian<std::uint32_t>(file, version);
    ogf::putLittleEndian<std::int64_t>(file, map_id);
    ogf::putLittleEndian<std::int64_t>(file, base_seq);
    ogf::putLittleEndian<std::uint32_t>(file, ogf::crc32(file.data(), file.size()));
    return file;
  }
  fs::path dir_;
};

TEST_F(JournalTest, FlushedRecordsReadBackExactly) {
  std::mt19937 rng(1);
  const auto path = dir_ / "journal";
  auto w = JournalWriter::create(path, 77, 10);
  ASSERT_TRUE(w.ok()) << w.error().message;
  std::vector<std::vector<ogf::Measurement>> sets;
  for (int i = 0; i < 20; ++i) {
    sets.push_back(randomSet(rng, i * 7));
    ASSERT_TRUE(w->append(11 + i, 1000 * i, sets.back()).ok());
    if (i % 3 == 0) {
      ASSERT_TRUE(w->flush().ok());
    }
  }
  ASSERT_TRUE(w->flush().ok());
  const auto r = readJournal(path);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->map_id, 77);
  EXPECT_EQ(r->base_seq, 10);
  EXPECT_FALSE(r->torn_tail_offset.has_value());
  ASSERT_EQ(r->records.size(), 20u);
  for (std::size_t i = 0; i < 20; ++i) {
    EXPECT_EQ(r->records[i].seq, static_cast<std::int64_t>(11 + i));
    EXPECT_EQ(r->records[i].utime, static_cast<std::int64_t>(1000 * i));
    EXPECT_EQ(r->records[i].measurements, sets[i]);
  }
}

TEST_F(JournalTest, UnflushedRecordsAreNotOnDisk) {
  const auto path = dir_ / "journal";
  auto w = JournalWriter::create(path, 1, 0);
  ASSERT_TRUE(w.ok());
  ASSERT_TRUE(w->append(1, 0, std::vector<ogf::Measurement>{{{1, 2, 3}, 1}}).ok());
  const auto r = readJournal(path);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->records.empty());
}

TEST_F(JournalTest, TornTailAtEveryCutKeepsEveryWholeRecordBeforeIt) {
  std::mt19937 rng(2);
  const auto path = dir_ / "journal";
  std::vector<std::uintmax_t> ends;  // file size after each record
  {
    auto w = JournalWriter::create(path, 1, 0);
    ASSERT_TRUE(w.ok());
    ends.push_back(fs::file_size(path));
    for (int i = 1; i <= 5; ++i) {
      ASSERT_TRUE(w->append(i, i, randomSet(rng, 4)).ok());
      ASSERT_TRUE(w->flush().ok());
      ends.push_back(fs::file_size(path));
    }
  }
  std::ifstream in(path, std::ios::binary);
  const std::string full((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (std::size_t cut = ends.front(); cut <= full.size(); ++cut) {
    const auto torn = dir_ / "torn";
    std::ofstream(torn, std::ios::binary).write(full.data(), static_cast<std::streamsize>(cut));
    const auto r = readJournal(torn);
    ASSERT_TRUE(r.ok()) << "cut " << cut;
    std::size_t whole = 0;
    while (whole + 1 < ends.size() && ends[whole + 1] <= cut) ++whole;
    EXPECT_EQ(r->records.size(), whole) << "cut " << cut;
    EXPECT_EQ(r->torn_tail_offset.has_value(), cut != ends[whole]) << "cut " << cut;
  }
}

TEST_F(JournalTest, CorruptByteLosesOnlyThatRecord) {
  std::mt19937 rng(3);
  const auto path = dir_ / "journal";
  std::uintmax_t second_record = 0, third_record = 0;
  {
    auto w = JournalWriter::create(path, 1, 0);
    ASSERT_TRUE(w.ok());
    for (int i = 1; i <= 3; ++i) {
      ASSERT_TRUE(w->append(i, i, randomSet(rng, 10)).ok());
      ASSERT_TRUE(w->flush().ok());
      if (i == 1) second_record = fs::file_size(path);
      if (i == 2) third_record = fs::file_size(path);
    }
  }
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(second_record + 30));
    f.put('\x5a');
  }
  const auto r = readJournal(path);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->records.size(), 2u);
  EXPECT_EQ(r->records[0].seq, 1);
  EXPECT_EQ(r->records[1].seq, 3);
  EXPECT_FALSE(r->torn_tail_offset.has_value());
  ASSERT_EQ(r->damaged.size(), 1u);
  EXPECT_EQ(r->damaged[0].offset, second_record);
  EXPECT_EQ(r->damaged[0].length, third_record - second_record);
  EXPECT_EQ(r->damaged[0].reason, "record checksum mismatch");
}

// Every byte of a small journal flipped in turn: the records read are all but the one the byte falls in
// (all of them when it falls in the header, which is then reported damaged).
TEST_F(JournalTest, FlippingAnyByteLosesAtMostTheRecordItFallsIn) {
  std::mt19937 rng(5);
  const auto path = dir_ / "journal";
  std::vector<std::uintmax_t> ends;  // end of the header, then of each record
  {
    auto w = JournalWriter::create(path, 9, 0);
    ASSERT_TRUE(w.ok());
    ends.push_back(fs::file_size(path));
    for (int i = 1; i <= 5; ++i) {
      ASSERT_TRUE(w->append(i, i * 100, randomSet(rng, 4)).ok());
      ASSERT_TRUE(w->flush().ok());
      ends.push_back(fs::file_size(path));
    }
  }
  std::ifstream in(path, std::ios::binary);
  const std::vector<char> original((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto damaged = dir_ / "damaged";
  for (std::size_t at = 0; at < original.size(); ++at) {
    for (const char mask : {'\xff', '\x01'}) {
      std::vector<char> bytes = original;
      bytes[at] = static_cast<char>(bytes[at] ^ mask);
      std::ofstream(damaged, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      const auto r = readJournal(damaged);
      ASSERT_TRUE(r.ok()) << "byte " << at << ": " << r.error().message;
      int hit = 0;  // the record the byte falls in, 0 for the header
      while (at >= ends[static_cast<std::size_t>(hit)]) ++hit;
      std::vector<std::int64_t> want;
      for (int i = 1; i <= 5; ++i)
        if (i != hit) want.push_back(i);
      std::vector<std::int64_t> got;
      for (const auto& rec : r->records) got.push_back(rec.seq);
      EXPECT_EQ(got, want) << "byte " << at << " mask " << int(mask);
      EXPECT_EQ(!r->header_damage.empty(), hit == 0) << "byte " << at;
      if (hit != 0 && hit != 5) {
        ASSERT_EQ(r->damaged.size(), 1u) << "byte " << at;
        EXPECT_EQ(r->damaged[0].offset, ends[static_cast<std::size_t>(hit - 1)]);
      }
      if (hit == 5) {
        EXPECT_EQ(r->torn_tail_offset, ends[4]) << "damage in the last record is a torn tail";
      }
      for (const auto& rec : r->records)
        EXPECT_EQ(rec.utime, rec.seq * 100) << "byte " << at;
    }
  }
}

TEST_F(JournalTest, ResumeCutsTheTornTailAndContinues) {
  std::mt19937 rng(4);
  const auto path = dir_ / "journal";
  {
    auto w = JournalWriter::create(path, 5, 100);
    ASSERT_TRUE(w.ok());
    ASSERT_TRUE(w->append(101, 0, randomSet(rng, 3)).ok());
    ASSERT_TRUE(w->append(102, 0, randomSet(rng, 3)).ok());
    ASSERT_TRUE(w->flush().ok());
  }
  fs::resize_file(path, fs::file_size(path) - 5);  // the crash tore record 102
  auto contents = readJournal(path);
  ASSERT_TRUE(contents.ok());
  ASSERT_EQ(contents->records.size(), 1u);
  auto w = JournalWriter::resume(path, *contents);
  ASSERT_TRUE(w.ok()) << w.error().message;
  EXPECT_EQ(w->lastSeq(), 101);
  EXPECT_FALSE(w->append(101, 0, randomSet(rng, 1)).ok());  // sequence must increase
  const auto again = randomSet(rng, 6);
  ASSERT_TRUE(w->append(102, 0, again).ok());
  ASSERT_TRUE(w->flush().ok());
  const auto r = readJournal(path);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r->torn_tail_offset.has_value());
  ASSERT_EQ(r->records.size(), 2u);
  EXPECT_EQ(r->records[1].measurements, again);
}

TEST_F(JournalTest, DamagedHeaderOrMissingFileIsAnErrorNamingThePath) {
  const auto missing = readJournal(dir_ / "nope");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("nope"), std::string::npos);
  const auto path = dir_ / "journal";
  ASSERT_TRUE(JournalWriter::create(path, 1, 0).ok());
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(13);
    f.put('\x01');
  }
  const auto r = readJournal(path);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("header checksum"), std::string::npos);
}

// The record coding gives back any set exactly: keys anywhere in int32, any y, in any order.
TEST_F(JournalTest, MeasurementCodingRoundTripsAnySetExactly) {
  std::mt19937 rng(11);
  constexpr std::int32_t kLow = std::numeric_limits<std::int32_t>::min();
  constexpr std::int32_t kHigh = std::numeric_limits<std::int32_t>::max();
  std::vector<std::vector<ogf::Measurement>> sets = {
      {},
      {{{kLow, kHigh, kLow}, 1}, {{kHigh, kLow, kHigh}, -1}, {{0, 0, 0}, 0}, {{0, 0, 1}, -128}, {{0, 1, -127}, 127}},
      randomSet(rng, 500),
  };
  std::uniform_int_distribution<int> any(kLow, kHigh), small(-3, 3), value(-128, 127);
  std::vector<ogf::Measurement> walk;  // small steps: every form, y mostly ±1
  ogf::CellKey at{0, 0, 0};
  for (int i = 0; i < 5000; ++i) {
    at = at + ogf::CellKey{small(rng) == 0 ? small(rng) : 0, small(rng) > 1 ? small(rng) * 20 : 0,
                           small(rng) * (i % 2 == 0 ? 30 : 1)};
    walk.push_back({at, static_cast<std::int8_t>(i % 97 == 0 ? value(rng) : (i % 3 == 0 ? 1 : -1))});
  }
  sets.push_back(walk);
  std::vector<ogf::Measurement> wide;
  for (int i = 0; i < 500; ++i) wide.push_back({{any(rng), any(rng), any(rng)}, static_cast<std::int8_t>(value(rng))});
  sets.push_back(wide);
  for (const auto& set : sets) {
    std::vector<std::byte> bytes;
    encodeMeasurements(set, bytes);
    EXPECT_LE(bytes.size(), set.size() * kMaxCodedMeasurement);
    std::vector<ogf::Measurement> back;
    ASSERT_TRUE(decodeMeasurements(bytes, set.size(), back));
    EXPECT_EQ(back, set);
    if (set.empty()) continue;
    // A count or a length that does not match is refused, never read past.
    EXPECT_FALSE(decodeMeasurements(bytes, set.size() + 1, back));
    EXPECT_FALSE(decodeMeasurements(bytes, set.size() - 1, back));
    EXPECT_FALSE(decodeMeasurements(std::span(bytes).first(bytes.size() - 1), set.size(), back));
  }
  std::vector<ogf::Measurement> back;
  for (const unsigned tag : {0xC3U, 0xC4U, 0xDFU}) {
    const std::vector<std::byte> bad{static_cast<std::byte>(tag), std::byte{0}, std::byte{0}, std::byte{0}};
    EXPECT_FALSE(decodeMeasurements(bad, 1, back)) << tag;
  }
  // Form D (version 3 only): 0xE0 | (dx + 8) << 1 | o, then (dy + 8) << 4 | (dz + 8).
  const std::vector<std::byte> formD{std::byte{0xE0 | (3 + 8) << 1 | 1}, std::byte{(-8 + 8) << 4 | (7 + 8)},
                                     std::byte{0xE0 | (-8 + 8) << 1}, std::byte{(7 + 8) << 4 | (-1 + 8)}};
  ASSERT_TRUE(decodeMeasurements(formD, 2, back));
  EXPECT_EQ(back, (std::vector<ogf::Measurement>{{{3, -8, 7}, 1}, {{-5, -1, 6}, -1}}));
  EXPECT_FALSE(decodeMeasurements(formD, 2, back, CodingVersion::k2));
  EXPECT_FALSE(decodeMeasurements(std::span(formD).first(3), 2, back));  // the second byte of form D missing
  // A difference that leaves int32: x = INT32_MAX + 1.
  std::vector<std::byte> beyond;
  encodeMeasurements(std::vector<ogf::Measurement>{{{kHigh, 0, 0}, 1}}, beyond);
  beyond.push_back(std::byte{0xC1});
  beyond.push_back(std::byte{2});  // zigzag(+1)
  beyond.push_back(std::byte{0});
  beyond.push_back(std::byte{0});
  EXPECT_FALSE(decodeMeasurements(beyond, 2, back));
}

// A scan's set comes brick by brick: the coding takes a small part of the 13 bytes a measurement of the
// fixed form took. Cells of a few rays' worth of shells and columns, in the order MeasurementSet gives them.
TEST_F(JournalTest, ScanLikeSetsTakeUnderTwoBytesAMeasurement) {
  std::mt19937 rng(12);
  std::bernoulli_distribution keep(0.35);
  std::vector<ogf::Measurement> set;
  for (int x = -150; x <= 150; ++x) {
    for (int y = -150; y <= 150; ++y) {
      const int r2 = x * x + y * y;
      if (r2 > 150 * 150 || !keep(rng)) continue;
      const int top = r2 < 30 * 30 ? 8 : 2;  // tall columns near the sensor, a thin layer far away
      for (int z = -2; z < top; ++z) set.push_back({{x, y, z}, static_cast<std::int8_t>(z == -2 ? 1 : -1)});
    }
  }
  // Bricks of 8 x 8 x 8 cells in key order, each brick's cells in key order.
  const auto brick = [](const ogf::CellKey& k) { return ogf::CellKey{k.x >> 3, k.y >> 3, k.z >> 3}; };
  std::sort(set.begin(), set.end(), [&](const auto& a, const auto& b) {
    return brick(a.key) == brick(b.key) ? a.key < b.key : brick(a.key) < brick(b.key);
  });
  std::vector<std::byte> bytes;
  encodeMeasurements(set, bytes);
  const double per = static_cast<double>(bytes.size()) / static_cast<double>(set.size());
  EXPECT_LT(per, 2.0) << set.size() << " measurements";

  std::vector<ogf::Measurement> back;
  ASSERT_TRUE(decodeMeasurements(bytes, set.size(), back));
  EXPECT_EQ(back, set);
}

// A journal written in the fixed form (version 1) is read, resumed and continued in the coded form.
TEST_F(JournalTest, VersionOneJournalIsReadAndContinued) {
  const auto path = dir_ / "journal";
  const std::vector<ogf::Measurement> first{{{1, 2, 3}, 1}, {{-4, 5, -6}, -1}};
  const std::vector<ogf::Measurement> second{{{7, 8, 9}, -1}};
  {
    std::vector<std::byte> file = header(1, 55, 4);
    std::int64_t seq = 5;
    for (const auto* set : {&first, &second}) {
      const std::size_t start = file.size();
      ogf::putLittleEndian<std::uint32_t>(file, 0x4352524A);
      ogf::putLittleEndian<std::uint32_t>(file, static_cast<std::uint32_t>(set->size()));
      ogf::putLittleEndian<std::int64_t>(file, seq++);
      ogf::putLittleEndian<std::int64_t>(file, 1000);
      for (const auto& m : *set) {
        ogf::putLittleEndian<std::int32_t>(file, m.key.x);
        ogf::putLittleEndian<std::int32_t>(file, m.key.y);
        ogf::putLittleEndian<std::int32_t>(file, m.key.z);
        ogf::putLittleEndian<std::int8_t>(file, m.y);
      }
      ogf::putLittleEndian<std::uint32_t>(file, ogf::crc32(file.data() + start, file.size() - start));
    }
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(file.data()),
                                                static_cast<std::streamsize>(file.size()));
  }
  auto r = readJournal(path);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->header_damage.empty()) << r->header_damage;
  EXPECT_EQ(r->map_id, 55);
  EXPECT_EQ(r->base_seq, 4);
  ASSERT_EQ(r->records.size(), 2u);
  EXPECT_EQ(r->records[0].measurements, first);
  EXPECT_EQ(r->records[1].measurements, second);
  EXPECT_EQ(r->records[1].offset, 32u + 24u + 2u * 13u + 4u);
  auto w = JournalWriter::resume(path, *r);
  ASSERT_TRUE(w.ok()) << w.error().message;
  ASSERT_TRUE(w->append(7, 2000, first).ok());
  ASSERT_TRUE(w->flush().ok());
  auto again = readJournal(path);
  ASSERT_TRUE(again.ok());
  ASSERT_EQ(again->records.size(), 3u);
  EXPECT_EQ(again->records[2].seq, 7);
  EXPECT_EQ(again->records[2].measurements, first);
  EXPECT_TRUE(again->damaged.empty());
}

// Records of coding version 2 ("JRC2", no form D) are still read; form D inside one is damage, not a step.
TEST_F(JournalTest, CodingVersionTwoRecordsAreReadAndRefuseFormD) {
  const auto path = dir_ / "journal";
  // {1, 2, 3} by form C, {1, 2, 4} by form A; then a record whose only measurement is form D.
  const std::vector<std::byte> version2{std::byte{0xC1}, std::byte{2}, std::byte{4}, std::byte{6},
                                        std::byte{0}};
  const std::vector<std::byte> formD{std::byte{0xE0 | (1 + 8) << 1 | 1}, std::byte{8 << 4 | 8}};
  const std::vector<ogf::Measurement> set{{{1, 2, 3}, 1}, {{1, 2, 4}, -1}};
  {
    std::vector<std::byte> file = header(2, 9, 0);
    std::int64_t seq = 1;
    for (const auto& [coding, count] :
         {std::pair{version2, 2U}, std::pair{formD, 1U}, std::pair{version2, 2U}}) {
      const std::size_t start = file.size();
      ogf::putLittleEndian<std::uint32_t>(file, 0x3243524A);  // "JRC2"
      ogf::putLittleEndian<std::uint32_t>(file, count);
      ogf::putLittleEndian<std::int64_t>(file, seq++);
      ogf::putLittleEndian<std::int64_t>(file, 1000);
      ogf::putLittleEndian<std::uint32_t>(file, static_cast<std::uint32_t>(coding.size()));
      file.insert(file.end(), coding.begin(), coding.end());
      ogf::putLittleEndian<std::uint32_t>(file, ogf::crc32(file.data() + start, file.size() - start));
    }
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
  }
  auto r = readJournal(path);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->records.size(), 2u);
  EXPECT_EQ(r->records[0].seq, 1);
  EXPECT_EQ(r->records[0].measurements, set);
  EXPECT_EQ(r->records[1].seq, 3);
  EXPECT_EQ(r->records[1].measurements, set);
  ASSERT_EQ(r->damaged.size(), 1u);
}

// A record whose checksum holds but whose measurements are not a coding (written by no ogf) is damage:
// skipped and reported, the records around it kept.
TEST_F(JournalTest, RecordWithAChecksumButNoValidCodingIsSkippedAsDamaged) {
  const auto path = dir_ / "journal";
  const std::vector<ogf::Measurement> set{{{1, 1, 1}, 1}};
  std::uintmax_t second = 0;
  {
    auto w = JournalWriter::create(path, 1, 0);
    ASSERT_TRUE(w.ok());
    ASSERT_TRUE(w->append(1, 0, set).ok());
    ASSERT_TRUE(w->flush().ok());
    second = fs::file_size(path);
    ASSERT_TRUE(w->append(3, 0, set).ok());
    ASSERT_TRUE(w->flush().ok());
  }
  std::vector<char> file;
  {
    std::ifstream in(path, std::ios::binary);
    file.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::vector<std::byte> rec;  // seq 2 between them
  ogf::putLittleEndian<std::uint32_t>(rec, 0x3243524A);
  ogf::putLittleEndian<std::uint32_t>(rec, 1);
  ogf::putLittleEndian<std::int64_t>(rec, 2);
  ogf::putLittleEndian<std::int64_t>(rec, 0);
  ogf::putLittleEndian<std::uint32_t>(rec, 1);
  rec.push_back(std::byte{0xFF});  // no such form
  ogf::putLittleEndian<std::uint32_t>(rec, ogf::crc32(rec.data(), rec.size()));
  const auto* raw = reinterpret_cast<const char*>(rec.data());
  file.insert(file.begin() + static_cast<std::ptrdiff_t>(second), raw, raw + rec.size());
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(file.data(), static_cast<std::streamsize>(file.size()));
  const auto r = readJournal(path);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->records.size(), 2u);
  EXPECT_EQ(r->records[1].seq, 3);
  EXPECT_EQ(r->records[1].offset, second + rec.size());
  ASSERT_EQ(r->damaged.size(), 1u);
  EXPECT_EQ(r->damaged[0].offset, second);
  EXPECT_EQ(r->damaged[0].length, rec.size());
  EXPECT_EQ(r->damaged[0].reason, "measurements not in the journal's coding");
}

}  // namespace
