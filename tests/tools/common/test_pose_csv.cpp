// The pose CSV every tool reads: well-formed lines in every accepted spelling, each kind of malformed line
// skipped, counted and named by source, line and field, and rows written so they read back.
#include <gtest/gtest.h>

#include <string>

#include "ogf/tools/pose_csv.hpp"

namespace ogf::tools {
namespace {

TEST(PoseCsv, ReadsHeaderCommentsBlankLinesAndSpacedFields) {
  const PoseCsv csv = parsePoseCsv(
      "# written by hand\nutime, x, y, z, qw, qx, qy, qz\n\n100,1,2,3,1,0,0,0\r\n 200 , +1.5 ,-2,3e0,0.5,0.5,0.5,0.5\n",
      "odo.csv");
  EXPECT_EQ(csv.skipped, 0);
  ASSERT_EQ(csv.rows.size(), 2U);
  EXPECT_EQ(csv.rows[0].line, 4);
  EXPECT_EQ(csv.rows[0].utime, 100);
  EXPECT_EQ(csv.rows[1].line, 5);
  EXPECT_EQ(csv.rows[1].utime, 200);
  EXPECT_EQ(csv.rows[1].values, (std::array<double, 7>{1.5, -2.0, 3.0, 0.5, 0.5, 0.5, 0.5}));
}

TEST(PoseCsv, TheHeaderIsOptionalButOnlyFirst) {
  const PoseCsv csv = parsePoseCsv("100,0,0,0,1,0,0,0\nutime,x,y,z,qw,qx,qy,qz\n", "odo.csv");
  ASSERT_EQ(csv.rows.size(), 1U);
  ASSERT_EQ(csv.skipped, 1);
  EXPECT_NE(csv.problems[0].find("odo.csv:2: utime 'utime' is not an integer"), std::string::npos) << csv.problems[0];
}

TEST(PoseCsv, MalformedLinesAreSkippedCountedAndNamed) {
  const PoseCsv csv = parsePoseCsv(
      "utime,x,y,z,qw,qx,qy,qz\n"
      "1,0,0,0,1,0,0\n"          // 7 fields
      "2,0,0,0,1,0,0,0,9\n"      // 9 fields
      "3.5,0,0,0,1,0,0,0\n"      // utime not an integer
      "4,0,zero,0,1,0,0,0\n"     // not a number
      "5,0,0,nan,1,0,0,0\n"      // not finite
      "6,0,0,0,inf,0,0,0\n"      // not finite
      "7,0,0,0,1,0,0,\n"         // empty field
      "8,0,0,0,1,0,0,0\n",
      "odo.csv");
  ASSERT_EQ(csv.rows.size(), 1U);
  EXPECT_EQ(csv.rows[0].utime, 8);
  EXPECT_EQ(csv.skipped, 7);
  ASSERT_EQ(csv.problems.size(), 7U);
  const char* expected[] = {"odo.csv:2: 7 fields, expected 8", "odo.csv:3: more than 8 fields",
                            "odo.csv:4: utime '3.5' is not an integer", "odo.csv:5: y 'zero' is not a finite number",
                            "odo.csv:6: z 'nan' is not a finite number", "odo.csv:7: qw 'inf' is not a finite number",
                            "odo.csv:8: qz '' is not a finite number"};
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_NE(csv.problems[i].find(expected[i]), std::string::npos) << csv.problems[i];
    EXPECT_NE(csv.problems[i].find("; line skipped"), std::string::npos) << csv.problems[i];
  }
}

TEST(PoseCsv, ProblemsAreCappedTheCountIsNot) {
  std::string text;
  for (int i = 0; i < 80; ++i) text += "bad\n";
  const PoseCsv csv = parsePoseCsv(text, "odo.csv");
  EXPECT_EQ(csv.skipped, 80);
  EXPECT_EQ(csv.problems.size(), 50U);
}

TEST(PoseCsv, WrittenRowsReadBack) {
  const std::array<double, 7> pose{1.25, -0.0, 1e-7, 0.7071067812, 0.0, -0.0, 0.7071067812};
  const std::string row = formatPoseCsvRow(-42, pose);
  EXPECT_EQ(row, "-42,1.250000,0.000000,0.000000,0.707106781,0.000000000,0.000000000,0.707106781");
  const PoseCsv csv = parsePoseCsv(std::string(kPoseCsvHeader) + "\n" + row + "\n", "written");
  ASSERT_EQ(csv.rows.size(), 1U);
  EXPECT_EQ(csv.rows[0].utime, -42);
  EXPECT_DOUBLE_EQ(csv.rows[0].values[0], 1.25);
  EXPECT_NEAR(csv.rows[0].values[3], 0.7071067812, 1e-9);
}

}  // namespace
}  // namespace ogf::tools
