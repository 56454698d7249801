// The paper's real-data claim (Sun et al. Sec. VI-B, Fig. 5) on a real capture: the OGF, configured as
// shipped, holds at least as many of a static VLP-16's returns in occupied cells as OctoMap built in this
// test from the same returns through liboctomap's OcTree::insertPointCloud, at 0.05, 0.1 and 0.2 m, and keeps
// the air in front of them open (≥ 0.99 of the points half-way along each ray in free cells).
#include <gtest/gtest.h>

#include <vector>

#include "ogf/eval/octomap_baseline.hpp"
#include "ogf/eval/return_scores.hpp"
#include "ogf/filter/map_queries.hpp"
#include "ogf/fusion/measurement_set.hpp"
#include "ogf/map_io/pcap_scans.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "support/shared_data.hpp"

namespace {

using ogf::eval::ReturnScores;

struct Shares {
  ReturnScores ogf;
  ReturnScores octomap;
};

Shares mapCapture(const std::vector<std::vector<Eigen::Vector3d>>& scans, double resolution) {
  ogf::pipeline::MapperConfig config;
  config.setResolution(resolution);
  auto mapper = ogf::pipeline::ScanMapper::create(config);
  EXPECT_TRUE(mapper.ok()) << (mapper.ok() ? "" : mapper.error().message);
  const auto& m = config.fusion.measurement;
  ogf::eval::OctomapBaseline octo(resolution);
  ogf::fusion::MeasurementSet set(m);
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  for (const auto& scan : scans) {
    const std::vector<Eigen::Vector3d> origins(scan.size(), origin);
    mapper->apply(set.build(origins, scan));
    octo.insertCloud(scan, origin, m.max_range_m);
  }
  octo.finish();
  ogf::eval::ReturnScorer ogfScore(resolution, m.min_range_m + 0.1, m.max_range_m - 1.0);
  ogf::eval::ReturnScorer octoScore(resolution, m.min_range_m + 0.1, m.max_range_m - 1.0);
  const auto& filter = mapper->filter();
  for (const auto& scan : scans) {
    for (const auto& p : scan) {
      ogfScore.add(origin, p, [&](const ogf::CellKey& k) {
        const auto q = ogf::filter::queryCell(filter, k);
        return ogf::eval::CellEstimate{q.occupancyClass, q.predictiveProbability};
      });
      octoScore.add(origin, p, [&](const ogf::CellKey& k) { return octo.estimate(k); });
    }
  }
  return {ogfScore.scores(), octoScore.scores()};
}

TEST(RealCaptureDensity, OgfHoldsAtLeastOctomapsShareOfTheReturns) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  OGF_REQUIRE_SHARED_FILE(calib, "data/real/calib/VLP-16.xml");
  ogf::map_io::PcapScanConfig pc;
  pc.calibration = calib;
  std::vector<std::vector<Eigen::Vector3d>> scans;
  const auto read = ogf::map_io::readPcapScans(pcap, pc, [&](const ogf::map_io::ScanRecord& scan) {
    std::vector<Eigen::Vector3d> points(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) points[i] = Eigen::Vector3d(scan.x[i], scan.y[i], scan.z[i]);
    scans.push_back(std::move(points));
  });
  ASSERT_TRUE(read.ok()) << read.error().message;
  ASSERT_GE(scans.size(), 40u);
  for (const double resolution : {0.2, 0.1, 0.05}) {
    const Shares s = mapCapture(scans, resolution);
    SCOPED_TRACE(testing::Message() << "resolution " << resolution << " m: returns in occupied cells OGF "
                                    << s.ogf.occupied << ", OctoMap " << s.octomap.occupied
                                    << "; half-way points free OGF " << s.ogf.halfway_free);
    EXPECT_GT(s.ogf.returns, 100000);
    EXPECT_EQ(s.ogf.returns, s.octomap.returns);
    EXPECT_GE(s.ogf.occupied, s.octomap.occupied);
    EXPECT_GE(s.ogf.halfway_free, 0.99);
  }
}

}  // namespace
