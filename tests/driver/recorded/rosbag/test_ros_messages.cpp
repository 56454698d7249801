// The CDR reader and the ROS message decoders: primitives in both byte orders with CDR's alignment,
// messages written here decode back to the same values, and truncated or damaged messages give an error
// naming the byte and the field, never a crash or a read out of bounds.
#include <gtest/gtest.h>

#include <numeric>
#include <random>

#include "bag_writer.hpp"
#include "ogf/rosbag/cdr_reader.hpp"
#include "ogf/rosbag/ros_messages.hpp"

namespace {

using namespace ogf::rosbag;
using ogf::testing::CdrWriter;

OdometryMessage sampleOdometry() {
  OdometryMessage m;
  m.header = {{1673400471, 837873222}, "odom"};
  m.child_frame_id = "base_link";
  m.position = {1.25, -3.5, 0.125};
  m.orientation = {0.0, 0.0, 0.38268343236508978, 0.92387953251128674};
  std::iota(m.pose_covariance.begin(), m.pose_covariance.end(), 0.5);
  m.linear_velocity = {0.7, 0.0, 0.0};
  m.angular_velocity = {0.0, 0.0, 0.1};
  std::iota(m.twist_covariance.begin(), m.twist_covariance.end(), -10.0);
  return m;
}

TfMessage sampleTf() {
  TfMessage tf;
  tf.transforms.push_back({{{100, 5000}, "odom"}, "base_link", {1, 2, 3}, {0, 0, 0, 1}});
  tf.transforms.push_back({{{100, 5000}, "base_link"}, "velodyne", {0.2, 0, 0.8}, {0.5, 0.5, 0.5, 0.5}});
  return tf;
}

std::vector<std::uint8_t> packetBytes(std::uint8_t seed) {
  std::vector<std::uint8_t> p(kVelodynePacketBytes);
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = static_cast<std::uint8_t>(seed + i * 7);
  return p;
}

TEST(CdrReader, ReadsPrimitivesAlignedFromTheEndOfTheHeaderInBothByteOrders) {
  for (bool big : {false, true}) {
    CdrWriter w(big);
    w.u8(7);
    w.u32(0xDEADBEEF);  // 3 padding bytes before it
    w.u8(1);
    w.f64(-2.5);  // 7 padding bytes before it
    w.string("velodyne");
    w.i32(-42);
    auto r = CdrReader::open(w.bytes());
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r->bigEndian(), big);
    std::uint8_t a = 0, b = 0;
    std::uint32_t u = 0;
    double d = 0;
    std::string s;
    std::int32_t i = 0;
    EXPECT_TRUE(r->u8(a, "a") && r->u32(u, "u") && r->u8(b, "b") && r->f64(d, "d") && r->string(s, "s") &&
                r->i32(i, "i"))
        << r->error();
    EXPECT_EQ(a, 7);
    EXPECT_EQ(u, 0xDEADBEEFU);
    EXPECT_EQ(b, 1);
    EXPECT_EQ(d, -2.5);
    EXPECT_EQ(s, "velodyne");
    EXPECT_EQ(i, -42);
    EXPECT_EQ(r->offset(), 4 + 24 + 4 + 9 + 3 + 4U);
    EXPECT_EQ(r->remaining(), 0U);
  }
}

TEST(CdrReader, RefusesOtherEncapsulationsAndShortHeaders) {
  const std::vector<std::uint8_t> xcdr2{0x00, 0x07, 0, 0, 1, 2, 3, 4};
  auto r = CdrReader::open(xcdr2);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("00 07"), std::string::npos) << r.error().message;
  const std::vector<std::uint8_t> short_header{0x00, 0x01};
  EXPECT_FALSE(CdrReader::open(short_header));
}

