// Recovery from the state directory: snapshot + the journal after it, whatever instant the previous run
// stopped at; a damaged snapshot is refused rather than half-loaded, and one that cannot be read is left
// where it is.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "ogf/persistence/state_directory.hpp"

namespace {

using namespace ogf::persistence;
namespace fs = std::filesystem;

class StateDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ogf-state-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::vector<ogf::Measurement> set(int i) {
    return {{{i, 0, 0}, 1}, {{i, 1, 0}, -1}};
  }
  fs::path dir_;
};

TEST_F(StateDirectoryTest, FreshDirectoryStartsANewMap) {
  auto sd = StateDirectory::open(dir_);
  ASSERT_TRUE(sd.ok()) << sd.error().message;
  auto r = sd->recover(42);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->map_id, 42);
  EXPECT_EQ(r->last_seq, 0);
  EXPECT_TRUE(r->replay.empty());
  EXPECT_TRUE(r->snapshot_map.empty());
}

TEST_F(StateDirectoryTest, JournalAloneIsReplayedAfterARestart) {
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    for (int i = 1; i <= 3; ++i) ASSERT_TRUE(sd->journal(i, i * 10, set(i)).ok());
  }  // "killed" here: nothing else is written
  auto sd = StateDirectory::open(dir_);
  auto r = sd->recover(99);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->map_id, 7);  // the map survives the restart
  ASSERT_EQ(r->replay.size(), 3u);
  EXPECT_EQ(r->replay[2].seq, 3);
  EXPECT_EQ(r->replay[2].measurements, set(3));
  EXPECT_EQ(r->last_seq, 3);
  ASSERT_TRUE(sd->journal(4, 40, set(4)).ok());  // and appending continues the same journal
  auto again = StateDirectory::open(dir_)->recover(1);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->replay.size(), 4u);
}

TEST_F(StateDirectoryTest, SnapshotThenJournalReplaysOnlyWhatCameAfter) {
  const std::vector<std::uint8_t> map{1, 2, 3, 4, 5};
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    for (int i = 1; i <= 3; ++i) ASSERT_TRUE(sd->journal(i, 0, set(i)).ok());
    ASSERT_TRUE(sd->snapshot(3, map).ok());
    for (int i = 4; i <= 5; ++i) ASSERT_TRUE(sd->journal(i, 0, set(i)).ok());
  }
  auto r = StateDirectory::open(dir_)->recover(1);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->snapshot_seq, 3);
  EXPECT_EQ(r->snapshot_map, map);
  ASSERT_EQ(r->replay.size(), 2u);
  EXPECT_EQ(r->replay[0].seq, 4);
  EXPECT_EQ(r->last_seq, 5);
}

TEST_F(StateDirectoryTest, CrashBetweenSnapshotAndJournalResetSkipsRecordsTheSnapshotHolds) {
  // The old journal (records 1..5) is still there next to a snapshot at seq 3.
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    for (int i = 1; i <= 5; ++i) ASSERT_TRUE(sd->journal(i, 0, set(i)).ok());
  }
  const std::vector<std::uint8_t> map{9, 9};
  const auto snap = encodeSnapshot(7, 3, map);
  std::ofstream(dir_ / "snapshot.ogfs", std::ios::binary)
      .write(reinterpret_cast<const char*>(snap.data()), static_cast<std::streamsize>(snap.size()));
  auto sd = StateDirectory::open(dir_);
  auto r = sd->recover(1);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->replay.size(), 2u);
  EXPECT_EQ(r->replay[0].seq, 4);
  EXPECT_FALSE(r->notes.empty());
  // The directory was rewritten to snapshot + journal(4, 5), so a second recovery agrees.
  ASSERT_TRUE(sd->journal(6, 0, set(6)).ok());
  auto again = StateDirectory::open(dir_)->recover(1);
  ASSERT_TRUE(again.ok());
  ASSERT_EQ(again->replay.size(), 3u);
  EXPECT_EQ(again->replay.back().seq, 6);
}

