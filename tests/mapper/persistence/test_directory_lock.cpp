// DirectoryLock: one holder at a time, the holder's pid in the refusal, the lock free again once the
// holder is gone, and a directory created when missing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "ogf/persistence/directory_lock.hpp"

namespace {

namespace fs = std::filesystem;
using ogf::persistence::DirectoryLock;

class DirectoryLockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ogf-lock-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(DirectoryLockTest, SecondHolderIsRefusedWithTheFirstsPid) {
  auto first = DirectoryLock::acquire(dir_ / "state");
  ASSERT_TRUE(first.lock.has_value()) << first.message;
  EXPECT_TRUE(fs::is_directory(dir_ / "state"));
  EXPECT_EQ(DirectoryLock::holderOf(dir_ / "state"), ::getpid());
  const auto second = DirectoryLock::acquire(dir_ / "state");
  EXPECT_FALSE(second.lock.has_value());
  EXPECT_TRUE(second.in_use);
  EXPECT_NE(second.message.find((dir_ / "state").string() + " is in use by process " + std::to_string(::getpid())),
            std::string::npos)
      << second.message;
}

TEST_F(DirectoryLockTest, FreeAgainOnceReleased) {
  {
    auto first = DirectoryLock::acquire(dir_);
    ASSERT_TRUE(first.lock.has_value()) << first.message;
  }
  const auto again = DirectoryLock::acquire(dir_);
  EXPECT_TRUE(again.lock.has_value()) << again.message;
  EXPECT_FALSE(again.in_use);
}

TEST_F(DirectoryLockTest, MovedLockStaysHeld) {
  auto first = DirectoryLock::acquire(dir_);
  ASSERT_TRUE(first.lock.has_value());
  DirectoryLock moved = std::move(*first.lock);
  first.lock.reset();
  EXPECT_TRUE(DirectoryLock::acquire(dir_).in_use);
}

TEST_F(DirectoryLockTest, UncreatableDirectoryIsNotInUse) {
  fs::create_directories(dir_);
  { std::ofstream(dir_ / "file") << "x"; }
  const auto r = DirectoryLock::acquire(dir_ / "file" / "state");
  EXPECT_FALSE(r.lock.has_value());
  EXPECT_FALSE(r.in_use);
  EXPECT_NE(r.message.find("cannot create"), std::string::npos) << r.message;
}

}  // namespace