TEST(CdrReader, ErrorNamesTheByteAndFieldAndLaterReadsFail) {
  CdrWriter w;
  w.u32(5);
  auto r = CdrReader::open(w.bytes());
  ASSERT_TRUE(r);
  std::uint32_t u = 0;
  double d = 0;
  EXPECT_TRUE(r->u32(u, "first"));
  EXPECT_FALSE(r->f64(d, "second"));
  EXPECT_EQ(r->error(), "byte 8 (second): needs 12 bytes, 0 left");
  EXPECT_FALSE(r->u32(u, "third"));
  EXPECT_EQ(r->error(), "byte 8 (second): needs 12 bytes, 0 left");  // the first failure is kept
}

TEST(CdrReader, RefusesSequenceLengthsTheBytesCannotHold) {
  CdrWriter w;
  w.u32(0xFFFFFFFF);
  w.u32(0);
  auto r = CdrReader::open(w.bytes());
  ASSERT_TRUE(r);
  std::uint32_t n = 0;
  EXPECT_FALSE(r->sequenceLength(n, 1, "packets"));
  EXPECT_NE(r->error().find("4294967295 elements"), std::string::npos) << r->error();
}

TEST(CdrReader, RefusesStringsWithoutTheirNulOrLongerThanTheMessage) {
  CdrWriter w;
  w.u32(3);
  w.octets(std::vector<std::uint8_t>{'a', 'b', 'c'});
  auto r = CdrReader::open(w.bytes());
  std::string s;
  EXPECT_FALSE(r->string(s, "frame_id"));
  EXPECT_NE(r->error().find("does not end with NUL"), std::string::npos) << r->error();
  CdrWriter w2;
  w2.u32(1000);
  w2.u8(0);
  auto r2 = CdrReader::open(w2.bytes());
  EXPECT_FALSE(r2->string(s, "frame_id"));
  EXPECT_NE(r2->error().find("string of 1000 bytes, 1 left"), std::string::npos) << r2->error();
}

TEST(RosMessages, OdometryDecodesToTheValuesWrittenInBothByteOrders) {
  const OdometryMessage in = sampleOdometry();
  for (bool big : {false, true}) {
    auto out = decodeOdometry(ogf::testing::encodeOdometry(in, big));
    ASSERT_TRUE(out) << out.error().message;
    EXPECT_EQ(out->header.stamp.sec, in.header.stamp.sec);
    EXPECT_EQ(out->header.stamp.nanosec, in.header.stamp.nanosec);
    EXPECT_EQ(out->header.frame_id, "odom");
    EXPECT_EQ(out->child_frame_id, "base_link");
    EXPECT_EQ(out->position.x, in.position.x);
    EXPECT_EQ(out->position.y, in.position.y);
    EXPECT_EQ(out->position.z, in.position.z);
    EXPECT_EQ(out->orientation.z, in.orientation.z);
    EXPECT_EQ(out->orientation.w, in.orientation.w);
    EXPECT_EQ(out->pose_covariance, in.pose_covariance);
    EXPECT_EQ(out->angular_velocity.z, 0.1);
    EXPECT_EQ(out->twist_covariance, in.twist_covariance);
  }
}

TEST(RosMessages, TfMessageDecodesEveryTransform) {
  auto out = decodeTfMessage(ogf::testing::encodeTfMessage(sampleTf()));
  ASSERT_TRUE(out) << out.error().message;
  ASSERT_EQ(out->transforms.size(), 2U);
  EXPECT_EQ(out->transforms[0].header.frame_id, "odom");
  EXPECT_EQ(out->transforms[0].child_frame_id, "base_link");
  EXPECT_EQ(out->transforms[0].translation.z, 3.0);
  EXPECT_EQ(out->transforms[1].child_frame_id, "velodyne");
  EXPECT_EQ(out->transforms[1].rotation.x, 0.5);
  EXPECT_EQ(out->transforms[1].header.stamp.nanosec, 5000U);
}

