// ogf-mapper: the mapping daemon. Scans (VELODYNE_SCAN) and the robot's odometry (POSE, ogf.odometry_t or
// bot_core.pose_t; or, with --static, one fixed pose from the configuration) in; the OGF map out as deltas on OGF_MAP_DELTA, keyframes on request, status on
// OGF_MAPPER_STATUS; the map kept in a state directory so a restart resumes it.
#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>

#include "ogf/common/command_line.hpp"
#include "ogf/mapper_daemon/mapper_daemon.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/persistence/directory_lock.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/lcm_asio_bridge.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"

namespace {

using ogf::mapper_daemon::MapperOptions;

// The command line: the configuration file and the flags that override its values.
struct Flags {
  std::string config_path;
  std::string url, state_dir, time_base, log_level = "info";
  std::optional<double> resolution, max_range, min_range, snapshot_s, keyframe_s, drop_fraction, drop_nav_fraction;
  std::optional<int> threads;
  std::optional<std::string> scan_ch, pose_ch, delta_ch, request_ch, status_ch;
  bool in_memory = false;
  bool is_static = false;
  std::optional<std::string> print_config;
};

void declareFlags(CLI::App& app, Flags& f) {
  app.add_option("--config", f.config_path, "YAML configuration file (see --print-config)")->check(CLI::ExistingFile);
  app.add_option("--lcm-url", f.url, "LCM URL (default: the file's lcm_url, $LCM_DEFAULT_URL, LCM's default)");
  app.add_option("--state-dir", f.state_dir,
                 "Directory for snapshots and the journal (default: the file's state_dir, else $STATE_DIRECTORY)");
  app.add_flag("--in-memory", f.in_memory, "Keep the map in memory only, ignoring any state directory");
  app.add_option("--resolution", f.resolution, "Cell size, metres")->check(ogf::cli::positive());
  app.add_option("--min-range", f.min_range, "Returns closer than this are ignored, metres")->check(ogf::cli::nonNegative());
  app.add_option("--max-range", f.max_range, "Returns beyond are cut here (free cells only), metres")->check(ogf::cli::positive());
  app.add_option("--threads", f.threads, "Filter update threads (the map is identical for any count)")->check(ogf::cli::positive());
  app.add_option("--time-base", f.time_base, "Scan clock the odometry shares: auto (device with PPS locked, else host), device or host")
      ->check(CLI::IsMember({"auto", "device", "host"}));
  app.add_option("--snapshot-interval", f.snapshot_s, "Seconds between snapshots")->check(ogf::cli::positive());
  app.add_option("--keyframe-interval", f.keyframe_s, "Seconds between unsolicited keyframes")->check(ogf::cli::positive());
  app.add_flag("--static", f.is_static,
               "The sensor does not move (an infrastructure lidar, a bench): every scan is mapped at the file's "
               "static_pose (default: the origin), no odometry needed (pose_source: static)");
  app.add_option("--scan-channel", f.scan_ch, "Scan channel (default VELODYNE_SCAN)");
  app.add_option("--pose-channel", f.pose_ch, "Odometry channel (default POSE)");
  app.add_option("--delta-channel", f.delta_ch, "Delta channel (default OGF_MAP_DELTA)");
  app.add_option("--request-channel", f.request_ch, "Keyframe request channel (default OGF_MAP_REQUEST)");
  app.add_option("--status-channel", f.status_ch, "Status channel (default OGF_MAPPER_STATUS)");
  app.add_option("--test-drop-deltas", f.drop_fraction, "Testing: drop this fraction of delta updates (gap injection)")
      ->check(ogf::cli::between(0.0, 0.99));
  app.add_option("--test-drop-nav", f.drop_nav_fraction,
                 "Testing: drop this fraction of navigation grid updates (gap injection)")
      ->check(ogf::cli::between(0.0, 0.99));
  app.add_option("--log-level", f.log_level, "trace, debug, info, warn, error")->capture_default_str();
  app.add_option("--print-config", f.print_config,
                 "Print the configuration (every key with its value: the defaults, then --config's and the flags') "
                 "as YAML and exit; --print-config=markdown prints the table of keys instead")
      ->expected(0, 1)
      ->check(CLI::IsMember({"", "yaml", "markdown"}));
}

// The flags given override the file's values.
void applyFlags(const Flags& f, MapperOptions& options) {
  if (!f.url.empty()) options.lcm_url = f.url;
  if (!f.state_dir.empty()) options.state_dir = f.state_dir;
  if (f.is_static) options.pose_source = ogf::mapper_daemon::PoseSource::kStatic;
  if (f.resolution) options.map.setResolution(*f.resolution);
  if (f.min_range) options.map.fusion.measurement.min_range_m = *f.min_range;
  if (f.max_range) options.map.fusion.measurement.max_range_m = *f.max_range;
  if (f.threads) options.map.filter.threads = *f.threads;
  if (!f.time_base.empty())
    options.time_base = f.time_base == "host"     ? ogf::mapper_daemon::ScanTimeBase::kHost
                        : f.time_base == "device" ? ogf::mapper_daemon::ScanTimeBase::kDevice
                                                  : ogf::mapper_daemon::ScanTimeBase::kAuto;
  if (f.snapshot_s) options.snapshot_interval_s = *f.snapshot_s;
  if (f.keyframe_s) options.keyframe_interval_s = *f.keyframe_s;
  if (f.scan_ch) options.scan_channel = *f.scan_ch;
  if (f.pose_ch) options.pose_channel = *f.pose_ch;
  if (f.delta_ch) options.delta_channel = *f.delta_ch;
  if (f.request_ch) options.request_channel = *f.request_ch;
  if (f.status_ch) options.status_channel = *f.status_ch;
  if (f.drop_fraction) options.test_drop_delta_fraction = *f.drop_fraction;
  if (f.drop_nav_fraction) options.test_drop_nav_fraction = *f.drop_nav_fraction;
}

// The configuration: the defaults, then the file's values, then the flags'; the reason when invalid.
ogf::Status readOptions(const Flags& f, MapperOptions& options) {
  if (!f.config_path.empty()) {
    if (auto st = ogf::mapper_daemon::loadMapperOptions(f.config_path, options); !st) return st;
  }
  applyFlags(f, options);
  return options.validate();
}

// The state directory: the configuration's, else $STATE_DIRECTORY; none with --in-memory (said either way).
void chooseStateDirectory(const Flags& f, MapperOptions& options) {
  if (options.state_dir.empty()) {
    if (const char* sd = std::getenv("STATE_DIRECTORY"); sd != nullptr && *sd != '\0') options.state_dir = sd;
  }
  if (f.in_memory) options.state_dir.clear();
  if (options.state_dir.empty() && f.in_memory) {
    spdlog::info("--in-memory: the map lives in memory only and is lost when ogf-mapper stops");
  } else if (options.state_dir.empty()) {
    spdlog::warn("no state directory (--state-dir, state_dir in the configuration, or $STATE_DIRECTORY): the map "
                 "lives in memory only and is lost when ogf-mapper stops");
  }
}

// One mapper per state directory, for this process's whole life (the kernel releases it at exit); false
// (said) when another mapper holds it.
bool lockStateDirectory(const MapperOptions& options, std::optional<ogf::persistence::DirectoryLock>& lock) {
  if (options.state_dir.empty()) return true;
  auto l = ogf::persistence::DirectoryLock::acquire(options.state_dir);
  if (l.in_use) {
    spdlog::critical("state directory: {}", l.message);
    return false;
  }
  if (!l.lock) spdlog::warn("state directory: {}", l.message);
  lock = std::move(l.lock);
  return true;
}

// What the mapper maps, said once it runs, and systemd told it is ready.
void announce(const MapperOptions& options, const std::string& bus, ogf::transport::DaemonLoop& loop) {
  if (!options.sources.empty()) {
    const auto sources = ogf::mapper_daemon::resolveSources(options);  // validated before the daemon started
    if (!sources) return;
    std::string listed;
    for (const auto& s : *sources)
      listed += fmt::format("{}{} ({} {} of robot {}{})", listed.empty() ? "" : ", ", s.name, s.packets ? "packets on" : "scans on",
                            s.channel, s.robot,
                            options.pose_source == ogf::mapper_daemon::PoseSource::kStatic ? ", static pose"
                                                                                         : " on " + s.pose_channel);
    spdlog::info("mapping {} sources on {} at {} m: {}; deltas on {}", options.sources.size(), bus,
                 options.map.filter.resolution, listed, options.delta_channel);
    loop.ready("mapping");
    return;
  }
  if (options.pose_source == ogf::mapper_daemon::PoseSource::kStatic) {
    const Eigen::Isometry3d body = options.static_pose.bodyFromSensor();
    const Eigen::Quaterniond q(body.linear());
    spdlog::info("mapping {} with a static pose on {} at {} m; deltas on {}; the body at ({}, {}, {}) m, quaternion "
                 "(w {:.4f}, x {:.4f}, y {:.4f}, z {:.4f}) in the map frame; {} is not used",
                 options.scan_channel, bus, options.map.filter.resolution, options.delta_channel,
                 body.translation().x(), body.translation().y(), body.translation().z(), q.w(), q.x(), q.y(), q.z(),
                 options.pose_channel);
    loop.ready("mapping with a static pose");
  } else {
    spdlog::info("mapping {} + {} on {} at {} m; deltas on {}", options.scan_channel, options.pose_channel, bus,
                 options.map.filter.resolution, options.delta_channel);
    loop.ready("mapping");
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ogf-mapper: fuses lidar scans with the robot's odometry through the Occupancy Grid Filter "
               "(Sun et al. 2018) and streams the map on LCM."};
  Flags flags;
  declareFlags(app, flags);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (flags.print_config && *flags.print_config == "markdown") {
    std::cout << ogf::mapper_daemon::mapperConfigMarkdown();
    return 0;
  }
  if (!ogf::transport::setupLoggingAt("ogf-mapper", "--log-level", flags.log_level)) return ogf::cli::kExitUsage;
  MapperOptions options;
  if (auto st = readOptions(flags, options); !st) {
    spdlog::critical("configuration: {}", st.error().message);
    return ogf::cli::exitCodeFor(st.error());
  }
  if (flags.print_config) {
    // Before $STATE_DIRECTORY is looked up, so the output reads back to this configuration anywhere.
    std::cout << ogf::mapper_daemon::mapperConfigYaml(options);
    return 0;
  }
  chooseStateDirectory(flags, options);
  std::optional<ogf::persistence::DirectoryLock> lock;
  if (!lockStateDirectory(options, lock)) return ogf::cli::kExitFailure;

  const std::string bus = ogf::transport::withReceiveBuffer(ogf::transport::resolveLcmUrl(options.lcm_url));
  lcm::LCM lcm(bus);
  if (!lcm.good()) {
    spdlog::critical("cannot join the LCM bus {} (udpm needs a multicast route)", bus);
    return ogf::cli::kExitFailure;
  }
  if (const auto why = ogf::transport::receiveProblem(lcm, bus)) {
    spdlog::critical("{}", *why);
    return ogf::cli::kExitFailure;
  }
  // Map services on an instance of their own (its own socket, receive thread and queues); a provider whose
  // instances do not share one bus (memq) keeps them on the one instance.
  std::optional<lcm::LCM> service_bus;
  if (bus.rfind("udpm://", 0) == 0) {
    service_bus.emplace(bus);
    if (!service_bus->good()) {
      spdlog::critical("cannot join the LCM bus {} for the map services", bus);
      return ogf::cli::kExitFailure;
    }
    if (const auto why = ogf::transport::receiveProblem(*service_bus, bus)) {
      spdlog::critical("map services: {}", *why);
      return ogf::cli::kExitFailure;
    }
  }
  ogf::transport::DaemonLoop loop;
  ogf::transport::LcmAsioBridge bridge(loop.io(), lcm, [&loop] { loop.requestStop(ogf::cli::kExitFailure); });
  auto daemon =
      ogf::mapper_daemon::MapperDaemon::create(options, lcm, service_bus ? &*service_bus : nullptr, loop);
  if (!daemon) {
    spdlog::critical("{}", daemon.error().message);
    return ogf::cli::exitCodeFor(daemon.error());
  }
  auto& d = **daemon;
  loop.onShutdown([&d] { d.stop(); });
  loop.setHealthCheck([&d] { return d.healthy(); });
  d.start();
  announce(options, bus, loop);
  return loop.run();
}
