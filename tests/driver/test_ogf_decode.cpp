// ogf-decode as a program: its output line format, CSV header and rows, PLY header, range flags, and the
// errors it reports for bad flags and files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "support/child_process.hpp"
#include "support/shared_data.hpp"

using ogf::testing::ChildProcess;

namespace {

struct DecodeRun {
  int exit_code;
  std::string output;
};

DecodeRun decode(const std::vector<std::string>& args) {
  std::vector<std::string> argv{OGF_DECODE_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  const std::string log =
      (std::filesystem::temp_directory_path() / ("ogf-decode-" + std::to_string(::getpid()) + ".out"))
          .string();
  ChildProcess p(argv, log);
  const auto code = p.wait(std::chrono::seconds(60));
  return {code.value_or(-999), p.log()};
}

std::string temp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "-" + name)).string();
}

}  // namespace

TEST(OgfDecode, PrintsOneLinePerScanThenTotals) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  const DecodeRun r = decode({"--pcap", pcap.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::regex line("^scan (\\d+) points (\\d+) packets (\\d+) lost (\\d+)$");
  std::istringstream in(r.output);
  std::string l;
  int scans = 0;
  bool totals = false;
  while (std::getline(in, l)) {
    std::smatch m;
    if (std::regex_match(l, m, line)) {
      EXPECT_EQ(std::stoi(m[1]), scans);
      ++scans;
    } else if (l.rfind("total scans 52 ", 0) == 0) {
      totals = true;
      EXPECT_NE(l.find("packets 1902"), std::string::npos) << l;
      EXPECT_NE(l.find("model VLP-16"), std::string::npos) << l;
    }
  }
  EXPECT_EQ(scans, 52);
  EXPECT_TRUE(totals) << r.output;
}

TEST(OgfDecode, CsvHasTheHeaderAndEveryPointWithinTheRangeFlags) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  const std::string csv = temp("points.csv");
  const DecodeRun r = decode({"--pcap", pcap.string(), "--csv", csv, "--min-range", "0", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "scan,x,y,z,intensity,ring,laser_id,azimuth_deg,distance_m,time_s,return_type");
  std::string row;
  std::int64_t rows = 0, short_range = 0;
  while (std::getline(in, row)) {
    ++rows;
    std::istringstream fields(row);
    std::string f;
    std::vector<std::string> v;
    while (std::getline(fields, f, ',')) v.push_back(f);
    ASSERT_EQ(v.size(), 11u) << row;
    const double distance = std::stod(v[8]);
    EXPECT_GT(distance, 0.0);
    short_range += distance < 0.9;
    EXPECT_GE(std::stod(v[9]), 0.0);
    EXPECT_EQ(v[10], "strongest");
  }
  EXPECT_EQ(rows, 700400);
  // A short-range scene: --min-range 0 keeps the returns closer than the 0.9 m the ROS driver drops.
  EXPECT_GT(short_range, 100000);
  std::filesystem::remove(csv);
}

TEST(OgfDecode, TruncatedCaptureIsReportedAndDecodedUpToTheDamage) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/sampleShort.pcap");
  const DecodeRun r = decode({"--pcap", pcap.string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("truncated"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("total scans 5 "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("packets 291 "), std::string::npos) << r.output;
}

TEST(OgfDecode, PlyIsBinaryWithTheVertexCount) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/derived/nebula_vlp16_dual_1673400471837873222.DERIVED.pcap");
  const std::string ply = temp("points.ply");
  const DecodeRun r =
      decode({"--pcap", pcap.string(), "--ply", ply, "--min-range", "1", "--max-range", "50"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(ply, std::ios::binary);
  std::string first, format, l;
  std::getline(in, first);
  std::getline(in, format);
  EXPECT_EQ(first, "ply");
  EXPECT_EQ(format, "format binary_little_endian 1.0");
  std::int64_t vertices = -1;
  while (std::getline(in, l) && l != "end_header")
    if (l.rfind("element vertex ", 0) == 0) vertices = std::stoll(l.substr(15));
  const auto body_start = in.tellg();
  in.seekg(0, std::ios::end);
  // Per vertex: 5 floats, 2 ushorts, 1 uint, 1 uchar = 29 bytes.
  EXPECT_EQ(static_cast<std::int64_t>(in.tellg() - body_start), vertices * 29);
  EXPECT_GT(vertices, 10000);
  std::filesystem::remove(ply);
}

TEST(OgfDecode, BadFlagsAndBadFilesFailWithAMessage) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/sampleShort.pcap");
  const DecodeRun model = decode({"--pcap", pcap.string(), "--model", "HDL-64E"});
  EXPECT_NE(model.exit_code, 0);
  EXPECT_NE(model.output.find("--model"), std::string::npos) << model.output;
  const std::string calib = temp("bad.yaml");
  std::ofstream(calib) << "lasers:\n- {laser_id: 0, vert_correction: nope}\n";
  const DecodeRun bad_calib = decode({"--pcap", pcap.string(), "--calib", calib});
  EXPECT_NE(bad_calib.exit_code, 0);
  EXPECT_NE(bad_calib.output.find(":2: field 'vert_correction'"), std::string::npos) << bad_calib.output;
  std::filesystem::remove(calib);
  const DecodeRun missing = decode({"--pcap", "/nonexistent.pcap"});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("/nonexistent.pcap"), std::string::npos);
  const DecodeRun range = decode({"--pcap", pcap.string(), "--min-range", "5", "--max-range", "1"});
  EXPECT_NE(range.exit_code, 0);
}

TEST(OgfDecode, HelpDocumentsTheCsvTimeBase) {
  const DecodeRun r = decode({"--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("RELATIVE TO THE SCAN START"), std::string::npos);
}

// Without --calib the points come from the model's nominal table: the output says so, and names the file
// when one is given, so a forgotten --calib is never silent.
TEST(OgfDecode, NamesTheCalibrationItDecodedWith) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  OGF_REQUIRE_SHARED_FILE(calib, "data/real/calib/VLP-16.xml");
  const DecodeRun nominal = decode({"--pcap", pcap.string(), "--quiet"});
  ASSERT_EQ(nominal.exit_code, 0) << nominal.output;
  EXPECT_NE(nominal.output.find("calibration: the nominal VLP-16 table, built in (no --calib;"), std::string::npos)
      << nominal.output;
  const DecodeRun file = decode({"--pcap", pcap.string(), "--calib", calib.string(), "--quiet"});
  ASSERT_EQ(file.exit_code, 0) << file.output;
  EXPECT_NE(file.output.find("calibration: " + calib.string() + " (--calib)"), std::string::npos) << file.output;
  EXPECT_EQ(file.output.find("nominal"), std::string::npos) << file.output;
}