TEST_F(StateDirectoryTest, DamagedSnapshotIsRefusedNamingTheFile) {
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    ASSERT_TRUE(sd->snapshot(1, std::vector<std::uint8_t>(100, 3)).ok());
  }
  fs::resize_file(dir_ / "snapshot.ogfs", 60);
  auto r = StateDirectory::open(dir_)->recover(1);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("snapshot.ogfs"), std::string::npos);
  EXPECT_EQ(r.error().kind, ogf::ErrorKind::input_damaged) << r.error().message;
  {
    std::fstream f(dir_ / "snapshot.ogfs", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(0);
    f.put('X');
  }
  const auto bad_magic = StateDirectory::open(dir_)->recover(1);
  ASSERT_FALSE(bad_magic.ok());
  EXPECT_EQ(bad_magic.error().kind, ogf::ErrorKind::input_damaged) << bad_magic.error().message;
}

std::vector<char> bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool anyDamagedDirectory(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind("damaged-", 0) == 0) return true;
  return false;
}

// Two generations (snapshots at seq 1 and 2, a record after each) for the unreadable-file tests.
void writeTwoGenerations(const fs::path& dir) {
  auto sd = StateDirectory::open(dir);
  ASSERT_TRUE(sd->recover(7).ok());
  ASSERT_TRUE(sd->journal(1, 1, std::vector<ogf::Measurement>{{{1, 0, 0}, 1}}).ok());
  ASSERT_TRUE(sd->snapshot(1, std::vector<std::uint8_t>(80, 1)).ok());
  ASSERT_TRUE(sd->journal(2, 2, std::vector<ogf::Measurement>{{{2, 0, 0}, 1}}).ok());
  ASSERT_TRUE(sd->snapshot(2, std::vector<std::uint8_t>(80, 2)).ok());
  ASSERT_TRUE(sd->journal(3, 3, std::vector<ogf::Measurement>{{{3, 0, 0}, 1}}).ok());
}

// A snapshot that cannot be read (here a directory in its place: EISDIR, which root meets too) is not
// known to be damaged: recovery fails with the system's reason, of kind io, and neither falls back to the
// previous generation nor copies or moves anything, so the map is there once the file can be read.
TEST_F(StateDirectoryTest, SnapshotThatCannotBeReadIsAnIoErrorAndNothingIsSetAsideOrFallenBackFrom) {
  ASSERT_NO_FATAL_FAILURE(writeTwoGenerations(dir_));
  fs::rename(dir_ / "snapshot.ogfs", dir_ / "snapshot.kept");
  fs::create_directory(dir_ / "snapshot.ogfs");
  const auto previous = bytesOf(dir_ / "snapshot.prev.ogfs");
  const auto journal = bytesOf(dir_ / "journal.ogfj");
  auto sd = StateDirectory::open(dir_);
  ASSERT_TRUE(sd.ok()) << sd.error().message;
  auto r = sd->recover(1, 5000);
  ASSERT_FALSE(r.ok()) << "restored from the previous generation instead of failing";
  EXPECT_EQ(r.error().kind, ogf::ErrorKind::io) << r.error().message;
  EXPECT_NE(r.error().message.find((dir_ / "snapshot.ogfs").string()), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find(std::strerror(EISDIR)), std::string::npos) << r.error().message;
  EXPECT_FALSE(anyDamagedDirectory(dir_)) << "an unreadable snapshot is not damage";
  EXPECT_TRUE(fs::is_directory(dir_ / "snapshot.ogfs"));
  EXPECT_EQ(bytesOf(dir_ / "snapshot.prev.ogfs"), previous);
  EXPECT_EQ(bytesOf(dir_ / "journal.ogfj"), journal);
  fs::remove(dir_ / "snapshot.ogfs");
  fs::rename(dir_ / "snapshot.kept", dir_ / "snapshot.ogfs");
  auto again = StateDirectory::open(dir_)->recover(1);
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(again->snapshot_seq, 2);
  EXPECT_EQ(again->last_seq, 3) << "the whole map, once the snapshot can be read";
}

