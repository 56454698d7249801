// ogf-mapper's pose source in its configuration: pose_source odometry|static and static_pose (the body in
// the map frame), read from YAML; anything else is refused naming the file, line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ogf/mapper_daemon/mapper_options.hpp"

namespace ogf::mapper_daemon {
namespace {

TEST(PoseSourceOptions, StaticWithItsPoseIsReadAndOdometryIsTheDefault) {
  MapperOptions o;
  EXPECT_EQ(o.pose_source, PoseSource::kOdometry);
  EXPECT_TRUE(o.static_pose.bodyFromSensor().isApprox(Eigen::Isometry3d::Identity()));
  ASSERT_TRUE(parseMapperOptions(
      "pose_source: static\nstatic_pose: {translation: [1, 2, 3], rpy: [0, 0, 1.5707963267948966]}\n",
      "m.yaml", o));
  EXPECT_EQ(o.pose_source, PoseSource::kStatic);
  const Eigen::Isometry3d body = o.static_pose.bodyFromSensor();
  EXPECT_TRUE(body.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE((body * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(1, 3, 3), 1e-9)) << "yaw 90 degrees";
  EXPECT_TRUE(o.validate());
  ASSERT_TRUE(
      parseMapperOptions("static_pose: {quaternion: [0, 0, 0, 1]}\npose_source: odometry\n", "m.yaml", o));
  EXPECT_EQ(o.pose_source, PoseSource::kOdometry);
  EXPECT_TRUE((o.static_pose.bodyFromSensor().linear() * Eigen::Vector3d(1, 0, 0))
                  .isApprox(Eigen::Vector3d(-1, 0, 0)));
}

TEST(PoseSourceOptions, AnUnknownSourceOrAMalformedPoseIsRefusedNamingTheKey) {
  for (const char* bad : {"pose_source: gps\n", "static_pose: {translation: [1, 2]}\n",
                          "static_pose: {scale: 2}\n", "static_pose: {quaternion: [1, 0, 0]}\n"}) {
    MapperOptions o;
    const auto st = parseMapperOptions(bad, "m.yaml", o);
    ASSERT_FALSE(st) << bad;
    EXPECT_EQ(st.error().message.rfind("m.yaml:1: ", 0), 0U) << st.error().message;
    EXPECT_NE(st.error().message.find(std::string(bad).substr(0, std::string(bad).find(':'))),
              std::string::npos)
        << st.error().message;
  }
  MapperOptions o;
  ASSERT_TRUE(
      parseMapperOptions("pose_source: static\nstatic_pose: {quaternion: [2, 0, 0, 0]}\n", "m.yaml", o));
  EXPECT_FALSE(o.validate()) << "not a unit quaternion";
  o = {};
  ASSERT_TRUE(parseMapperOptions("pose_source: static\npose_correction: {mode: scan-match}\n", "m.yaml", o));
  ASSERT_FALSE(o.validate());
  EXPECT_NE(o.validate().error().message.find("pose_source: odometry"), std::string::npos)
      << o.validate().error().message;
}

}  // namespace
}  // namespace ogf::mapper_daemon
