// A real capture of a sensor that did not move, scored without ground truth: both maps (the OGF through the
// mapping pipeline, OctoMap through its own OcTree::insertPointCloud) are built from its returns with the
// sensor at the extrinsic's origin, then asked how they hold those returns (return_scores.hpp); with a
// held-out split, built again from the kept rays and asked about the held-out ones (held_out.hpp).
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/core/cell_key.hpp>
#include <ogf/map_io/pcap_scans.hpp>
#include <ogf/pipeline/mapper_config.hpp>
#include <ogf/pipeline/scan_mapper.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <unordered_set>
#include <vector>

#include "ogf/eval/held_out.hpp"
#include "ogf/eval/octomap_baseline.hpp"
#include "ogf/eval/return_scores.hpp"

namespace ogf::eval {

struct StaticCapture {
  std::vector<std::vector<Eigen::Vector3d>> scans;  // each scan's points in the body frame
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the sensor in the body frame
  map_io::PcapScanCounts counts;                    // what reading the capture found
};

// The capture's scans, decoded with `calib` (empty: the built-in table) and moved into the body frame by
// `config`'s extrinsic; points closer than its min range are dropped by the reader.
Result<StaticCapture> readStaticCapture(const std::filesystem::path& pcap, const std::string& calib,
                                        const pipeline::MapperConfig& config);

struct StaticMaps {
  pipeline::ScanMapper ogf;
  OctomapBaseline octo;
  std::unordered_set<CellKey, CellKeyHash> measured;  // cells the OGF's measurements named
};

// Both maps from the rays `keep(scan, ray)` accepts; an error when `config` makes no mapper.
using RaySelection = std::function<bool(std::int64_t scan, std::size_t ray)>;
Result<StaticMaps> buildStaticMaps(const StaticCapture& capture, const pipeline::MapperConfig& config,
                                   const RaySelection& keep);

// The range of returns scored: 0.1 m beyond min range (at least 0.5 m) to 1 m short of max range, inside
// the mapped range with a margin.
struct ReturnRange {
  double from_m = 0.0;
  double to_m = 0.0;
};
ReturnRange scoredReturnRange(const fusion::MeasurementConfig& measurement);

// How the OGF and the OctoMap (in that order) hold every return of the capture within `range`.
std::vector<ReturnScores> scoreOwnReturns(const StaticCapture& capture, const StaticMaps& maps, double resolution,
                                          const ReturnRange& range);

// The OGF and the OctoMap (in that order) built from the kept rays, asked about the held-out ones.
std::vector<HeldOutScores> scoreHeldOutReturns(const StaticCapture& capture, const StaticMaps& kept,
                                               const HeldOutSplit& split, const fusion::MeasurementConfig& measurement);

}  // namespace ogf::eval