TEST(RosMessages, VelodyneScanPacketsViewTheExactPayloadBytes) {
  const auto a = packetBytes(1), b = packetBytes(2);
  VelodyneScanMessage in;
  in.header = {{10, 20}, "velodyne"};
  in.packets = {{{10, 999'999'500}, a}, {{11, 1}, b}};
  const auto bytes = ogf::testing::encodeVelodyneScan(in);
  auto out = decodeVelodyneScan(bytes);
  ASSERT_TRUE(out) << out.error().message;
  ASSERT_EQ(out->packets.size(), 2U);
  EXPECT_TRUE(std::equal(a.begin(), a.end(), out->packets[0].data.begin(), out->packets[0].data.end()));
  EXPECT_TRUE(std::equal(b.begin(), b.end(), out->packets[1].data.begin(), out->packets[1].data.end()));
  EXPECT_EQ(out->packets[0].stamp.utime(), 11'000'000);  // 10.9999995 s rounds up to the microsecond
  EXPECT_EQ(out->packets[1].stamp.utime(), 11'000'000);
}

TEST(RosMessages, RosTimeRoundsToTheNearestMicrosecond) {
  EXPECT_EQ((RosTime{1, 1499}).utime(), 1'000'001);
  EXPECT_EQ((RosTime{1, 1500}).utime(), 1'000'002);
  EXPECT_EQ((RosTime{-1, 0}).utime(), -1'000'000);
  EXPECT_EQ((RosTime{-1, 999'999'400}).utime(), -1);
}

// Every prefix of a valid message is an error naming a byte; random damage never crashes.
template <class Decode>
void expectDamageIsAnError(const std::vector<std::uint8_t>& valid, Decode decode) {
  ASSERT_TRUE(decode(std::span<const std::uint8_t>(valid)));
  for (std::size_t n = 0; n < valid.size(); ++n) {
    const std::vector<std::uint8_t> cut(valid.begin(), valid.begin() + static_cast<std::ptrdiff_t>(n));
    auto r = decode(std::span<const std::uint8_t>(cut));
    ASSERT_FALSE(r) << "prefix of " << n << " bytes decoded";
    EXPECT_FALSE(r.error().message.empty());
    if (n >= 4) {
      EXPECT_NE(r.error().message.find("byte "), std::string::npos) << r.error().message;
    }
  }
  std::mt19937 rng(1234);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<std::uint8_t> damaged = valid;
    const int flips = 1 + trial % 4;
    for (int k = 0; k < flips; ++k) damaged[rng() % damaged.size()] = static_cast<std::uint8_t>(rng());
    damaged.resize(damaged.size() - rng() % 16);
    (void)decode(std::span<const std::uint8_t>(damaged));  // ok or an error; ASan/UBSan builds check the rest
  }
}

TEST(RosMessages, TruncatedOrDamagedOdometryIsAnErrorNeverACrash) {
  expectDamageIsAnError(ogf::testing::encodeOdometry(sampleOdometry()), decodeOdometry);
}

TEST(RosMessages, TruncatedOrDamagedTfMessageIsAnErrorNeverACrash) {
  expectDamageIsAnError(ogf::testing::encodeTfMessage(sampleTf()), decodeTfMessage);
}

TEST(RosMessages, TruncatedOrDamagedVelodyneScanIsAnErrorNeverACrash) {
  const auto a = packetBytes(3);
  VelodyneScanMessage in;
  in.header = {{10, 20}, "velodyne"};
  in.packets = {{{10, 30}, a}, {{10, 40}, a}};
  expectDamageIsAnError(ogf::testing::encodeVelodyneScan(in, true), decodeVelodyneScan);
}

TEST(RosMessages, UndecodedTopicsAreListedWithTypeAndCount) {
  const std::vector<BagTopic> topics{{"/velodyne_packets", std::string(kVelodyneScanType), "cdr", 4},
                                     {"/imu", "sensor_msgs/msg/Imu", "cdr", 12},
                                     {"/odom", std::string(kOdometryType), "cdr", 5},
                                     {"/rosout", "rcl_interfaces/msg/Log", "cdr", 1}};
  EXPECT_EQ(undecodedTopicsSummary(topics),
            "/imu (sensor_msgs/msg/Imu, 12 messages), /rosout (rcl_interfaces/msg/Log, 1 message)");
  EXPECT_EQ(undecodedTopicsSummary(std::span<const BagTopic>(topics).first(1)), "");
}

}  // namespace