// The same for a journal: an unreadable one is an io error, not a journal to start anew (which would lose
// its records).
TEST_F(StateDirectoryTest, JournalThatCannotBeReadIsAnIoErrorNotAJournalStartedAnew) {
  ASSERT_NO_FATAL_FAILURE(writeTwoGenerations(dir_));
  fs::rename(dir_ / "journal.ogfj", dir_ / "journal.kept");
  fs::create_directory(dir_ / "journal.ogfj");
  auto r = StateDirectory::open(dir_)->recover(1, 5000);
  ASSERT_FALSE(r.ok()) << "the journal was started anew";
  EXPECT_EQ(r.error().kind, ogf::ErrorKind::io) << r.error().message;
  EXPECT_NE(r.error().message.find((dir_ / "journal.ogfj").string()), std::string::npos) << r.error().message;
  EXPECT_FALSE(anyDamagedDirectory(dir_));
  EXPECT_TRUE(fs::is_directory(dir_ / "journal.ogfj"));
  fs::remove(dir_ / "journal.ogfj");
  fs::rename(dir_ / "journal.kept", dir_ / "journal.ogfj");
  auto again = StateDirectory::open(dir_)->recover(1);
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(again->last_seq, 3);
}

TEST_F(StateDirectoryTest, AfterASnapshotJournalErrorsNameTheJournalThatIsThere) {
  auto sd = StateDirectory::open(dir_);
  ASSERT_TRUE(sd->recover(7).ok());
  ASSERT_TRUE(sd->journal(1, 0, set(1)).ok());
  // The snapshot starts the journal anew; seq 1 again is then refused, naming the journal.
  ASSERT_TRUE(sd->snapshot(1, std::vector<std::uint8_t>{1, 2, 3}).ok());
  const auto st = sd->journal(1, 0, set(1));
  ASSERT_FALSE(st.ok());
  const std::string& message = st.error().message;
  EXPECT_NE(message.find((dir_ / "journal.ogfj").string() + ":"), std::string::npos) << message;
  EXPECT_EQ(message.find(".new"), std::string::npos) << message;
}

TEST_F(StateDirectoryTest, UnusablePathIsAnErrorNamingIt) {
  std::ofstream(dir_.string() + "-file") << "x";  // a file where the directory should be
  auto sd = StateDirectory::open(fs::path(dir_.string() + "-file") / "state");
  ASSERT_FALSE(sd.ok());
  EXPECT_NE(sd.error().message.find("-file"), std::string::npos);
  EXPECT_EQ(sd.error().kind, ogf::ErrorKind::io) << sd.error().message;
  fs::remove(dir_.string() + "-file");
}

TEST_F(StateDirectoryTest, ReadGivesWhatRecoverWouldAndWritesNothing) {
  const std::vector<std::uint8_t> map{1, 2, 3};
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    for (int i = 1; i <= 2; ++i) ASSERT_TRUE(sd->journal(i, 0, set(i)).ok());
    ASSERT_TRUE(sd->snapshot(2, map).ok());
    ASSERT_TRUE(sd->journal(3, 0, set(3)).ok());
  }
  const auto journal_size = fs::file_size(dir_ / "journal.ogfj");
  const auto snapshot_time = fs::last_write_time(dir_ / "snapshot.ogfs");
  auto r = StateDirectory::read(dir_, 99);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->map_id, 7);
  EXPECT_EQ(r->snapshot_seq, 2);
  EXPECT_EQ(r->snapshot_map, map);
  ASSERT_EQ(r->replay.size(), 1u);
  EXPECT_EQ(r->replay[0].measurements, set(3));
  EXPECT_EQ(r->last_seq, 3);
  EXPECT_EQ(fs::file_size(dir_ / "journal.ogfj"), journal_size);
  EXPECT_EQ(fs::last_write_time(dir_ / "snapshot.ogfs"), snapshot_time);
  // A directory that does not exist reads as a new map, and is not created.
  auto none = StateDirectory::read(dir_ / "absent", 5);
  ASSERT_TRUE(none.ok());
  EXPECT_EQ(none->map_id, 5);
  EXPECT_FALSE(fs::exists(dir_ / "absent"));
}

