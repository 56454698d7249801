// Everything ogf-mapper is configured with: the bus and channels, the map (through MapperConfig), the
// state directory and the timers. The offline programs that map (ogf-map, ogf-eval) read the same file
// with the same reader: one schema (config_schema.cpp) declares every key once, with its type, default,
// unit, meaning, check and place in MapperOptions, and drives the YAML reader, --print-config and the
// table of keys in docs/configuration.md. Read from a YAML file (unknown keys are refused, so a typo never silently falls
// back to a default), then overridden by flags, then validated as a whole.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/common/result.hpp"
#include "ogf/correction/scan_pose_correction.hpp"
#include "ogf/mapper_daemon/source_options.hpp"
#include "ogf/navigation/nav_band.hpp"
#include "ogf/pipeline/mapper_config.hpp"

namespace ogf::mapper_daemon {

using adapters::ScanTimeBase;

// Where the body's pose comes from: the odometry on the pose channel, or one fixed pose from the
// configuration (a sensor on a mast or a bench: infrastructure lidars, tests).
enum class PoseSource { kOdometry, kStatic };

// The map services (OGF_MAP_QUERY, OGF_MAP_COMMAND): the `services:` section.
struct ServicesOptions {
  // Commands (save, reset, export) are refused unless enabled, and then need a MAC with the key in key_file
  // (command_auth.hpp); the mapper refuses to start when the file is missing, not a regular file, or
  // readable by the group or others.
  bool commands_enabled = false;
  std::filesystem::path key_file;
  // Exports go only here; empty = <state_dir>/exports (no export without either).
  std::filesystem::path export_dir;
  // An export is refused when its size bound (map_export.hpp) would leave less than this free.
  std::uint64_t export_min_free_bytes = 1024ULL * 1024 * 1024;
  // A box query over more cells is refused before any of the map is read or paged in.
  std::int64_t max_query_cells = 4'000'000;
  // Service work between two scans on the mapping thread: queries and commands are served until this
  // is spent (at least one step: one command, one cells query, or one chunk of a box), the rest wait.
  double budget_ms_per_scan = 10.0;
  // Cells of a box query summarised in one step (a box is answered over several scans when larger).
  std::int64_t box_chunk_cells = 100'000;

  // The export directory in force for `state_dir` (empty when none).
  std::filesystem::path exportDirFor(const std::filesystem::path& state_dir) const;
};

// OGF_MAP_DELTA's publishing rule and byte budget: the `deltas:` section (delta/publishing_rule.hpp,
// delta/link_budget.hpp).
struct DeltaOptions {
  // A cell goes out when its class changes, or its probability moves this far from the value last
  // published (0: any change of the quantised probability), or (when > 0) its variance by this fraction
  // of the published one.
  double probability_step = 0.02;
  double variance_step = 0.0;
  // Encoded bytes per second of the delta channel, keyframes included (0: unbounded); what a scan's
  // changes need beyond it waits for later updates. 2 MB/s leaves room on a Wi-Fi link of a few MB/s.
  std::int64_t max_bytes_per_s = 2'000'000;
  // The most the channel sends at once after a quiet spell, in seconds of the rate.
  double burst_s = 0.25;
  // The most cells that wait for the rate, in seconds of it (1 s at 2 MB/s: about 105 k cells, some
  // 20 MB); a change beyond them marks its 8 × 8 slab stale, read again from the map once they drain.
  double max_wait_s = 1.0;
};

// The 2-D navigation grid (mapper/navigation): the `nav:` section. The band is also what ogf-map --export-nav
// projects.
struct NavOptions {
  bool enabled = true;  // publish the grid on channels.nav_grid
  navigation::NavBand band;
  // Changed tiles go out at most this often (the changes of the scans between accumulate).
  double update_interval_s = 0.5;
  // The whole grid goes out unasked this often (and on request, on channels.nav_request).
  double keyframe_interval_s = 5.0;
};

struct MapperOptions {
  std::string lcm_url;  // "" = $LCM_DEFAULT_URL, else LCM's default
  std::string scan_channel = "VELODYNE_SCAN";
  std::string pose_channel = "POSE";
  std::string delta_channel = "OGF_MAP_DELTA";
  std::string request_channel = "OGF_MAP_REQUEST";
  std::string status_channel = "OGF_MAPPER_STATUS";
  std::string corrected_pose_channel = "POSE_CORRECTED";  // published only when pose correction is on
  // Map services; each answers on its channel + "_REPLY".
  std::string query_channel = "OGF_MAP_QUERY";
  std::string command_channel = "OGF_MAP_COMMAND";
  std::string nav_grid_channel = "OGF_NAV_GRID";
  std::string nav_request_channel = "OGF_NAV_REQUEST";
  // Which scan clock the odometry's utime shares: the sensor's device time (GPS/PPS or top-of-hour +
  // host hour) or the driver host's receive time.
  ScanTimeBase time_base = ScanTimeBase::kAuto;
  PoseSource pose_source = PoseSource::kOdometry;
  // With pose_source kStatic: the body in the map frame (the extrinsic still places the sensor on the
  // body); identity by default.
  fusion::ExtrinsicConfig static_pose;

