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

TEST(SimSceneFile, MoversAreNamedSetsResolvedByName) {
  const char* yaml =
      "ground: {height: 0}\n"
      "bounds: {min: [-1, -1, -1], max: [5, 5, 3]}\n"
      "materials:\n  - {name: person, reflectivity: 30}\n"
      "movers:\n"
      "  cart:\n"
      "    - {type: box, center: [0, 0, 0.5], size: [1, 0.6, 1], start_s: 2,\n"
      "       path: {speed: 0.5, waypoints: [[0, 0], [3, 0]]}}\n"
      "    - {type: cylinder, center: [0, 0], radius: 0.2, z: [0, 1.8], material: person,\n"
      "       path: {waypoints: [[1, 1], [1, 4]]}}\n";
  const auto scene = parseScene(yaml, "movers.yaml");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto cart = resolveMovers(*scene, "cart");
  ASSERT_TRUE(cart.ok()) << cart.error().message;
  ASSERT_EQ(cart->size(), 2u);
  EXPECT_EQ((*cart)[0].start_s, 2.0);
  EXPECT_EQ((*cart)[0].path.speed, 0.5);
  EXPECT_EQ((*cart)[1].start_s, 0.0);
  EXPECT_TRUE(std::holds_alternative<Cylinder>((*cart)[1].solid.shape));
  EXPECT_TRUE(resolveMovers(*scene, "none")->empty());
  EXPECT_TRUE(resolveMovers(*scene, "")->empty());
  const auto unknown = resolveMovers(*scene, "bus");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message.find("cart"), std::string::npos) << unknown.error().message;
}

TEST(SimSceneFile, AMoverWithoutAPathOrWithAMisspeltKeyIsRefused) {
  auto scene = parseScene("solids:\n  - {type: box, center: [3, 3, 1], size: [1, 1, 2]}\n"
                          "movers:\n  x:\n    - {type: box, center: [0, 0, 0.5], size: [1, 1, 1]}\n",
                          "p.yaml");
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().message.find("p.yaml:5"), std::string::npos) << scene.error().message;
  EXPECT_NE(scene.error().message.find("path"), std::string::npos) << scene.error().message;
  scene = parseScene("solids:\n  - {type: box, center: [3, 3, 1], size: [1, 1, 2]}\nmovers:\n  x:\n    - {type: box, center: [0, 0, 0.5], size: [1, 1, 1], start: 1,\n"
                     "       path: {waypoints: [[0, 0], [1, 0]]}}\n",
                     "k.yaml");
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().message.find("start: unknown field"), std::string::npos) << scene.error().message;
}

TEST(SimSceneFile, TheLabHasAPersonWalkingThrough) {
  const auto lab = resolveScene("lab");
  ASSERT_TRUE(lab.ok()) << lab.error().message;
  const auto person = resolveMovers(*lab, "person");
  ASSERT_TRUE(person.ok()) << person.error().message;
  ASSERT_EQ(person->size(), 1u);
  EXPECT_GT((*person)[0].start_s, 0.0);
}

}  // namespace
}  // namespace ogf::sim