// Every byte of the journal after a snapshot flipped in turn: recovery gives the snapshot and every record
// but the damaged one, keeps the damaged journal in damaged-<time>/, says so, and leaves a directory that
// recovers the same map cleanly.
TEST_F(StateDirectoryTest, FlippingAnyJournalByteLosesAtMostTheDamagedRecord) {
  const fs::path clean = dir_.string() + "-clean";
  fs::remove_all(clean);
  std::vector<std::uintmax_t> ends;
  {
    auto sd = StateDirectory::open(clean);
    ASSERT_TRUE(sd->recover(7).ok());
    ASSERT_TRUE(sd->journal(1, 0, set(1)).ok());
    ASSERT_TRUE(sd->snapshot(1, std::vector<std::uint8_t>(50, 1)).ok());
    ends.push_back(fs::file_size(clean / "journal.ogfj"));
    for (int i = 2; i <= 5; ++i) {
      ASSERT_TRUE(sd->journal(i, i, set(i)).ok());
      ends.push_back(fs::file_size(clean / "journal.ogfj"));
    }
  }
  std::ifstream in(clean / "journal.ogfj", std::ios::binary);
  const std::vector<char> original((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (std::size_t at = 0; at < original.size(); ++at) {
    fs::remove_all(dir_);
    fs::copy(clean, dir_, fs::copy_options::recursive);
    std::vector<char> bytes = original;
    bytes[at] = static_cast<char>(bytes[at] ^ 0x20);
    std::ofstream(dir_ / "journal.ogfj", std::ios::binary | std::ios::trunc)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    int hit = 0;  // 0: the header; i: the record of seq i + 1
    while (at >= ends[static_cast<std::size_t>(hit)]) ++hit;
    std::vector<std::int64_t> want;
    for (int seq = 2; seq <= 5; ++seq)
      if (seq != hit + 1) want.push_back(seq);
    for (int round = 0; round < 2; ++round) {  // the damaged directory, then the one recovery left
      auto r = StateDirectory::open(dir_)->recover(1, 1000 + round);
      ASSERT_TRUE(r.ok()) << "byte " << at << ": " << r.error().message;
      EXPECT_EQ(r->map_id, 7);
      EXPECT_EQ(r->snapshot_seq, 1);
      std::vector<std::int64_t> got;
      for (const auto& rec : r->replay) got.push_back(rec.seq);
      EXPECT_EQ(got, want) << "byte " << at << " round " << round;
      const bool reported = round == 0 && hit != 4;  // damage in the last record is a torn tail
      EXPECT_EQ(!r->damage.empty(), reported) << "byte " << at << " round " << round << ": " << r->damage;
      if (reported) {
        EXPECT_TRUE(fs::exists(dir_ / "damaged-1000" / "journal.ogfj")) << "byte " << at;
        EXPECT_NE(r->damage.find("journal.ogfj: offset"), std::string::npos) << r->damage;
      }
    }
  }
  fs::remove_all(clean);
}

TEST_F(StateDirectoryTest, DamagedNewestSnapshotFallsBackToThePreviousOneAndBothJournals) {
  const std::vector<std::uint8_t> first(80, 1), second(90, 2);
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    for (int i = 1; i <= 2; ++i) ASSERT_TRUE(sd->journal(i, i, set(i)).ok());
    ASSERT_TRUE(sd->snapshot(2, first).ok());
    for (int i = 3; i <= 4; ++i) ASSERT_TRUE(sd->journal(i, i, set(i)).ok());
    ASSERT_TRUE(sd->snapshot(4, second).ok());
    ASSERT_TRUE(sd->journal(5, 5, set(5)).ok());
  }
  const auto size = fs::file_size(dir_ / "snapshot.ogfs");
  fs::resize_file(dir_ / "snapshot.ogfs", size / 2);
  auto r = StateDirectory::open(dir_)->recover(1, 2000);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->map_id, 7);
  EXPECT_EQ(r->snapshot_seq, 2);
  EXPECT_EQ(r->snapshot_map, first);
  std::vector<std::int64_t> got;
  for (const auto& rec : r->replay) got.push_back(rec.seq);
  EXPECT_EQ(got, (std::vector<std::int64_t>{3, 4, 5}));
  EXPECT_EQ(r->last_seq, 5);
  EXPECT_NE(r->damage.find("snapshot.ogfs"), std::string::npos) << r->damage;
  EXPECT_EQ(fs::file_size(dir_ / "damaged-2000" / "snapshot.ogfs"), size / 2) << "the damaged snapshot is kept";
  // What recovery left recovers the same map without damage, and goes on.
  auto sd = StateDirectory::open(dir_);
  auto again = sd->recover(1, 3000);
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_TRUE(again->damage.empty()) << again->damage;
  EXPECT_EQ(again->snapshot_map, first);
  EXPECT_EQ(again->last_seq, 5);
  ASSERT_TRUE(sd->journal(6, 6, set(6)).ok());
  ASSERT_TRUE(sd->snapshot(6, second).ok());
  auto third = StateDirectory::open(dir_)->recover(1);
  ASSERT_TRUE(third.ok());
  EXPECT_EQ(third->snapshot_seq, 6);
  EXPECT_TRUE(third->replay.empty());
}

