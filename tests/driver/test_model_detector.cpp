// Model detection: configuration wins, the product byte decides except 0x21, which the packet period
// resolves (HDL-32E or early VLP-16 firmware).
#include <gtest/gtest.h>

#include "ogf/velodyne/model_detector.hpp"

namespace ov = ogf::velodyne;

TEST(ModelDetector, ConfigurationWinsOverTheProductByte) {
  ov::ModelDetector d(ov::Model::Vlp32C);
  EXPECT_EQ(d.observe(0x22, 0x37, 0), ov::Model::Vlp32C);
}

TEST(ModelDetector, UnambiguousProductBytesDecideAtOnce) {
  EXPECT_EQ(ov::ModelDetector().observe(0x22, 0x37, 0), ov::Model::Vlp16);
  EXPECT_EQ(ov::ModelDetector().observe(0x24, 0x37, 0), ov::Model::Vlp16HiRes);
  EXPECT_EQ(ov::ModelDetector().observe(0x28, 0x39, 0), ov::Model::Vlp32C);
  ov::ModelDetector unknown;
  for (int i = 0; i < 40; ++i)
    EXPECT_EQ(unknown.observe(0x63, 0x37, static_cast<std::uint32_t>(i * 1000)), std::nullopt);
}

TEST(ModelDetector, Product0x21IsResolvedByThePacketPeriod) {
  ov::ModelDetector vlp16;
  EXPECT_EQ(vlp16.observe(0x21, 0x37, 1000), std::nullopt);
  EXPECT_EQ(vlp16.observe(0x21, 0x37, 2327), ov::Model::Vlp16);  // 1327 us
  ov::ModelDetector hdl;
  EXPECT_EQ(hdl.observe(0x21, 0x37, 1000), std::nullopt);
  EXPECT_EQ(hdl.observe(0x21, 0x37, 1553), ov::Model::Hdl32E);  // 553 us
  ov::ModelDetector dual;
  EXPECT_EQ(dual.observe(0x21, 0x39, 1000), std::nullopt);
  EXPECT_EQ(dual.observe(0x21, 0x39, 1664), ov::Model::Vlp16);  // 663.5 us: a dual VLP-16
}

TEST(ModelDetector, Undecided0x21FallsBackToTheProductByte) {
  ov::ModelDetector d;
  std::optional<ov::Model> m;
  // Every gap is a lost-packet multiple: never one period.
  for (int i = 0; i < ov::ModelDetector::kMaxPackets; ++i)
    m = d.observe(0x21, 0x37, static_cast<std::uint32_t>(i * 5000));
  EXPECT_EQ(m, ov::Model::Hdl32E);
}
