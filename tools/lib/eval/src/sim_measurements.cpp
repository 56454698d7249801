// Recomputing a simulator run's measurements: see sim_measurements.hpp.
#include "ogf/eval/sim_measurements.hpp"

#include <ogf/fusion/pose_buffer.hpp>
#include <ogf/fusion/deskew.hpp>
#include <ogf/fusion/measurement_set.hpp>
#include <ogf/pipeline/scan_mapper.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>

#include "ogf/map_io/odometry_clock.hpp"
#include "ogf/map_io/odometry_file.hpp"
#include "ogf/map_io/pcap_scans.hpp"

namespace ogf::eval {

Result<fusion::ExtrinsicConfig> readSimExtrinsic(const std::filesystem::path& sim_dir) {
  const auto path = sim_dir / "sim.yaml";
  try {
    const YAML::Node root = YAML::LoadFile(path.string());
    const YAML::Node s2b = root["sensor_to_body"];
    if (!s2b || !s2b["xyz"] || !s2b["quaternion_wxyz"])
      return Error{path.string() + ": sensor_to_body: expected {xyz: [x, y, z], quaternion_wxyz: [w, x, y, z]}"};
    const YAML::Node xyz = s2b["xyz"];
    const YAML::Node q = s2b["quaternion_wxyz"];
    if (!xyz.IsSequence() || xyz.size() != 3 || !q.IsSequence() || q.size() != 4)
      return Error{path.string() + ": sensor_to_body: xyz needs 3 numbers and quaternion_wxyz 4"};
    fusion::ExtrinsicConfig e;
    e.translation_m = {xyz[0].as<double>(), xyz[1].as<double>(), xyz[2].as<double>()};
    e.quaternion = Eigen::Quaterniond(q[0].as<double>(), q[1].as<double>(), q[2].as<double>(), q[3].as<double>());
    return e;
  } catch (const YAML::Exception& ex) {
    return Error{path.string() + ": " + ex.what()};
  }
}

Result<SimMeasurementCounts> replaySimRays(const std::filesystem::path& sim_dir, const pipeline::MapperConfig& config,
                                           const RayVisitor& visit, map_io::TimeBase time_base) {
  auto odometry = map_io::readOdometry(sim_dir / "odometry.csv");
  if (!odometry) return Error{odometry.error().message};
  fusion::PoseBufferConfig pb = config.fusion.pose_buffer;
  pb.capacity = std::max<std::size_t>(odometry->poses.size(), 2);
  fusion::PoseBuffer poses(pb);
  for (const auto& p : odometry->poses) poses.insert(p);

  fusion::Deskew deskew(config.fusion.extrinsic.bodyFromSensor());
  std::vector<Eigen::Vector3d> origins, endpoints;
  SimMeasurementCounts counts;
  map_io::PcapScanConfig pc;
  pc.min_range_m = config.fusion.measurement.min_range_m;
  auto read = map_io::readPcapScans(sim_dir / "capture.pcap", pc, [&](const map_io::ScanRecord& scan) {
    const std::int64_t index = counts.scans++;
    if (deskew.place(scan.points(time_base), poses, origins, endpoints) != fusion::PoseCoverage::kCovered) {
      if (counts.clock_mismatch.empty()) {
        if (const auto mismatch = map_io::clockMismatch(scan, time_base, poses))
          counts.clock_mismatch = mismatch->describe("--time");
      }
      return;
    }
    ++counts.scans_measured;
    visit(index, origins, endpoints);
  });
  if (!read) return Error{read.error().message};
  return counts;
}

Result<SimMeasurementCounts> replaySimMeasurements(const std::filesystem::path& sim_dir,
                                                   const pipeline::MapperConfig& config,
                                                   const std::function<void(std::span<const Measurement>)>& visit,
                                                   map_io::TimeBase time_base) {
  fusion::MeasurementSet set(config.fusion.measurement);
  std::int64_t measurements = 0;
  auto counts = replaySimRays(sim_dir, config, [&](std::int64_t, std::span<const Eigen::Vector3d> origins,
                                                   std::span<const Eigen::Vector3d> endpoints) {
    const auto ms = set.build(origins, endpoints);
    measurements += static_cast<std::int64_t>(ms.size());
    visit(ms);
  }, time_base);
  if (!counts) return counts.error();
  counts->measurements = measurements;
  return counts;
}

}  // namespace ogf::eval
