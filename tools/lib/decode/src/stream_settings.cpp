#include "ogf/decode/stream_settings.hpp"

#include <utility>

#include "ogf/velodyne/calibration.hpp"

namespace ogf::decode {

Result<velodyne::StreamConfig> streamConfig(const StreamSettings& s) {
  velodyne::StreamConfig config;
  if (!s.model_name.empty()) {
    config.model = velodyne::parseModelName(s.model_name);
    if (!config.model)
      return Error{"--model: unknown model '" + s.model_name + "' (VLP-16, VLP-16-HiRes, VLP-32C, HDL-32E)"};
  }
  if (!s.return_mode_name.empty()) config.return_mode = velodyne::parseReturnModeName(s.return_mode_name);
  if (!s.calib_path.empty()) {
    auto calib = velodyne::loadCalibrationFile(s.calib_path);
    if (!calib) return Error{"--calib: " + calib.error().message};
    config.calibration = std::move(*calib);
  }
  config.min_range_m = s.min_range_m;
  config.max_range_m = s.max_range_m;
  config.assembler.cut_angle_deg = s.cut_angle_deg;
  return config;
}

}  // namespace ogf::decode
