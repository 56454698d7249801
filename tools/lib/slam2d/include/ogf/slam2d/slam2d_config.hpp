// ogf-slam2d's corrector configuration from its flags: the mode (none, scan-match, rbpf); in scan-match
// mode the scan-matching preset (GridFastSlamConfig::scanMatching) for the flags the command line did not
// give; two-step sampling; the matcher's usable range equal to the map update's.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/slam/pose_corrector.hpp>
#include <string>

namespace ogf::slam2d {

// The flags whose scan-match preset a given flag overrides.
struct PresetFlagsGiven {
  bool linear_update = false, angular_update = false, unmatched_distance = false;
  bool heading_starts = false, heading_start_step = false;
};

// `config` as the flags set it, completed and validated; the error names the flag ("--mode: ...") or says
// "configuration: ...".
Result<slam::PoseCorrectorConfig> slam2dConfig(slam::PoseCorrectorConfig config, const std::string& mode,
                                               const PresetFlagsGiven& given, bool two_step_sampling);

}  // namespace ogf::slam2d
