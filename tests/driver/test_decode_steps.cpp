// ogf-decode's steps as library functions (ogf::decode, tools/lib/decode): the decoder's settings from the
// flags, a real capture's datagrams sorted by port into the decoder, and the lines the program prints.
#include <gtest/gtest.h>

#include <string>

#include "ogf/decode/decode_report.hpp"
#include "ogf/decode/recorded_packets.hpp"
#include "ogf/decode/stream_settings.hpp"
#include "support/shared_data.hpp"

namespace {

using namespace ogf;

TEST(DecodeStreamSettings, AnUnknownModelIsRefusedNamingTheFlagAndTheKnownModels) {
  decode::StreamSettings s;
  s.model_name = "VLP-99";
  const auto config = decode::streamConfig(s);
  ASSERT_FALSE(config.ok());
  EXPECT_EQ(config.error().message,
            "--model: unknown model 'VLP-99' (VLP-16, VLP-16-HiRes, VLP-32C, HDL-32E)");
}

TEST(DecodeStreamSettings, ModelReturnModeRangesAndCutAngleReachTheDecoder) {
  decode::StreamSettings s;
  s.model_name = "VLP-16";
  s.return_mode_name = "last";
  s.min_range_m = 1.5;
  s.max_range_m = 42.0;
  s.cut_angle_deg = 90.0;
  const auto config = decode::streamConfig(s);
  ASSERT_TRUE(config.ok()) << config.error().message;
  EXPECT_EQ(config->model, velodyne::Model::Vlp16);
  EXPECT_EQ(config->return_mode, velodyne::ReturnMode::Last);
  EXPECT_FALSE(config->calibration.has_value());
  EXPECT_DOUBLE_EQ(config->min_range_m, 1.5);
  EXPECT_DOUBLE_EQ(config->max_range_m, 42.0);
  EXPECT_DOUBLE_EQ(config->assembler.cut_angle_deg, 90.0);
}

TEST(DecodeStreamSettings, AnUnreadableCalibrationIsRefusedNamingTheFlag) {
  decode::StreamSettings s;
  s.calib_path = "/nonexistent/calibration.xml";
  const auto config = decode::streamConfig(s);
  ASSERT_FALSE(config.ok());
  EXPECT_EQ(config.error().message.rfind("--calib: ", 0), 0U) << config.error().message;
}

TEST(DecodeReport, CalibrationNoteSaysWhichAnglesThePointsWereComputedWith) {
  EXPECT_EQ(decode::calibrationNote("vlp16.xml", velodyne::Model::Vlp16), "calibration: vlp16.xml (--calib)");
  EXPECT_EQ(
      decode::calibrationNote("", velodyne::Model::Hdl32E),
      "calibration: the nominal HDL-32E table, built in (no --calib; give the sensor's own file for its "
      "exact angles)");
  EXPECT_EQ(decode::calibrationNote("", std::nullopt),
            "calibration: none: no data packet told the sensor model");
}

// Decodes the real VLP-16 capture with `ports`; the totals line after it.
std::string decodeCapture(const std::filesystem::path& pcap, const decode::Ports& ports,
                          decode::FeedCounts& fed) {
  auto stream = velodyne::PacketStream::create(*decode::streamConfig({}));
  EXPECT_TRUE(stream.ok());
  decode::ScanTotals totals;
  stream->setScanSink([&](const velodyne::Scan& scan) { totals.add(scan); });
  auto counts = decode::feedPcap(pcap, ports, *stream);
  EXPECT_TRUE(counts.ok());
  stream->finish();
  fed = *counts;
  return decode::totalsLine(*stream, totals, fed);
}

TEST(RecordedPackets, DatagramsGoToTheDecoderByPortAndOthersAreOnlyCounted) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  decode::FeedCounts fed;
  const std::string decoded = decodeCapture(pcap, {}, fed);
  EXPECT_EQ(fed.other_ports, 0);
  EXPECT_TRUE(fed.warnings.empty());
  EXPECT_EQ(decoded.rfind("total scans 52 points 700400 packets 1902 lost 0 ", 0), 0U) << decoded;
  EXPECT_NE(decoded.find(" other_port 0 fragments 0 cut_short 0 model VLP-16 return_mode strongest"),
            std::string::npos)
      << decoded;
  // Nothing on port 9999: every data packet is counted as another port's, none decoded.
  const std::string elsewhere = decodeCapture(pcap, {9999, 8308}, fed);
  EXPECT_EQ(fed.other_ports, 1902);
  EXPECT_EQ(elsewhere.rfind("total scans 0 points 0 packets 0 lost 0 ", 0), 0U) << elsewhere;
}

TEST(RecordedPackets, AMissingCaptureIsAnError) {
  auto stream = velodyne::PacketStream::create(*decode::streamConfig({}));
  ASSERT_TRUE(stream.ok());
  EXPECT_FALSE(decode::feedPcap("/nonexistent/capture.pcap", {}, *stream).ok());
}

}  // namespace
