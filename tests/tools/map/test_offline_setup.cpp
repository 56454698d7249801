// ogf-map's steps as library functions: the request's checks, the run made ready from the request and the
// --config file (which setting wins, which combinations are refused), the exports' lines and the closing
// line.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "ogf/map_io/map_exports.hpp"
#include "ogf/map_io/map_request.hpp"
#include "ogf/map_io/offline_report.hpp"
#include "ogf/map_io/offline_setup.hpp"
#include "scratch_dir.hpp"
#include "wall_mapping.hpp"

namespace {

using namespace ogf;
using map_io::MapRequest;
using map_io::OfflineConfig;

MapRequest pcapRequest() {
  MapRequest r;
  r.pcap = "capture.pcap";
  r.out = "map.ogfm";
  r.given.out = true;
  return r;
}

// A --config file's content as readOfflineConfig leaves it.
OfflineConfig fileSetting(const std::string& key) {
  OfflineConfig c;
  c.keys_read.push_back(key);
  return c;
}

TEST(MapRequestCheck, MappingNeedsAnInputAnOutAndRawPacketsForCalib) {
  MapRequest r = pcapRequest();
  EXPECT_TRUE(map_io::checkMappingRequest(r).ok());
  r.given.out = false;
  ASSERT_FALSE(map_io::checkMappingRequest(r).ok());
  EXPECT_EQ(map_io::checkMappingRequest(r).error().message, "--out is required when mapping");
  MapRequest pcd;
  pcd.pcd = {"a.pcd"};
  pcd.given.out = pcd.given.calib = true;
  ASSERT_FALSE(map_io::checkMappingRequest(pcd).ok());
  EXPECT_NE(map_io::checkMappingRequest(pcd).error().message.find("--calib applies to raw packets"),
            std::string::npos);
  ASSERT_FALSE(map_io::checkMappingRequest(MapRequest{}).ok());
  EXPECT_NE(map_io::checkMappingRequest(MapRequest{}).error().message.find("no input"), std::string::npos);
}

TEST(MapRequestCheck, AMissingInputFileIsNamedByItsFlag) {
  MapRequest r = pcapRequest();
  r.odometry = "/nonexistent/odometry.csv";
  r.pcap.clear();
  const auto st = map_io::checkInputFilesExist(r);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().message, "--odometry: /nonexistent/odometry.csv: no such file");
}

TEST(OfflineSetup, TheClockIsTheFlagsThenTheFilesThenHostForABag) {
  MapRequest bag;
  bag.rosbag2 = "bag";
  EXPECT_EQ(map_io::chooseTimeBase(bag, nullptr), map_io::TimeBase::kHost);
  EXPECT_EQ(map_io::chooseTimeBase(pcapRequest(), nullptr), map_io::TimeBase::kAuto);
  OfflineConfig file = fileSetting("time_base");
  file.options.time_base = map_io::TimeBase::kDevice;
  EXPECT_EQ(map_io::chooseTimeBase(bag, &file), map_io::TimeBase::kDevice);
  bag.time_base = "auto";
  bag.given.time_base = true;
  EXPECT_EQ(map_io::chooseTimeBase(bag, &file), map_io::TimeBase::kAuto);
}

TEST(OfflineSetup, AStaticPoseSourceInTheFileHoldsTheSensorUnlessTheOdometryIsNamed) {
  OfflineConfig file = fileSetting("pose_source");
  file.options.pose_source = mapper_daemon::PoseSource::kStatic;
  auto held = map_io::prepareOfflineMapping(pcapRequest(), &file);
  ASSERT_TRUE(held.ok()) << held.error().message;
  EXPECT_TRUE(held->is_static);
  MapRequest moving = pcapRequest();
  moving.odometry = "odometry.csv";
  moving.given.odometry = true;
  auto moved = map_io::prepareOfflineMapping(moving, &file);
  ASSERT_TRUE(moved.ok()) << moved.error().message;
  EXPECT_FALSE(moved->is_static);
  const auto refused = map_io::prepareOfflineMapping(pcapRequest(), nullptr);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().message, "--pcap needs --odometry FILE or --static");
}

