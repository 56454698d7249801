// The journal keeps every flushed record and, after a crash mid-write, every whole record before the torn
// tail; a resumed journal continues right after the last whole record.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "ogf/persistence/journal.hpp"

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

}  // namespace
