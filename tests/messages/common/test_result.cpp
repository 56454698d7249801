#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "ogf/common/atomic_file.hpp"
#include "ogf/common/command_line.hpp"
#include "ogf/common/read_file.hpp"
#include "ogf/common/result.hpp"

namespace {

ogf::Result<int> parsePositive(int v) {
  if (v <= 0) return ogf::Error{"value: must be positive, got " + std::to_string(v)};
  return v;
}

TEST(Result, HoldsAValueOrAnError) {
  const auto good = parsePositive(3);
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(*good, 3);
  const auto bad = parsePositive(-1);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "value: must be positive, got -1");
  EXPECT_TRUE(ogf::okStatus().ok());
}

using ogf::Error;
using ogf::ErrorKind;

TEST(Error, EachFactoryGivesItsKindAndKeepsTheMessage) {
  const std::pair<Error, ErrorKind> cases[] = {
      {Error::usage("--x: unknown"), ErrorKind::usage},
      {Error::configuration("a.yaml:3: key: bad"), ErrorKind::configuration},
      {Error::inputDamaged("f: offset 8: bad magic"), ErrorKind::input_damaged},
      {Error::io("f: cannot read"), ErrorKind::io},
      {Error::resource("f: no space"), ErrorKind::resource},
      {Error::internal("no journal open"), ErrorKind::internal},
      {Error{ErrorKind::io, "f: cannot read"}, ErrorKind::io},
  };
  for (const auto& [error, kind] : cases) {
    EXPECT_EQ(error.kind, kind) << error.message;
    EXPECT_TRUE(error.is(kind)) << error.message;
    EXPECT_FALSE(error.message.empty());
  }
  EXPECT_EQ(Error::io("f: cannot read").message, "f: cannot read");
}

TEST(Error, AnErrorMadeWithoutAKindIsInternal) {
  EXPECT_EQ(Error{"something"}.kind, ErrorKind::internal);
  EXPECT_EQ(Error{}.kind, ErrorKind::internal);
  const ogf::Status st = Error{"something"};
  EXPECT_EQ(st.error().kind, ErrorKind::internal);
}

TEST(Error, EveryKindHasItsOwnName) {
  EXPECT_EQ(ogf::kindName(ErrorKind::usage), "usage");
  EXPECT_EQ(ogf::kindName(ErrorKind::configuration), "configuration");
  EXPECT_EQ(ogf::kindName(ErrorKind::input_damaged), "input damaged");
  EXPECT_EQ(ogf::kindName(ErrorKind::io), "I/O");
  EXPECT_EQ(ogf::kindName(ErrorKind::resource), "resource");
  EXPECT_EQ(ogf::kindName(ErrorKind::internal), "internal");
}

TEST(Error, RunningOutOfSpaceQuotaMemoryOrDescriptorsIsAResourceErrorAnyOtherErrnoIo) {
  for (const int e : {ENOSPC, EDQUOT, ENOMEM, EMFILE, ENFILE})
    EXPECT_EQ(ogf::kindOfErrno(e), ErrorKind::resource) << std::strerror(e);
  for (const int e : {EIO, EACCES, ENOENT, EISDIR, ENOTDIR, EROFS, EPERM})
    EXPECT_EQ(ogf::kindOfErrno(e), ErrorKind::io) << std::strerror(e);
}

TEST(Error, ASystemErrorSaysWhatFailedAndTheSystemsReason) {
  const Error full = Error::system("/state/snapshot.ogfs: write failed", ENOSPC);
  EXPECT_EQ(full.kind, ErrorKind::resource);
  EXPECT_EQ(full.message, std::string("/state/snapshot.ogfs: write failed: ") + std::strerror(ENOSPC));
  const Error denied = Error::system("/state: cannot create", std::make_error_code(std::errc::permission_denied));
  EXPECT_EQ(denied.kind, ErrorKind::io);
  EXPECT_NE(denied.message.find("/state: cannot create: "), std::string::npos) << denied.message;
  EXPECT_EQ(Error::system("x", std::make_error_code(std::errc::not_enough_memory)).kind, ErrorKind::resource);
}

TEST(Error, WithinAddsContextAndKeepsTheKind) {
  const Error e = Error::configuration("must be positive").within("map.resolution");
  EXPECT_EQ(e.message, "map.resolution: must be positive");
  EXPECT_EQ(e.kind, ErrorKind::configuration);
}

// docs/reliability.md, "Exit codes": 2 when the person starting the program must change what they gave it,
// 1 for a failure at run time.
TEST(Error, UsageAndConfigurationErrorsExit2AndEveryOtherKind1) {
  EXPECT_EQ(ogf::cli::exitCodeFor(Error::usage("u")), ogf::cli::kExitUsage);
  EXPECT_EQ(ogf::cli::exitCodeFor(Error::configuration("c")), ogf::cli::kExitUsage);
  for (const ErrorKind kind : {ErrorKind::input_damaged, ErrorKind::io, ErrorKind::resource, ErrorKind::internal})
    EXPECT_EQ(ogf::cli::exitCodeFor(Error{kind, "x"}), ogf::cli::kExitFailure) << ogf::kindName(kind);
  EXPECT_EQ(ogf::cli::kExitUsage, 2);
  EXPECT_EQ(ogf::cli::kExitFailure, 1);
}

TEST(ReadWholeFile, GivesEveryByteOfAFile) {
  const auto path = std::filesystem::temp_directory_path() / ("ogf-read-" + std::to_string(::getpid()));
  const std::string text(200'000, 'x');  // more than one read
  std::ofstream(path, std::ios::binary) << text;
  const auto bytes = ogf::readWholeFile(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message;
  ASSERT_EQ(bytes->size(), text.size());
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(bytes->data()), bytes->size()), text);
}

TEST(ReadWholeFile, ADirectoryOrAMissingFileIsAnIoErrorNamingIt) {
  const auto dir = std::filesystem::temp_directory_path();
  const auto read = ogf::readWholeFile(dir);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error().kind, ErrorKind::io);
  EXPECT_EQ(read.error().message, dir.string() + ": cannot read: " + std::strerror(EISDIR));
  const auto missing = ogf::readWholeFile(dir / "ogf-no-such-file");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().kind, ErrorKind::io);
  EXPECT_NE(missing.error().message.find("ogf-no-such-file: cannot open: "), std::string::npos);
}

TEST(WriteFileAtomically, AFileThatCannotBeCreatedIsAnIoErrorWithTheSystemsReason) {
  const auto path = std::filesystem::temp_directory_path() / "ogf-no-such-directory" / "snapshot.ogfs";
  const std::byte one{1};
  const auto st = ogf::writeFileAtomically(path, std::span(&one, 1));
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().kind, ErrorKind::io) << st.error().message;
  EXPECT_NE(st.error().message.find(path.string() + ": cannot create "), std::string::npos) << st.error().message;
  EXPECT_NE(st.error().message.find(std::strerror(ENOENT)), std::string::npos) << st.error().message;
}

}  // namespace
