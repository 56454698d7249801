#include <gtest/gtest.h>

#include <string>

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

}  // namespace
