// The measurements a simulator run gives, recomputed offline: the run's capture decoded with the driver's
// reader and decoder (ogf_map_io's readPcapScans), each scan deskewed with the run's odometry and ray cast
// into one measurement per cell (pipeline::ScanMapper::measure, the daemon's own code, without the filter).
// ogf-eval uses them twice: the cells where a ray ended (for the gap-filling score) and, fed to OctoMap,
// the baseline built from exactly the same rays as the OGF.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/core/measurement.hpp>
#include <ogf/map_io/scan_record.hpp>
#include <ogf/pipeline/mapper_config.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>

namespace ogf::eval {

struct SimMeasurementCounts {
  std::int64_t scans = 0;           // decoded from the capture
  std::int64_t scans_measured = 0;  // covered by the odometry
  std::int64_t measurements = 0;
  // When the first scan the odometry left out lies on another clock than the odometry: its times, the
  // offset and the fix: time_base, ogf-eval's --time (map_io::clockMismatch); "" else.
  std::string clock_mismatch;
};

// The extrinsic (sensor -> body) ogf-sim wrote into DIR/sim.yaml (`sensor_to_body: {xyz: [..],
// quaternion_wxyz: [..]}`); an error naming the file and key when missing or malformed.
Result<fusion::ExtrinsicConfig> readSimExtrinsic(const std::filesystem::path& sim_dir);

// The rays of every scan the odometry covers, deskewed as the mapper places them (origin and endpoint per
// point, odometry frame), handed to `visit` with the scan's number in capture order. Each scan is timed on
// the clock `time_base` names (ogf-mapper's rule for auto).
using RayVisitor = std::function<void(std::int64_t scan, std::span<const Eigen::Vector3d> origins,
                                      std::span<const Eigen::Vector3d> endpoints)>;
Result<SimMeasurementCounts> replaySimRays(const std::filesystem::path& sim_dir, const pipeline::MapperConfig& config,
                                           const RayVisitor& visit,
                                           map_io::TimeBase time_base = map_io::TimeBase::kAuto);

// Replays DIR/capture.pcap with DIR/odometry.csv through `config`'s measurement pipeline, handing each
// scan's measurements to `visit` in capture order.
Result<SimMeasurementCounts> replaySimMeasurements(const std::filesystem::path& sim_dir,
                                                   const pipeline::MapperConfig& config,
                                                   const std::function<void(std::span<const Measurement>)>& visit,
                                                   map_io::TimeBase time_base = map_io::TimeBase::kAuto);

}  // namespace ogf::eval
