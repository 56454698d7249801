// A static capture's maps and their scores: see static_capture.hpp.
#include "ogf/eval/static_capture.hpp"

#include <ogf/fusion/measurement_set.hpp>

#include <algorithm>

#include "ogf/eval/map_estimate.hpp"

namespace ogf::eval {

Result<StaticCapture> readStaticCapture(const std::filesystem::path& pcap, const std::string& calib,
                                        const pipeline::MapperConfig& config) {
  map_io::PcapScanConfig pc;
  pc.min_range_m = config.fusion.measurement.min_range_m;
  if (!calib.empty()) pc.calibration = calib;
  const Eigen::Isometry3d body_from_sensor = config.fusion.extrinsic.bodyFromSensor();
  StaticCapture capture;
  capture.origin = body_from_sensor.translation();
  auto read = map_io::readPcapScans(pcap, pc, [&](const map_io::ScanRecord& scan) {
    std::vector<Eigen::Vector3d> points(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i)
      points[i] = body_from_sensor * Eigen::Vector3d(scan.x[i], scan.y[i], scan.z[i]);
    capture.scans.push_back(std::move(points));
  });
  if (!read) return read.error();
  capture.counts = std::move(*read);
  return capture;
}

Result<StaticMaps> buildStaticMaps(const StaticCapture& capture, const pipeline::MapperConfig& config,
                                   const RaySelection& keep) {
  const auto& m = config.fusion.measurement;
  auto mapper = pipeline::ScanMapper::create(config);
  if (!mapper) return Error{"configuration: " + mapper.error().message};
  StaticMaps maps{std::move(*mapper), OctomapBaseline(m.resolution_m), {}};
  fusion::MeasurementSet set(m);
  std::vector<Eigen::Vector3d> origins, points, cloud;
  for (std::size_t s = 0; s < capture.scans.size(); ++s) {
    const auto& scan = capture.scans[s];
    points.clear();
    cloud.clear();
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!keep(static_cast<std::int64_t>(s), i)) continue;
      points.push_back(scan[i]);
      if ((scan[i] - capture.origin).norm() >= m.min_range_m) cloud.push_back(scan[i]);
    }
    origins.assign(points.size(), capture.origin);
    const auto ms = set.build(origins, points);
    for (const auto& x : ms) maps.measured.insert(x.key);
    maps.ogf.apply(ms);
    maps.octo.insertCloud(cloud, capture.origin, m.max_range_m);
  }
  maps.octo.finish();
  return maps;
}

ReturnRange scoredReturnRange(const fusion::MeasurementConfig& measurement) {
  return {std::max(measurement.min_range_m + 0.1, 0.5), measurement.max_range_m - 1.0};
}

std::vector<ReturnScores> scoreOwnReturns(const StaticCapture& capture, const StaticMaps& maps, double resolution,
                                          const ReturnRange& range) {
  ReturnScorer ogf_returns(resolution, range.from_m, range.to_m), octo_returns(resolution, range.from_m, range.to_m);
  for (const auto& scan : capture.scans) {
    for (const auto& p : scan) {
      ogf_returns.add(capture.origin, p, [&](const CellKey& k) { return ogfEstimate(maps.ogf.filter(), k); });
      octo_returns.add(capture.origin, p, [&](const CellKey& k) { return maps.octo.estimate(k); });
    }
  }
  return {ogf_returns.scores(), octo_returns.scores()};
}

std::vector<HeldOutScores> scoreHeldOutReturns(const StaticCapture& capture, const StaticMaps& kept,
                                               const HeldOutSplit& split, const fusion::MeasurementConfig& m) {
  HeldOutScorer ogf_held(m.resolution_m, m.min_range_m, m.max_range_m),
      octo_held(m.resolution_m, m.min_range_m, m.max_range_m);
  const auto seen = [&](const CellKey& k) { return kept.measured.contains(k); };
  for (std::size_t s = 0; s < capture.scans.size(); ++s) {
    for (std::size_t i = 0; i < capture.scans[s].size(); ++i) {
      if (!split.heldOut(static_cast<std::int64_t>(s), i)) continue;
      const auto& p = capture.scans[s][i];
      ogf_held.add(capture.origin, p, [&](const CellKey& k) { return ogfEstimate(kept.ogf.filter(), k); }, seen);
      octo_held.add(capture.origin, p, [&](const CellKey& k) { return kept.octo.estimate(k); }, seen);
    }
  }
  return {ogf_held.scores(), octo_held.scores()};
}

}  // namespace ogf::eval
