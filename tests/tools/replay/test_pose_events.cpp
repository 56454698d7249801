// ogf-replay's odometry: CSV lines become odometry_t messages in time order; malformed lines are skipped
// and named; an LCM log's pose events are republished byte for byte.
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/odometry_t.hpp>

#include <filesystem>
#include <fstream>

#include "ogf/replay/pose_events.hpp"

namespace {

ogf::odometry_t decode(const ogf::replay::PoseEvent& e) {
  ogf::odometry_t m;
  EXPECT_GT(m.decode(e.bytes.data(), 0, static_cast<int>(e.bytes.size())), 0);
  return m;
}

TEST(PoseEvents, CsvLinesBecomeOdometryMessagesSortedByTime) {
  const auto ev = ogf::replay::parsePoseCsv(
      "utime,x,y,z,qw,qx,qy,qz\n20,1,2,3,1,0,0,0\n10,4,5,6,0,0,0,1\n", "odo.csv");
  ASSERT_EQ(ev.events.size(), 2U);
  EXPECT_EQ(ev.skipped, 0);
  EXPECT_EQ(ev.events[0].utime, 10);
  const auto m = decode(ev.events[0]);
  EXPECT_EQ(m.utime, 10);
  EXPECT_EQ(m.position[2], 6.0);
  EXPECT_EQ(m.orientation[3], 1.0);
  EXPECT_EQ(m.frame_id, "odom");
}

TEST(PoseEvents, MalformedCsvLinesAreSkippedCountedAndNamedByLine) {
  const auto ev = ogf::replay::parsePoseCsv("utime,x,y,z,qw,qx,qy,qz\n10,1,2,3,1,0,0\nabc,1,2,3,1,0,0,0\n"
                                            "30,1,2,nan,1,0,0,0\n40,1,2,3,1,0,0,0\n",
                                            "odo.csv");
  ASSERT_EQ(ev.events.size(), 1U);
  EXPECT_EQ(ev.skipped, 3);
  ASSERT_EQ(ev.problems.size(), 3U);
  EXPECT_NE(ev.problems[0].find("odo.csv:2:"), std::string::npos) << ev.problems[0];
  EXPECT_NE(ev.problems[1].find("odo.csv:3: utime"), std::string::npos) << ev.problems[1];
  EXPECT_NE(ev.problems[2].find("odo.csv:4: z"), std::string::npos) << ev.problems[2];
}

TEST(PoseEvents, AnLcmLogsPoseEventsAreRepublishedByteForByte) {
  const auto path = std::filesystem::temp_directory_path() / ("ogf-replay-poses-" + std::to_string(::getpid()) + ".lcmlog");
  std::vector<std::uint8_t> payload{1, 2, 3, 4, 5};
  {
    lcm::LogFile log(path.string(), "w");
    ASSERT_TRUE(log.good());
    lcm::LogEvent e{};
    e.eventnum = 0;
    e.timestamp = 777;
    e.channel = "POSE";
    e.datalen = static_cast<int32_t>(payload.size());
    e.data = payload.data();
    log.writeEvent(&e);
    e.timestamp = 778;
    e.channel = "OTHER";
    log.writeEvent(&e);
  }
  auto ev = ogf::replay::loadPoseEvents(path, "POSE");
  std::filesystem::remove(path);
  ASSERT_TRUE(ev.ok()) << ev.error().message;
  ASSERT_EQ(ev->events.size(), 1U);
  EXPECT_EQ(ev->events[0].utime, 777);
  EXPECT_EQ(ev->events[0].bytes, payload);
}

TEST(PoseEvents, AFileWithoutAnyPoseIsAnErrorNamingIt) {
  const auto path = std::filesystem::temp_directory_path() / ("ogf-replay-empty-" + std::to_string(::getpid()) + ".csv");
  std::ofstream(path) << "utime,x,y,z,qw,qx,qy,qz\nbad\n";
  auto ev = ogf::replay::loadPoseEvents(path, "POSE");
  std::filesystem::remove(path);
  ASSERT_FALSE(ev.ok());
  EXPECT_NE(ev.error().message.find(path.string()), std::string::npos);
}

}  // namespace
