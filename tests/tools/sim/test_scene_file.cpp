// Scene YAML: the presets load, and malformed scenes are refused with the line and the field.
#include <gtest/gtest.h>

#include "ogf/sim/scene.hpp"

namespace ogf::sim {
namespace {

TEST(SimSceneFile, EveryPresetLoadsWithItsTrajectories) {
  const auto names = scenePresetNames();
  ASSERT_GE(names.size(), 3u);
  for (const auto& name : names) {
    const auto scene = presetScene(name);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    EXPECT_EQ(scene->world.name, name);
    for (const char* t : {"static", "loop", "corridor"}) {
      const auto spec = resolveTrajectory(*scene, t);
      ASSERT_TRUE(spec.ok()) << name << ": " << spec.error().message;
      EXPECT_TRUE(Trajectory::build(*spec).ok()) << name << "/" << t;
    }
    // The sensor sits 0.5 to 1.5 m above the ground, level.
    const double h = scene->sensor_to_body.translation().z();
    EXPECT_GE(h, 0.5);
    EXPECT_LE(h, 1.5);
  }
}

TEST(SimSceneFile, DefaultWorldLabIsIndoorAndSmall) {
  const auto scene = resolveScene("lab");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const Eigen::Vector3d extent = scene->world.bounds.max - scene->world.bounds.min;
  EXPECT_LT(extent.x() * extent.y(), 200.0);
  // A semi-transparent material exists, so dual-return captures hold second returns.
  bool transparent = false;
  for (const auto& m : scene->world.materials) transparent = transparent || m.transmittance > 0.0;
  EXPECT_TRUE(transparent);
}

TEST(SimSceneFile, NegativeRadiusIsRefusedWithLineAndField) {
  const char* yaml =
      "name: bad\n"
      "ground: {height: 0}\n"
      "solids:\n"
      "  - {type: box, center: [0, 0, 1], size: [1, 1, 1]}\n"
      "  - {type: cylinder, center: [1, 1], radius: -2, z: [0, 1]}\n";
  const auto scene = parseScene(yaml, "bad.yaml");
  ASSERT_FALSE(scene.ok());
  EXPECT_EQ(scene.error().message, "bad.yaml:5: solids[1].radius: must be positive");
}

TEST(SimSceneFile, MisspeltFieldIsRefusedNotIgnored) {
  const auto scene = parseScene("solids:\n  - {type: box, centre: [0, 0, 1], size: [1, 1, 1]}\n", "typo.yaml");
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().message.find("typo.yaml:2"), std::string::npos) << scene.error().message;
  EXPECT_NE(scene.error().message.find("solids[0].centre: unknown field"), std::string::npos) << scene.error().message;
}

TEST(SimSceneFile, NonNumberAndUnknownMaterialAreNamed) {
  auto scene = parseScene("solids:\n  - {type: box, center: [0, x, 1], size: [1, 1, 1]}\n", "s.yaml");
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().message.find("s.yaml:2: solids[0].center[1]: expected a number"), std::string::npos)
      << scene.error().message;
  scene = parseScene("solids:\n  - {type: box, center: [0, 0, 1], size: [1, 1, 1], material: gold}\n", "m.yaml");
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().message.find("no material named 'gold'"), std::string::npos) << scene.error().message;
}

TEST(SimSceneFile, InvalidYamlReportsItsLine) {
  const auto scene = parseScene("name: x\nsolids: [\n  {type: box\n", "broken.yaml");
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().message.find("broken.yaml:"), std::string::npos) << scene.error().message;
}

TEST(SimSceneFile, UnknownWorldListsThePresets) {
  const auto scene = resolveScene("moon");
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().message.find("lab"), std::string::npos) << scene.error().message;
}

TEST(SimSceneFile, TrajectoryEntryParses) {
  const auto spec = parseTrajectory("speed: 2\nloop: true\nwaypoints: [[0, 0], [4, 0, 0.5], [4, 3]]\n", "t.yaml");
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  EXPECT_EQ(spec->speed, 2.0);
  EXPECT_TRUE(spec->loop);
  ASSERT_EQ(spec->waypoints.size(), 3u);
  EXPECT_EQ(spec->waypoints[1], Eigen::Vector3d(4, 0, 0.5));
}

}  // namespace
}  // namespace ogf::sim
