// ogf-map's --config file (YAML): the mapping settings in one place, applied on top of the defaults, with
// the command-line flags applied after it. Unknown keys are errors (a misspelt key silently ignored is a
// map made with the wrong settings); every error names the file, the line and the key.
//
//   resolution: 0.2            # metres per cell (fusion and filter share it)
//   min_range: 0.4             # metres
//   max_range: 30.0            # metres; farther returns give free cells only
//   free_space_for_no_return: false
//   extrinsic:                 # sensor -> body
//     translation: [0, 0, 0]   # metres
//     rpy: [0, 0, 0]           # radians, R = Rz(yaw) Ry(pitch) Rx(roll)
//     quaternion: [1, 0, 0, 0] # w, x, y, z; replaces rpy when given
//   filter:
//     kernel_sigma: 0.1        # metres (default resolution / 2)
//     kernel_amplitude: 3.99   # default 1 / (sigma sqrt(2 pi))
//     stencil_radius: 1.414    # cells
//     stencil_manhattan_radius: 2
//     taper_support: 2.0       # cells
//     occupied_threshold: 0.65
//     free_threshold: 0.35
//     skip_tolerance: 1e-4
//     clamp_z: 3.0             # skip measurements agreeing with a cell beyond this probit z (0: never)
//     free_clamp_z: 1.5        # the same for free measurements (0: clamp_z)
//     occupied_priority: map   # map: a cell once measured occupied ignores free measurements; scan: exact
//     free_release_scans: 20   # ... until this many scans in a row measure it free (0: never)
//     covariance: compact      # compact: mean and variance per cell; banded: also the covariances (exact)
//     threads: 1
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/pipeline/mapper_config.hpp>

#include <string_view>

namespace ogf::map_io {

// Whether the YAML text is ogf-mapper's configuration (it has a top-level key only the daemon's file has:
// map, fusion, channels, lcm_url, state_dir, ...) rather than this flat format. Text that is not YAML is not.
bool isMapperDaemonConfig(std::string_view yaml);

// Applies the YAML text onto `config`; `source` names it in errors ("map.yaml:3: filter.threads: ...").
Status applyMapConfigYaml(std::string_view yaml, std::string_view source, pipeline::MapperConfig& config);

}  // namespace ogf::map_io