TEST_F(StateDirectoryTest, BothSnapshotGenerationsDamagedIsAnErrorAndEverythingCanBeSetAside) {
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    ASSERT_TRUE(sd->journal(1, 1, set(1)).ok());
    ASSERT_TRUE(sd->snapshot(1, std::vector<std::uint8_t>(80, 1)).ok());
    ASSERT_TRUE(sd->journal(2, 2, set(2)).ok());
    ASSERT_TRUE(sd->snapshot(2, std::vector<std::uint8_t>(80, 2)).ok());
  }
  fs::resize_file(dir_ / "snapshot.ogfs", 40);
  fs::resize_file(dir_ / "snapshot.prev.ogfs", 40);
  auto sd = StateDirectory::open(dir_);
  auto r = sd->recover(1);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("snapshot.ogfs"), std::string::npos);
  EXPECT_NE(r.error().message.find("snapshot.prev.ogfs"), std::string::npos);
  const auto aside = sd->setAside(4000);
  ASSERT_TRUE(aside.ok()) << aside.error().message;
  for (const char* f : {"snapshot.ogfs", "journal.ogfj", "snapshot.prev.ogfs", "journal.prev.ogfj"})
    EXPECT_TRUE(fs::exists(*aside / f)) << f;
  auto fresh = sd->recover(9);
  ASSERT_TRUE(fresh.ok());
  EXPECT_EQ(fresh->map_id, 9);
}

