// Rig files: the sensors land with their names, models, rates and mounts; each mistake is refused naming the
// source, the line and the field; the built-in front-rear rig has its two sensors where its comment says.
#include <gtest/gtest.h>

#include <cmath>

#include "ogf/sim/rig.hpp"

namespace {

using ogf::sim::parseRig;

std::string errorOf(const std::string& yaml) {
  auto rig = parseRig(yaml, "rig.yaml");
  return rig ? "parsed" : rig.error().message;
}

TEST(RigFile, SensorsLandWithTheirModelRateAndMount) {
  auto rig = parseRig("sensors:\n"
                      "  - {name: front, model: hdl32e, rpm: 1200, mount: {xyz: [0.5, 0, 0.4]}}\n"
                      "  - {name: rear, mount: {xyz: [-0.5, 0, 1.4], rpy_deg: [0, 0, 90]}}\n",
                      "rig.yaml");
  ASSERT_TRUE(rig) << rig.error().message;
  ASSERT_EQ(rig->sensors.size(), 2U);
  const auto& front = rig->sensors[0];
  const auto& rear = rig->sensors[1];
  EXPECT_EQ(front.name, "front");
  EXPECT_EQ(front.model, "hdl32e");
  EXPECT_EQ(front.rpm, 1200.0);
  EXPECT_TRUE(front.sensor_to_body.translation().isApprox(Eigen::Vector3d(0.5, 0, 0.4)));
  EXPECT_FALSE(rear.model) << "unset: ogf-sim's --model";
  EXPECT_FALSE(rear.rpm);
  // Yaw 90 degrees: the sensor's x axis along the body's y.
  EXPECT_TRUE((rear.sensor_to_body.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

TEST(RigFile, EachMistakeIsRefusedNamingTheLineAndTheField) {
  EXPECT_EQ(errorOf("sensors:\n  - {name: a, mount: {xyz: [1, 2]}}\n"),
            "rig.yaml:2: sensors[0].mount.xyz: expected 3 numbers");
  EXPECT_EQ(errorOf("sensors:\n  - {name: a, mount: {xyz: [0, 0, 1]}}\n  - {name: a, mount: {xyz: [0, 0, 1]}}\n"),
            "rig.yaml:3: sensors[1].name: 'a' is used twice");
  EXPECT_EQ(errorOf("sensors:\n  - {name: a, rpm: 5000, mount: {xyz: [0, 0, 1]}}\n"),
            "rig.yaml:2: sensors[0].rpm: must be 300 to 1200");
  EXPECT_EQ(errorOf("sensors:\n  - {name: a, model: vlp64, mount: {xyz: [0, 0, 1]}}\n"),
            "rig.yaml:2: sensors[0].model: expected vlp16 or hdl32e");
  EXPECT_EQ(errorOf("sensors:\n  - {name: a}\n"), "rig.yaml:2: sensors[0].mount: missing");
  EXPECT_EQ(errorOf("sensors:\n  - {name: 'a b', mount: {xyz: [0, 0, 1]}}\n"),
            "rig.yaml:2: sensors[0].name: must be 1 to 32 letters, digits, '_' or '-'");
  EXPECT_EQ(errorOf("sensors:\n  - {name: a, mount: {xyz: [0, 0, 1]}, tilt: 3}\n"),
            "rig.yaml:2: sensors[0].tilt: unknown key (name, model, rpm, mount)");
  EXPECT_EQ(errorOf("lidars: []\n"), "rig.yaml:1: sensors: missing: a rig lists its sensors");
}

TEST(RigFile, FrontRearHasALowSensorAheadAndAHighOneBehindLookingBackAndDown) {
  auto rig = ogf::sim::resolveRig("front-rear");
  ASSERT_TRUE(rig) << rig.error().message;
  ASSERT_EQ(rig->sensors.size(), 2U);
  const auto& front = rig->sensors[0].sensor_to_body;
  const auto& rear = rig->sensors[1].sensor_to_body;
  EXPECT_GT(front.translation().x(), 0);
  EXPECT_LT(rear.translation().x(), 0);
  EXPECT_GT(rear.translation().z(), front.translation().z());
  const Eigen::Vector3d rear_x = rear.linear() * Eigen::Vector3d::UnitX();
  EXPECT_LT(rear_x.x(), -0.9) << "looks backwards";
  EXPECT_LT(rear_x.z(), -0.2) << "tilted down";
}

}  // namespace
