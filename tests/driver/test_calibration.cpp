// Calibration parsing: the shipped VeloView XML and ROS YAML files, and malformed text refused with the
// line and the field.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ogf/velodyne/calibration.hpp"
#include "ogf/velodyne/packet_decoder.hpp"
#include "support/shared_data.hpp"

namespace ov = ogf::velodyne;

TEST(Calibration, NominalVlp16HasInterleavedAnglesAndVerticalOffsets) {
  const ov::Calibration c = ov::nominalCalibration(ov::Model::Vlp16);
  ASSERT_EQ(c.lasers.size(), 16u);
  EXPECT_NEAR(c.lasers[0].vert_correction_rad * 180 / std::numbers::pi, -15.0, 1e-9);
  EXPECT_NEAR(c.lasers[1].vert_correction_rad * 180 / std::numbers::pi, 1.0, 1e-9);
  EXPECT_NEAR(c.lasers[15].vert_correction_rad * 180 / std::numbers::pi, 15.0, 1e-9);
  EXPECT_NEAR(c.lasers[0].vert_offset_m, 0.0112, 1e-9);
  EXPECT_NEAR(c.lasers[15].vert_offset_m, -0.0112, 1e-9);
  EXPECT_DOUBLE_EQ(c.distance_resolution_m, 0.002);
  EXPECT_DOUBLE_EQ(ov::nominalCalibration(ov::Model::Vlp32C).distance_resolution_m, 0.004);
  EXPECT_EQ(ov::nominalCalibration(ov::Model::Hdl32E).lasers.size(), 32u);
}

TEST(Calibration, RingsRankLasersByElevation) {
  ov::DecoderConfig config;
  auto d = ov::PacketDecoder::create(config);
  ASSERT_TRUE(d);
  const auto& rings = d->rings();
  for (int id = 0; id < 16; ++id)
    EXPECT_EQ(rings[static_cast<std::size_t>(id)], id % 2 == 0 ? id / 2 : 8 + id / 2);
}

TEST(Calibration, ShippedXmlAndYamlFilesParseToTheSameAngles) {
  OGF_REQUIRE_SHARED_FILE(xml, "data/real/calib/VLP-16.xml");
  OGF_REQUIRE_SHARED_FILE(yaml, "data/real/calib/VLP16db.yaml");
  OGF_REQUIRE_SHARED_FILE(nebula, "data/real/calib/VLP16.yaml");
  OGF_REQUIRE_SHARED_FILE(hdl_xml, "data/real/calib/HDL-32.xml");
  OGF_REQUIRE_SHARED_FILE(hdl_yaml, "data/real/calib/32db.yaml");
  const auto a = ov::loadCalibrationFile(xml);
  const auto b = ov::loadCalibrationFile(yaml);
  const auto n = ov::loadCalibrationFile(nebula);
  ASSERT_TRUE(a) << a.error().message;
  ASSERT_TRUE(b) << b.error().message;
  ASSERT_TRUE(n) << n.error().message;
  EXPECT_EQ(a->lasers.size(), 64u);  // VeloView files always hold 64 entries
  EXPECT_EQ(b->lasers.size(), 16u);
  EXPECT_DOUBLE_EQ(a->distance_resolution_m, 0.002);
  for (std::size_t i = 0; i < 16; ++i) {
    EXPECT_NEAR(a->lasers[i].vert_correction_rad, b->lasers[i].vert_correction_rad, 1e-7);
    EXPECT_NEAR(n->lasers[i].vert_correction_rad, b->lasers[i].vert_correction_rad, 1e-7);
  }
  const auto c = ov::loadCalibrationFile(hdl_xml);
  const auto d = ov::loadCalibrationFile(hdl_yaml);
  ASSERT_TRUE(c) << c.error().message;
  ASSERT_TRUE(d) << d.error().message;
  for (std::size_t i = 0; i < 32; ++i)
    EXPECT_NEAR(c->lasers[i].vert_correction_rad, d->lasers[i].vert_correction_rad, 1e-6);
  EXPECT_NEAR(c->lasers[0].vert_correction_rad * 180 / std::numbers::pi, -30.67, 1e-5);
}