  // Several lidars, several robots (source_options.hpp); empty: one source on scan_channel and pose_channel,
  // timed by time_base and placed by map.fusion.extrinsic.
  std::vector<SourceOptions> sources;

  pipeline::MapperConfig map;
  // The optional stage between odometry and the OGF: none, scan-match or rbpf.
  correction::ScanPoseCorrectionConfig pose_correction;

  // Where snapshots and the journal live; empty = $STATE_DIRECTORY when set (systemd), else the map in
  // memory only (main.cpp resolves it).
  std::filesystem::path state_dir;
  // A restart replays the journal since the last snapshot (about 50 ms a scan at 0.2 m): 20 s of scans at
  // 10 Hz restart in about 10 s (docs/performance.md, "Restart after a crash").
  double snapshot_interval_s = 20.0;
  // Regions of the map farther than this from the sensor move to <state_dir>/pages and come back when a
  // scan reaches them again (0 = keep the whole map in memory). Needs a state directory.
  double page_out_distance_m = 60.0;
  double keyframe_interval_s = 30.0;
  DeltaOptions deltas;
  NavOptions nav;
  double status_interval_s = 1.0;
  ServicesOptions services;

  // Fault injection for tests: drop this fraction of delta updates before publishing (0 = never).
  double test_drop_delta_fraction = 0.0;
  // The same for the navigation grid's updates (keyframes always go out).
  double test_drop_nav_fraction = 0.0;
  std::uint32_t test_seed = 1;

  Status validate() const;
};

// The programs a configuration key matters to (a bit each); the others accept the key and ignore it.
enum ConfigUser : unsigned {
  kUsedByMapper = 1U,  // ogf-mapper
  kUsedByMap = 2U,     // ogf-map
  kUsedByEval = 4U,    // ogf-eval
};

// Reads a YAML file into `options` (keys not in the file keep their values). Errors name the file, the
// line and the key; a key spelt another way (a top-level `resolution`, `filter.kernel_sigma`) is refused
// naming the key to use. `keys_read`, when given, receives the path of every key the file set
// ("map.resolution", "channels.scan").
Status loadMapperOptions(const std::filesystem::path& path, MapperOptions& options,
                         std::vector<std::string>* keys_read = nullptr);

// The same from YAML text; `path` only names the source in errors.
Status parseMapperOptions(const std::string& yaml, const std::filesystem::path& path, MapperOptions& options,
                          std::vector<std::string>* keys_read = nullptr);

// The programs (ConfigUser bits) that use the key at `path`, a path loadMapperOptions reported; 0 for a
// path that is no key.
unsigned configKeyUsers(std::string_view path);

// Every key as YAML with the values in `options` (the defaults for MapperOptions{}), one comment a key
// with its unit and meaning; reading it back gives `options` again. Printed by --print-config.
std::string mapperConfigYaml(const MapperOptions& options = MapperOptions{});

// The table of keys in Markdown (key, type, default, programs, meaning): the table in docs/configuration.md,
// printed by --print-config=markdown.
std::string mapperConfigMarkdown();

}  // namespace ogf::mapper_daemon
