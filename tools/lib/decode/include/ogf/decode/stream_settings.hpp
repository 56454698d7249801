// ogf-decode's decoder settings from its flags: the model (default: detected from the packets), the return
// mode (default: each packet's own), the calibration file (default: the model's nominal table), the range
// window and the azimuth where scans are cut.
#pragma once

#include <ogf/common/result.hpp>
#include <string>

#include "ogf/velodyne/packet_stream.hpp"

namespace ogf::decode {

struct StreamSettings {
  std::string model_name;        // --model; empty: detected
  std::string return_mode_name;  // --return-mode: strongest, last or dual; empty: each packet's
  std::string calib_path;        // --calib; empty: the nominal table
  double min_range_m = 0.4, max_range_m = 250.0;
  double cut_angle_deg = 0.0;
};

// The decoder's configuration; the error names the flag ("--model: unknown model 'X' (...)", "--calib: ...").
Result<velodyne::StreamConfig> streamConfig(const StreamSettings& settings);

}  // namespace ogf::decode