// A snapshot written while mapping goes on: journal.ogfj takes every record until the new journal is put in
// place, so a crash at each step of it restores every record, from the old snapshot or the new one.
TEST_F(StateDirectoryTest, SnapshotWrittenWhileMappingGoesOnLosesNoRecordAtAnyStep) {
  const std::vector<std::uint8_t> old_map(70, 1), new_map(90, 2);
  enum Step { kBegun, kFileWritten, kFinished };
  for (const Step crash_after : {kBegun, kFileWritten, kFinished}) {
    SCOPED_TRACE(static_cast<int>(crash_after));
    fs::remove_all(dir_);
    {
      auto sd = StateDirectory::open(dir_);
      ASSERT_TRUE(sd->recover(7).ok());
      ASSERT_TRUE(sd->journal(1, 1, set(1)).ok());
      ASSERT_TRUE(sd->snapshot(1, old_map).ok());
      for (int i = 2; i <= 3; ++i) ASSERT_TRUE(sd->journal(i, i, set(i)).ok());
      ASSERT_TRUE(sd->beginSnapshot(3).ok());
      EXPECT_TRUE(sd->snapshotBegun());
      ASSERT_TRUE(sd->journal(4, 4, set(4)).ok());  // mapped while the file is written
      if (crash_after >= kFileWritten) {
        ASSERT_TRUE(StateDirectory::writeSnapshotFile(sd->snapshotPath(), sd->mapId(), 3, new_map, {}).ok());
        ASSERT_TRUE(sd->journal(5, 5, set(5)).ok());
      }
      if (crash_after >= kFinished) {
        ASSERT_TRUE(sd->finishSnapshot({}).ok());
        EXPECT_FALSE(sd->snapshotBegun());
        EXPECT_FALSE(fs::exists(sd->nextJournalPath()));
        ASSERT_TRUE(sd->journal(6, 6, set(6)).ok());
      }
    }  // killed here
    auto sd = StateDirectory::open(dir_);
    auto r = sd->recover(99);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->damage.empty()) << r->damage;
    EXPECT_EQ(r->map_id, 7);
    const std::int64_t last = crash_after == kBegun ? 4 : (crash_after == kFileWritten ? 5 : 6);
    EXPECT_EQ(r->snapshot_seq, crash_after == kBegun ? 1 : 3);
    EXPECT_EQ(r->snapshot_map, crash_after == kBegun ? old_map : new_map);
    std::vector<std::int64_t> got, want;
    for (const auto& rec : r->replay) got.push_back(rec.seq);
    for (std::int64_t s = r->snapshot_seq + 1; s <= last; ++s) want.push_back(s);
    EXPECT_EQ(got, want);
    EXPECT_EQ(r->replay.back().measurements, set(static_cast<int>(last)));
    // The directory recovery leaves goes on: a record more, and a second recovery has it too.
    ASSERT_TRUE(sd->journal(last + 1, 0, set(static_cast<int>(last + 1))).ok());
    auto again = StateDirectory::open(dir_)->recover(99);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again->last_seq, last + 1);
  }
}

TEST_F(StateDirectoryTest, DamagedNewSnapshotWrittenWhileMappingFallsBackWithEveryRecord) {
  const std::vector<std::uint8_t> old_map(70, 1), new_map(90, 2);
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    ASSERT_TRUE(sd->journal(1, 1, set(1)).ok());
    ASSERT_TRUE(sd->snapshot(1, old_map).ok());
    ASSERT_TRUE(sd->journal(2, 2, set(2)).ok());
    ASSERT_TRUE(sd->beginSnapshot(2).ok());
    ASSERT_TRUE(sd->journal(3, 3, set(3)).ok());
    ASSERT_TRUE(StateDirectory::writeSnapshotFile(sd->snapshotPath(), sd->mapId(), 2, new_map, {}).ok());
    ASSERT_TRUE(sd->journal(4, 4, set(4)).ok());
    ASSERT_TRUE(sd->finishSnapshot({}).ok());
    ASSERT_TRUE(sd->journal(5, 5, set(5)).ok());
  }
  fs::resize_file(dir_ / "snapshot.ogfs", 50);
  auto r = StateDirectory::open(dir_)->recover(1, 5000);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->snapshot_fallback);
  EXPECT_EQ(r->snapshot_map, old_map);
  std::vector<std::int64_t> got;
  for (const auto& rec : r->replay) got.push_back(rec.seq);
  EXPECT_EQ(got, (std::vector<std::int64_t>{2, 3, 4, 5}));
}

TEST_F(StateDirectoryTest, AbandonedSnapshotLeavesTheOldSnapshotAndTheWholeJournal) {
  const std::vector<std::uint8_t> map(70, 1);
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    ASSERT_TRUE(sd->journal(1, 1, set(1)).ok());
    ASSERT_TRUE(sd->snapshot(1, map).ok());
    ASSERT_TRUE(sd->journal(2, 2, set(2)).ok());
    ASSERT_TRUE(sd->beginSnapshot(2).ok());
    ASSERT_TRUE(sd->journal(3, 3, set(3)).ok());
    sd->abandonSnapshot();  // the file could not be written
    EXPECT_FALSE(sd->snapshotBegun());
    EXPECT_FALSE(fs::exists(sd->nextJournalPath()));
    ASSERT_TRUE(sd->journal(4, 4, set(4)).ok());
    EXPECT_FALSE(sd->finishSnapshot({}).ok());  // nothing begun: refused
  }
  auto r = StateDirectory::open(dir_)->recover(1);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->snapshot_seq, 1);
  EXPECT_EQ(r->last_seq, 4);
  EXPECT_EQ(r->replay.size(), 3u);
}

