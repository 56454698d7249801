// Real data: the first 2000 laser records of the Intel Research Lab log (../shared/data/slam), with a few
// particles, scored with the benchmark's relations inside that span, beat raw odometry clearly. The slice
// is that long because Intel's odometry is good for its first ~1500 records (0.017 m over 166 relations)
// and first fails after them (0.21 ± 1.2 m over the 246 relations of 2000 records).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <ogf/slam_io/relations.hpp>

#include "ogf/slam2d/slam_log.hpp"
#include "ogf/slam2d/slam_run.hpp"
#include "support/shared_data.hpp"

namespace ogf::slam2d {
namespace {

slam_io::RelationMetric score(const SlamLog& log, const std::vector<slam::Pose2>& poses,
                              const std::vector<slam_io::Relation>& relations) {
  std::vector<slam_io::StampedPose> traj;
  for (std::size_t i = 0; i < log.lasers.size(); ++i)
    traj.push_back({log.lasers[i].stamp.ipc_timestamp, toLogPose(poses[i])});
  std::stable_sort(traj.begin(), traj.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
  // Only relations whose two stamps both lie in the slice.
  const double t0 = traj.front().t, t1 = traj.back().t;
  std::vector<slam_io::Relation> inside;
  for (const auto& r : relations) {
    if (r.t1 >= t0 && r.t1 <= t1 && r.t2 >= t0 && r.t2 <= t1) inside.push_back(r);
  }
  return slam_io::evaluateRelations(traj, inside);
}

TEST(IntelSlice, RbpfWithFewParticlesBeatsRawOdometry) {
  OGF_REQUIRE_SHARED_FILE(clf, "data/slam/intel.clf");
  OGF_REQUIRE_SHARED_FILE(rel, "data/slam/intel.relations");
  std::ifstream in(clf);
  const SlamLog log = readSlamLog(in, clf.string(), 2000);
  ASSERT_EQ(log.lasers.size(), 2000U);
  std::ifstream rin(rel);
  auto relations = slam_io::readRelations(rin, rel.string());
  ASSERT_TRUE(relations.ok()) << relations.error().message;

  slam::PoseCorrectorConfig config;
  config.slam.particles = 5;
  auto run = runSlam(log, OdometrySource::kLaserRecords, config);
  ASSERT_TRUE(run.ok()) << run.error().message;
  const auto odometry = score(log, run->odometry, *relations);
  const auto slam = score(log, run->corrected, *relations);
  ASSERT_GT(slam.translation.count, 30U);
  EXPECT_EQ(slam.unmatched, 0U);
  RecordProperty("odometry_trans_m", std::to_string(odometry.translation.mean));
  RecordProperty("rbpf_trans_m", std::to_string(slam.translation.mean));
  EXPECT_LT(slam.translation.mean, 0.5 * odometry.translation.mean)
      << "odometry " << odometry.translation.mean << " m, rbpf " << slam.translation.mean << " m";
  EXPECT_LT(slam.rotation_deg.mean, odometry.rotation_deg.mean);
}

}  // namespace
}  // namespace ogf::slam2d
