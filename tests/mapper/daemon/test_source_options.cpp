// The configuration's `sources:` list: without it one source from the top-level keys; each entry lands
// resolved against them; --print-config reads back to the same sources; a wrong entry is refused naming the
// file, the line, the entry and the field, and configurations that cannot be mapped (a name twice, two
// sources on one channel, a robot on two pose channels, two robots on one) are refused naming both.
#include <gtest/gtest.h>

#include <string>

#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/source_options.hpp"

namespace {

using ogf::adapters::ScanTimeBase;
using ogf::mapper_daemon::MapperOptions;
using ogf::mapper_daemon::parseMapperOptions;
using ogf::mapper_daemon::resolveSources;

// The error of reading and validating `yaml`, or "ok".
std::string errorOf(const std::string& yaml) {
  MapperOptions o;
  if (auto st = parseMapperOptions(yaml, "m.yaml", o); !st) return st.error().message;
  if (auto st = o.validate(); !st) return st.error().message;
  return "ok";
}

TEST(SourceOptions, WithoutSourcesOneSourceComesFromTheTopLevelKeys) {
  MapperOptions o;
  ASSERT_TRUE(parseMapperOptions("channels: {scan: S, pose: P}\ntime_base: host\n"
                                 "map: {extrinsic: {translation: [1, 2, 3]}}\n",
                                 "m.yaml", o));
  const auto sources = resolveSources(o);
  ASSERT_TRUE(sources) << sources.error().message;
  ASSERT_EQ(sources->size(), 1U);
  const auto& s = sources->front();
  EXPECT_EQ(s.name, "lidar");
  EXPECT_EQ(s.robot, "robot");
  EXPECT_EQ(s.channel, "S");
  EXPECT_FALSE(s.packets);
  EXPECT_EQ(s.pose_channel, "P");
  EXPECT_EQ(s.time_base, ScanTimeBase::kHost);
  EXPECT_TRUE(s.body_from_sensor.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
}

TEST(SourceOptions, EachEntryLandsResolvedAgainstTheTopLevelKeys) {
  MapperOptions o;
  ASSERT_TRUE(parseMapperOptions("channels: {pose: ODOM}\n"
                                 "map: {extrinsic: {translation: [0, 0, 1]}}\n"
                                 "sources:\n"
                                 "  - {name: front, robot: r1, scan_channel: SCAN_F}\n"
                                 "  - name: rear\n"
                                 "    robot: r1\n"
                                 "    packet_channel: PACKETS_R\n"
                                 "    calibration: /etc/ogf/rear.xml\n"
                                 "    time_base: device\n"
                                 "    extrinsic: {translation: [-0.5, 0, 0.4], rpy: [0, 0, 3.14159]}\n"
                                 "  - {name: other, robot: r2, scan_channel: SCAN_O, pose_channel: ODOM2}\n",
                                 "m.yaml", o));
  const auto sources = resolveSources(o);
  ASSERT_TRUE(sources) << sources.error().message;
  ASSERT_EQ(sources->size(), 3U);
  const auto& front = (*sources)[0];
  const auto& rear = (*sources)[1];
  const auto& other = (*sources)[2];
  EXPECT_EQ(front.pose_channel, "ODOM");
  EXPECT_EQ(front.time_base, ScanTimeBase::kAuto);
  EXPECT_TRUE(front.body_from_sensor.translation().isApprox(Eigen::Vector3d(0, 0, 1))) << "map.extrinsic by default";
  EXPECT_TRUE(rear.packets);
  EXPECT_EQ(rear.channel, "PACKETS_R");
  EXPECT_EQ(rear.calibration, "/etc/ogf/rear.xml");
  EXPECT_EQ(rear.time_base, ScanTimeBase::kDevice);
  EXPECT_TRUE(rear.body_from_sensor.translation().isApprox(Eigen::Vector3d(-0.5, 0, 0.4)));
  EXPECT_NEAR(rear.body_from_sensor.linear()(0, 0), -1.0, 1e-5);
  EXPECT_EQ(other.robot, "r2");
  EXPECT_EQ(other.pose_channel, "ODOM2");
}

TEST(SourceOptions, PrintedSourcesReadBackToTheSameSources) {
  MapperOptions o;
  ASSERT_TRUE(parseMapperOptions("sources:\n"
                                 "  - {name: a, robot: r1, scan_channel: \"SCAN A\", time_base: host,\n"
                                 "     extrinsic: {translation: [0.25, 0, 0.5], quaternion: [0, 0, 0, 1]}}\n"
                                 "  - {name: b, robot: r2, packet_channel: P, calibration: c.yaml, pose_channel: Q}\n",
                                 "m.yaml", o));
  MapperOptions back;
  ASSERT_TRUE(parseMapperOptions(ogf::mapper_daemon::mapperConfigYaml(o), "printed.yaml", back));
  const auto a = resolveSources(o), b = resolveSources(back);
  ASSERT_TRUE(a && b);
  ASSERT_EQ(a->size(), b->size());
  for (std::size_t i = 0; i < a->size(); ++i) {
    EXPECT_EQ((*a)[i].name, (*b)[i].name);
    EXPECT_EQ((*a)[i].robot, (*b)[i].robot);
    EXPECT_EQ((*a)[i].channel, (*b)[i].channel);
    EXPECT_EQ((*a)[i].packets, (*b)[i].packets);
    EXPECT_EQ((*a)[i].calibration, (*b)[i].calibration);
    EXPECT_EQ((*a)[i].pose_channel, (*b)[i].pose_channel);
    EXPECT_EQ((*a)[i].time_base, (*b)[i].time_base);
    EXPECT_TRUE((*a)[i].body_from_sensor.isApprox((*b)[i].body_from_sensor));
  }
}

TEST(SourceOptions, AWrongEntryIsRefusedNamingTheFileTheLineTheEntryAndTheField) {
  EXPECT_EQ(errorOf("sources:\n  - {name: a, scan_channel: S}\n  - {name: b, scan_chanel: T}\n"),
            "m.yaml:3: sources[1].scan_chanel: unknown key (name, robot, scan_channel, packet_channel, calibration, "
            "pose_channel, time_base, extrinsic)");
  EXPECT_EQ(errorOf("sources:\n  - {name: a, scan_channel: S, time_base: gps}\n"),
            "m.yaml:2: sources[0].time_base: expected one of 'auto', 'device', 'host', got 'gps'");
  EXPECT_EQ(errorOf("sources:\n  - {scan_channel: S}\n"), "m.yaml:2: sources[0]: needs a name");
  EXPECT_EQ(errorOf("sources: {name: a}\n"), "m.yaml:1: sources: expected a list of sources");
  EXPECT_EQ(errorOf("sources:\n  - {name: a, scan_channel: S, extrinsic: {translation: [1, 2]}}\n"),
            "m.yaml:2: sources[0].extrinsic.translation: expected [x, y, z]");
}

TEST(SourceOptions, ConfigurationsThatCannotBeMappedAreRefusedNamingWhatClashes) {
  EXPECT_EQ(errorOf("sources: [{name: a, scan_channel: S}, {name: a, scan_channel: T}]\n"),
            "sources: the name 'a' is used twice");
  EXPECT_EQ(errorOf("sources: [{name: a, scan_channel: S}, {name: b, scan_channel: S}]\n"),
            "sources: 'a' and 'b' both read S: each source needs its own channel");
  EXPECT_EQ(errorOf("sources: [{name: a, scan_channel: S, packet_channel: P}]\n"),
            "sources[0] (a): needs exactly one of scan_channel (ogf.lidar_scan_t) and packet_channel "
            "(ogf.velodyne_packets_t)");
  EXPECT_EQ(errorOf("sources: [{name: a, scan_channel: S, calibration: c.xml}]\n"),
            "sources[0] (a): calibration is for a packet_channel: the scans on scan_channel are decoded already");
  EXPECT_EQ(errorOf("sources: [{name: 'a b', scan_channel: S}]\n"),
            "sources[0] (a b): name 'a b' must be 1 to 32 letters, digits, '_' or '-'");
  EXPECT_EQ(errorOf("sources: [{name: a, robot: r, scan_channel: S, pose_channel: P1},\n"
                    "          {name: b, robot: r, scan_channel: T, pose_channel: P2}]\n"),
            "sources: robot 'r' has its odometry on both P1 and P2: the sources of one robot share its pose_channel");
  EXPECT_EQ(errorOf("sources: [{name: a, robot: r1, scan_channel: S}, {name: b, robot: r2, scan_channel: T}]\n"),
            "sources: robots 'r1' and 'r2' both take their odometry from POSE: each robot needs its own pose_channel");
  EXPECT_EQ(errorOf("pose_correction: {mode: scan-match}\n"
                    "sources: [{name: a, robot: r1, scan_channel: S, pose_channel: P1},\n"
                    "          {name: b, robot: r2, scan_channel: T, pose_channel: P2}]\n"),
            "pose_correction.mode: corrects one robot's odometry; the sources name several robots");
  EXPECT_EQ(errorOf("pose_source: static\n"
                    "sources: [{name: a, robot: r1, scan_channel: S}, {name: b, robot: r2, scan_channel: T}]\n"),
            "ok")
      << "with one fixed pose the robots need no odometry of their own";
}

}  // namespace