TEST_F(StateDirectoryTest, NextJournalLeftByACrashIsNotReadAndIsReplaced) {
  {
    auto sd = StateDirectory::open(dir_);
    ASSERT_TRUE(sd->recover(7).ok());
    ASSERT_TRUE(sd->journal(1, 1, set(1)).ok());
    ASSERT_TRUE(sd->beginSnapshot(1).ok());
    ASSERT_TRUE(sd->journal(2, 2, set(2)).ok());
  }  // killed before the snapshot file was written
  ASSERT_TRUE(fs::exists(dir_ / "journal.next.ogfj"));
  auto sd = StateDirectory::open(dir_);
  auto r = sd->recover(1);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->snapshot_seq, 0);
  EXPECT_EQ(r->last_seq, 2);
  ASSERT_TRUE(sd->journal(3, 3, set(3)).ok());
  ASSERT_TRUE(sd->snapshot(3, std::vector<std::uint8_t>(40, 3)).ok());
  ASSERT_TRUE(sd->journal(4, 4, set(4)).ok());
  EXPECT_FALSE(fs::exists(dir_ / "journal.next.ogfj"));
  auto again = StateDirectory::open(dir_)->recover(1);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->snapshot_seq, 3);
  ASSERT_EQ(again->replay.size(), 1u);
  EXPECT_EQ(again->replay[0].seq, 4);
}

TEST_F(StateDirectoryTest, JournalBeforeThePreviousGenerationIsDeletedOnlyOnceTheSnapshotIsWritten) {
  const std::vector<std::uint8_t> map2(60, 2), map4(60, 4);
  auto sd = StateDirectory::open(dir_);
  ASSERT_TRUE(sd->recover(7).ok());
  ASSERT_TRUE(sd->journal(1, 1, set(1)).ok());
  ASSERT_TRUE(sd->snapshot(1, std::vector<std::uint8_t>(60, 1)).ok());
  ASSERT_TRUE(sd->journal(2, 2, set(2)).ok());
  ASSERT_TRUE(sd->snapshot(2, map2).ok());
  ASSERT_TRUE(sd->journal(3, 3, set(3)).ok());
  EXPECT_FALSE(fs::exists(sd->retiredJournalPath()));
  ASSERT_TRUE(sd->beginSnapshot(3).ok());
  ASSERT_TRUE(fs::exists(sd->retiredJournalPath())) << "the journal after snapshot 1 waits to be deleted";
  ASSERT_TRUE(sd->journal(4, 4, set(4)).ok());
  {
    // A crash now: snapshot 2 and the journal after it, whichever generation recovery reads.
    auto r = StateDirectory::read(dir_, 1);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->snapshot_seq, 2);
    EXPECT_EQ(r->last_seq, 4);
  }
  ASSERT_TRUE(StateDirectory::writeSnapshotFile(sd->snapshotPath(), sd->mapId(), 3, map4, {}).ok());
  StateDirectory::retireOldJournal(sd->retiredJournalPath());
  EXPECT_FALSE(fs::exists(sd->retiredJournalPath()));
  ASSERT_TRUE(sd->finishSnapshot({}).ok());
  ASSERT_TRUE(sd->journal(5, 5, set(5)).ok());
  fs::resize_file(dir_ / "snapshot.ogfs", 30);  // the newest snapshot damaged: the previous generation
  auto r = StateDirectory::open(dir_)->recover(1, 6000);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->snapshot_map, map2);
  std::vector<std::int64_t> got;
  for (const auto& rec : r->replay) got.push_back(rec.seq);
  EXPECT_EQ(got, (std::vector<std::int64_t>{3, 4, 5}));
}

}  // namespace