TEST(OfflineSetup, ResolutionFlagOverridesTheFileOnlyWhenGiven) {
  OfflineConfig file = fileSetting("map.resolution");
  file.options.map.setResolution(0.3);
  MapRequest r = pcapRequest();
  r.is_static = true;
  auto from_file = map_io::prepareOfflineMapping(r, &file);
  ASSERT_TRUE(from_file.ok()) << from_file.error().message;
  EXPECT_DOUBLE_EQ(from_file->mapping.mapper().config().fusion.measurement.resolution_m, 0.3);
  r.resolution = 0.25;
  r.given.resolution = true;
  auto from_flag = map_io::prepareOfflineMapping(r, &file);
  ASSERT_TRUE(from_flag.ok()) << from_flag.error().message;
  EXPECT_DOUBLE_EQ(from_flag->mapping.mapper().config().fusion.measurement.resolution_m, 0.25);
  // Without a file the flag's value applies, given or not.
  auto no_file = map_io::prepareOfflineMapping(r, nullptr);
  ASSERT_TRUE(no_file.ok());
  EXPECT_DOUBLE_EQ(no_file->mapping.mapper().config().fusion.measurement.resolution_m, 0.25);
}

TEST(OfflineSetup, PoseCorrectionNeedsAMovingSensorAndCorrectedOutNeedsACorrection) {
  MapRequest r = pcapRequest();
  r.is_static = true;
  r.pose_correction = "scan-match";
  r.given.pose_correction = true;
  const auto still = map_io::prepareOfflineMapping(r, nullptr);
  ASSERT_FALSE(still.ok());
  EXPECT_NE(still.error().message.find("--pose-correction needs a moving sensor"), std::string::npos);
  r.pose_correction = "sideways";
  const auto unknown = map_io::prepareOfflineMapping(r, nullptr);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().message.rfind("--pose-correction: ", 0), 0U) << unknown.error().message;
  MapRequest plain = pcapRequest();
  plain.is_static = true;
  plain.corrected_out = "poses.csv";
  const auto uncorrected = map_io::prepareOfflineMapping(plain, nullptr);
  ASSERT_FALSE(uncorrected.ok());
  EXPECT_EQ(uncorrected.error().message, "--corrected-out needs --pose-correction scan-match or rbpf");
  MapRequest moving = pcapRequest();
  moving.odometry = "odometry.csv";
  moving.pose_correction = "scan-match";
  moving.given.pose_correction = true;
  const auto corrected = map_io::prepareOfflineMapping(moving, nullptr);
  ASSERT_TRUE(corrected.ok()) << corrected.error().message;
  EXPECT_EQ(corrected->pose_correction, "scan-match");
}

TEST(MapExportsWrite, EachExportIsWrittenInItsFolderAndAFailureIsNamedByItsFlag) {
  const ogf::testing::ScratchDir dir;
  const auto run = ogf::testing::wallMapping();
  map_io::MapExports e;
  e.csv = (dir / "sub/cells.csv").string();
  e.ply = "/proc/no-such-dir/cells.ply";
  const auto notes = map_io::writeMapExports(run.mapper().filter(), e);
  EXPECT_TRUE(std::filesystem::is_regular_file(e.csv));
  ASSERT_EQ(notes.size(), 1U);
  EXPECT_TRUE(notes[0].failed);
  EXPECT_EQ(notes[0].text.rfind("--export-ply: ", 0), 0U) << notes[0].text;
  e = {};
  e.bt = (dir / "map.bt").string();
  const auto bt = map_io::writeMapExports(run.mapper().filter(), e);
  ASSERT_EQ(bt.size(), 1U);
  EXPECT_FALSE(bt[0].failed);
  EXPECT_NE(bt[0].text.find("occupied and"), std::string::npos) << bt[0].text;
}

TEST(OfflineReport, SummaryLineCarriesTheCountsAndTheFiltersChecksumInHex) {
  const auto run = ogf::testing::wallMapping();
  const auto& filter = run.mapper().filter();
  EXPECT_EQ(map_io::mapSummaryLine(run.counts(), filter, 1.234),
            fmt::format("scans 3 measurements {} cells {} seconds 1.23 checksum {:016x}",
                        run.counts().measurements, filter.allocatedCells(), filter.checksum()));
  EXPECT_GT(run.counts().measurements, 0);
}

}  // namespace
