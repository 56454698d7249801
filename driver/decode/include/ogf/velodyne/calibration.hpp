// Per-laser calibration: the built-in nominal tables of each model and the two file formats users have,
// VeloView XML (boost serialization, lengths in cm, angles in degrees) and ROS YAML
// (velodyne_pointcloud/params/*.yaml, metres and radians). A malformed file is refused with its line and
// field.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "ogf/velodyne/model.hpp"
#include "ogf/common/result.hpp"

namespace ogf::velodyne {

struct LaserCorrection {
  double rot_correction_rad = 0.0;   // subtracted from the azimuth (ros rawdata.cc, vd unpackPoint)
  double vert_correction_rad = 0.0;  // elevation of the beam
  double dist_correction_m = 0.0;    // added to the measured distance
  double vert_offset_m = 0.0;        // height of the beam origin
  double horiz_offset_m = 0.0;       // sideways offset of the beam origin
};

struct Calibration {
  std::vector<LaserCorrection> lasers;  // index = laser id; files may hold more than the model uses
  double distance_resolution_m = 0.002;
  std::string source;  // "nominal VLP-16" or the file path
};

// The nominal table of a model: VLP-16 angles -15..+15 interleaved with the per-laser vertical offsets
// of ros2 params/VLP16db.yaml (PR #518); Hi-Res angles and offsets (vd calib_db.cpp); HDL-32E and
// VLP-32C angles (vd calib_db.cpp; VLP-32C with its azimuth offsets).
Calibration nominalCalibration(Model model);

// `source` names the text in error messages ("VLP16db.yaml"): "VLP16db.yaml:12: field
// 'vert_correction': not a number".
Result<Calibration> parseRosYamlCalibration(std::string_view text, std::string_view source);
Result<Calibration> parseVeloViewXmlCalibration(std::string_view text, std::string_view source);

// Reads a file and parses it as XML when it starts with '<' (after blanks), else as ROS YAML.
Result<Calibration> loadCalibrationFile(const std::filesystem::path& path);

}  // namespace ogf::velodyne
