#include <gtest/gtest.h>

#include <string_view>

#include "ogf/common/crc32.hpp"

namespace {

TEST(Crc32, MatchesTheStandardCheckValue) {
  // The CRC-32/ISO-HDLC check value: crc of the ASCII string "123456789".
  constexpr std::string_view s = "123456789";
  EXPECT_EQ(ogf::crc32(s.data(), s.size()), 0xCBF43926U);
  EXPECT_EQ(ogf::crc32(s.data(), 0), 0U);
}

TEST(Crc32, IsIncremental) {
  constexpr std::string_view s = "The quick brown fox jumps over the lazy dog";
  const auto whole = ogf::crc32(s.data(), s.size());
  EXPECT_EQ(whole, 0x414FA339U);
  EXPECT_EQ(ogf::crc32(s.data() + 10, s.size() - 10, ogf::crc32(s.data(), 10)), whole);
}

}  // namespace
