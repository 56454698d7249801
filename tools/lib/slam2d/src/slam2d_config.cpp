#include "ogf/slam2d/slam2d_config.hpp"

namespace ogf::slam2d {
namespace {

// Scan matching alone has its own defaults (GridFastSlamConfig::scanMatching); flags still win.
void applyScanMatchPreset(slam::GridFastSlamConfig& c, const PresetFlagsGiven& given) {
  const slam::GridFastSlamConfig preset = slam::GridFastSlamConfig::scanMatching();
  if (!given.linear_update) c.linear_update_m = preset.linear_update_m;
  if (!given.angular_update) c.angular_update_rad = preset.angular_update_rad;
  if (!given.unmatched_distance) c.matcher.unmatched_distance_m = preset.matcher.unmatched_distance_m;
  if (!given.heading_starts) c.matcher.heading_starts = preset.matcher.heading_starts;
  if (!given.heading_start_step) c.matcher.heading_start_step_rad = preset.matcher.heading_start_step_rad;
}

}  // namespace

Result<slam::PoseCorrectorConfig> slam2dConfig(slam::PoseCorrectorConfig config, const std::string& mode,
                                               const PresetFlagsGiven& given, bool two_step_sampling) {
  const auto parsed = slam::parseCorrectionMode(mode);
  if (!parsed) return Error{"--mode: " + parsed.error().message};
  config.mode = *parsed;
  if (config.mode == slam::CorrectionMode::kScanMatch) applyScanMatchPreset(config.slam, given);
  config.slam.two_step_sampling = two_step_sampling;
  config.slam.matcher.usable_range_m = config.slam.map_update.usable_range_m;
  if (auto s = config.validate(); !s) return Error{"configuration: " + s.error().message};
  return config;
}

}  // namespace ogf::slam2d