TEST(Calibration, XmlUnitsAreCentimetresAndDegrees) {
  const char* text = R"(<boost_serialization><DB><distLSB_>0.2</distLSB_>
<points_><count>1</count>
<item><px><id_>0</id_><rotCorrection_>-1.5</rotCorrection_><vertCorrection_>-15</vertCorrection_>
<distCorrection_>120</distCorrection_><vertOffsetCorrection_>20.5</vertOffsetCorrection_>
<horizOffsetCorrection_>2.6</horizOffsetCorrection_></px></item>
</points_></DB></boost_serialization>)";
  const auto c = ov::parseVeloViewXmlCalibration(text, "x.xml");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_DOUBLE_EQ(c->lasers[0].dist_correction_m, 1.2);
  EXPECT_DOUBLE_EQ(c->lasers[0].vert_offset_m, 0.205);
  EXPECT_DOUBLE_EQ(c->lasers[0].horiz_offset_m, 0.026);
  EXPECT_NEAR(c->lasers[0].rot_correction_rad, -1.5 * std::numbers::pi / 180, 1e-12);
}

TEST(Calibration, MalformedYamlNamesTheLineAndField) {
  const char* text =
      "lasers:\n"
      "- {laser_id: 0, vert_correction: -0.26}\n"
      "- {laser_id: 1, vert_correction: abc}\n"
      "num_lasers: 2\n";
  const auto c = ov::parseRosYamlCalibration(text, "bad.yaml");
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find("bad.yaml:3"), std::string::npos) << c.error().message;
  EXPECT_NE(c.error().message.find("vert_correction"), std::string::npos) << c.error().message;
}

TEST(Calibration, YamlWithMissingFieldOrDuplicateIdIsRefused) {
  const auto missing = ov::parseRosYamlCalibration("lasers:\n- {laser_id: 0}\n", "m.yaml");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("m.yaml:2: field 'vert_correction': missing"), std::string::npos)
      << missing.error().message;
  const auto dup = ov::parseRosYamlCalibration(
      "lasers:\n- {laser_id: 0, vert_correction: 0.1}\n- {laser_id: 0, vert_correction: 0.2}\n", "d.yaml");
  ASSERT_FALSE(dup);
  EXPECT_NE(dup.error().message.find("laser_id"), std::string::npos);
  const auto degrees =
      ov::parseRosYamlCalibration("lasers:\n- {laser_id: 0, vert_correction: -15}\n", "g.yaml");
  ASSERT_FALSE(degrees);
  const auto count = ov::parseRosYamlCalibration(
      "lasers:\n- {laser_id: 0, vert_correction: 0.1}\nnum_lasers: 16\n", "n.yaml");
  ASSERT_FALSE(count);
  EXPECT_NE(count.error().message.find("n.yaml:3: field 'num_lasers'"), std::string::npos)
      << count.error().message;
  const auto syntax = ov::parseRosYamlCalibration("lasers: [\n", "s.yaml");
  ASSERT_FALSE(syntax);
  EXPECT_NE(syntax.error().message.find("s.yaml:"), std::string::npos);
}

TEST(Calibration, MalformedXmlNamesTheLineAndField) {
  const char* text =
      "<DB>\n<points_>\n<item><px><id_>0</id_>\n<vertCorrection_>1x</vertCorrection_>\n</px></item>\n</"
      "points_></DB>\n";
  const auto c = ov::parseVeloViewXmlCalibration(text, "bad.xml");
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find("bad.xml:4: field 'vertCorrection_'"), std::string::npos)
      << c.error().message;
  const auto none = ov::parseVeloViewXmlCalibration("<DB></DB>", "empty.xml");
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().message.find("points_"), std::string::npos);
  const auto gap = ov::parseVeloViewXmlCalibration(
      "<points_><px><id_>1</id_><vertCorrection_>1</vertCorrection_></px></points_>", "gap.xml");
  ASSERT_FALSE(gap);
  EXPECT_NE(gap.error().message.find("laser id 0 missing"), std::string::npos) << gap.error().message;
}

TEST(Calibration, TooFewLasersForTheModelIsRefused) {
  ov::DecoderConfig config;
  config.model = ov::Model::Hdl32E;
  config.calibration = ov::nominalCalibration(ov::Model::Vlp16);
  const auto d = ov::PacketDecoder::create(config);
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().message.find("needs 32"), std::string::npos) << d.error().message;
}

TEST(Calibration, MissingFileIsReportedWithItsPath) {
  const auto c = ov::loadCalibrationFile("/nonexistent/calib.yaml");
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find("/nonexistent/calib.yaml"), std::string::npos);
}
