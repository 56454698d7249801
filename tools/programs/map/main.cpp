// ogf-map: the mapping pipeline offline, as fast as the machine allows. Scans from a PCAP (with odometry
// from a file, or a tripod), an LCM log, a ROS 2 bag (with its own poses) or PCD files go through the same
// ScanMapper the daemon runs; the result is a map file and optional CSV, PLY, OctoMap and PNG exports. This
// file owns the logs, the progress bar and the exit code (the command line is in options.cpp); the work is in
// ogf_map_io.
// --from-map exports a map made before (a map file or a daemon snapshot) without mapping.
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <functional>
#include <ogf/filter/map_file.hpp>
#include <ogf/mapper_daemon/mapper_options.hpp>
#include <ogf/transport/logging.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ogf/common/command_line.hpp"
#include "ogf/map_formats/map_loader.hpp"
#include "ogf/map_io/bag_poses.hpp"
#include "ogf/map_io/drive_report.hpp"
#include "ogf/map_io/lcm_log_scans.hpp"
#include "ogf/map_io/map_config_file.hpp"
#include "ogf/map_io/map_exports.hpp"
#include "ogf/map_io/map_request.hpp"
#include "ogf/map_io/odometry_file.hpp"
#include "ogf/map_io/offline_report.hpp"
#include "ogf/map_io/offline_setup.hpp"
#include "ogf/map_io/pcap_scans.hpp"
#include "ogf/map_io/pcd_file.hpp"
#include "ogf/rosbag/bag_packets.hpp"
#include "ogf/rosbag/ros_messages.hpp"
#include "options.hpp"

namespace {

namespace mio = ogf::map_io;
using Clock = std::chrono::steady_clock;

using ogf::cli::kExitOk;
constexpr int kExitNothingMapped = 1;  // also: an output could not be written
using ogf::cli::kExitUsage;            // bad flags or configuration
constexpr int kUncoveredWarnings = 5;  // scans described one by one; the rest only counted

// A one-line bar on stderr, redrawn at most 10 times a second, only when stderr is a terminal.
class ProgressBar {
 public:
  ProgressBar() : enabled_(isatty(STDERR_FILENO) == 1) {}
  void update(double fraction, std::int64_t scans) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (drawn_ && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    drawn_ = true;
    constexpr int kWidth = 40;
    const double f = fraction < 0.0 ? 0.0 : (fraction > 1.0 ? 1.0 : fraction);
    const int filled = static_cast<int>(f * kWidth);
    std::fprintf(stderr, "\r[%s%s] %3d%% scans %lld",
                 std::string(static_cast<std::size_t>(filled), '#').c_str(),
                 std::string(static_cast<std::size_t>(kWidth - filled), ' ').c_str(),
                 static_cast<int>(f * 100.0), static_cast<long long>(scans));
    std::fflush(stderr);
  }
  void finish() {
    if (enabled_ && drawn_) std::fprintf(stderr, "\r%s\r", std::string(70, ' ').c_str());
  }

 private:
  bool enabled_;
  bool drawn_ = false;
  Clock::time_point last_;
};

void logProblems(const std::vector<std::string>& problems, std::int64_t total) {
  for (const auto& p : problems) spdlog::warn("{}", p);
  if (total > static_cast<std::int64_t>(problems.size()))
    spdlog::warn("{} more problems like these not shown", total - static_cast<std::int64_t>(problems.size()));
}

// Hands the odometry read from `source` to the run and says what it kept.
void useOdometry(const std::string& source, const std::vector<ogf::fusion::Pose>& poses,
                 mio::OfflineMapping& run) {
  run.setOdometry(poses);
  const auto& c = run.counts();
  if (c.poses_rejected > 0)
    spdlog::warn("{}: {} poses rejected (out of order, duplicate time, NaN or not a unit quaternion)", source,
                 c.poses_rejected);
  if (const auto span = run.odometrySpan())
    spdlog::info("{}: {} poses, utime {} .. {} ({:.1f} s)", source, c.poses_accepted, span->first,
                 span->second, static_cast<double>(span->second - span->first) * 1e-6);
  else
    spdlog::warn("{}: no usable pose: every scan will be left out", source);
}

// Reads odometry into the run; false when the file cannot be read at all.
bool loadOdometry(const std::string& path, const std::string& channel, mio::OfflineMapping& run) {
  auto odo = mio::readOdometry(path, channel);
  if (!odo) {
    spdlog::error("{}", odo.error().message);
    return false;
  }
  logProblems(odo->problems, odo->skipped);
  useOdometry(path, odo->poses, run);
  return true;
}

// Logs what went wrong reading raw packets (a damaged tail, skipped messages, gaps); false when they could
// not be read at all.
bool reportPacketProblems(const ogf::Result<mio::PcapScanCounts>& counts) {
  if (!counts) {
    spdlog::error("{}", counts.error().message);
    return false;
  }
  if (!counts->warning.empty()) spdlog::warn("{}", counts->warning);
  if (!counts->gaps.empty()) spdlog::warn("{}", counts->gaps);
  spdlog::info("calibration: {}", counts->calibration);
  return true;
}

// Reads the bag's poses into the run; false when they cannot be read at all.
bool loadBagPoses(const ogf::rosbag::Rosbag2Storage& bag, const ogf::map_io::BagPoseSource& source,
                  const std::string& name, mio::OfflineMapping& run) {
  auto poses = ogf::map_io::readBagPoses(bag, source);
  if (!poses) {
    spdlog::error("{}", poses.error().message);
    return false;
  }
  logProblems(poses->problems, poses->skipped);
  spdlog::info("{}: poses of {} in {} from {} messages ({})", name,
               poses->child_frame.empty() ? "?" : poses->child_frame,
               poses->parent_frame.empty() ? "?" : poses->parent_frame, poses->messages, source.type);
  useOdometry(name, poses->poses, run);
  return true;
}

// Logs each export's line; false when one failed.
bool writeExports(const ogf::filter::BandedOgf& map, const mio::MapExports& exports) {
  bool ok = true;
  for (const auto& note : mio::writeMapExports(map, exports)) {
    if (note.failed) {
      spdlog::error("{}", note.text);
      ok = false;
    } else {
      spdlog::info("{}", note.text);
    }
  }
  return ok;
}

// Each step of a mapping run returns nullopt to go on, or the exit code ogf-map stops with (its reason
// logged).
using Stop = std::optional<int>;

// The --config file into `config` (left empty without one); its keys ogf-map does not use are said once.
Stop readConfig(const mio::MapRequest& r, std::optional<mio::OfflineConfig>& config) {
  if (r.config_path.empty()) return std::nullopt;
  auto read = mio::readOfflineConfig(r.config_path, ogf::mapper_daemon::kUsedByMap);
  if (!read) {
    spdlog::error("--config: {}", read.error().message);
    return ogf::cli::exitCodeFor(read.error());
  }
  if (const auto note = read->unusedNote("ogf-map"); !note.empty()) spdlog::info("--config: {}", note);
  config = std::move(*read);
  return std::nullopt;
}

// --from-map: the exports of a map made before (a map file or a daemon snapshot), no mapping; the --config
// file gives the navigation grid's band.
int exportMapFile(mio::MapRequest r) {
  std::optional<mio::OfflineConfig> config;
  if (const Stop stop = readConfig(r, config)) return *stop;
  if (config) r.exports.nav_band = config->options.nav.band;
  auto loaded = ogf::map_formats::loadOgfMap(r.from_map);
  if (!loaded) {
    spdlog::error("--from-map: {}", loaded.error().message);
    return kExitNothingMapped;
  }
  int rc = kExitOk;
  if (!r.out.empty()) {
    if (auto st = ogf::filter::saveMapFile(loaded->map, r.out); !st) {
      spdlog::error("--out: {}", st.error().message);
      rc = kExitNothingMapped;
    }
  }
  if (!writeExports(loaded->map, r.exports)) rc = kExitNothingMapped;
  std::printf("map %s cells %zu\n", loaded->kind == "snapshot" ? "snapshot" : "file",
              loaded->map.allocatedCells());
  return rc;
}


// A ROS 2 bag input: the bag and the topics its packets and poses are read from.
struct BagInput {
  ogf::rosbag::Rosbag2Storage bag;
  std::string packets_topic;
  std::optional<mio::BagPoseSource>
      poses;  // nullopt: the poses come from --odometry, or the sensor is static
};

// Opens the bag and chooses its topics, saying what it holds, before anything is mapped.
Stop openBag(const mio::MapRequest& r, bool is_static, std::optional<BagInput>& input) {
  auto opened = ogf::rosbag::Rosbag2Storage::open(r.rosbag2);
  if (!opened) {
    spdlog::error("--rosbag2: {}", opened.error().message);
    return kExitNothingMapped;
  }
  if (const auto found = opened->whereFound(); !found.empty()) spdlog::info("{}", found);
  if (const auto others = ogf::rosbag::undecodedTopicsSummary(opened->topics()); !others.empty())
    spdlog::info("{}: not read (types ogf does not decode): {}", r.rosbag2, others);
  auto topic = ogf::rosbag::choosePacketTopic(*opened, r.packets_topic);
  if (!topic) {
    spdlog::error("--packets-topic: {}", topic.error().message);
    return kExitUsage;
  }
  if (!*topic) {
    spdlog::error("{}: no {} topic: nothing to map", r.rosbag2, ogf::rosbag::kVelodyneScanType);
    return kExitNothingMapped;
  }
  input.emplace(BagInput{std::move(*opened), **topic, std::nullopt});
  if (is_static || !r.odometry.empty()) return std::nullopt;
  auto source = mio::choosePoseSource(input->bag, r.pose_topic, r.body_frame);
  if (!source) {
    spdlog::error("--pose-topic: {}", source.error().message);
    return kExitUsage;
  }
  if (!*source) {
    spdlog::error("{}: no {} topic and no /tf: give --pose-topic, --odometry FILE or --static", r.rosbag2,
                  ogf::rosbag::kOdometryType);
    return kExitUsage;
  }
  input->poses = **source;
  return std::nullopt;
}

// One mapping run: the request, the mapping made ready, and what reading the input leaves for the end.
struct Session {
  Session(const mio::MapRequest& r, mio::OfflineSetup s) : request(r), setup(std::move(s)) {}

  const mio::MapRequest& request;
  mio::OfflineSetup setup;
  std::optional<BagInput> bag;
  std::string odometry_source;  // named in the lines about scans it does not cover
  ProgressBar bar;
  std::optional<mio::DriveReport> report;
  int uncovered_told = 0;
  bool input_failed = false;

  mio::OfflineMapping& run() { return setup.mapping; }

  // Maps one scan, adds it to the drive report, and says (the first few times) that the odometry missed it.
  void addScan(const mio::ScanRecord& scan) {
    const auto began = Clock::now();
    const mio::ScanOutcome outcome =
        setup.is_static ? run().addStaticScan(scan, setup.static_pose) : run().addScan(scan, setup.time_base);
    if (report && outcome == mio::ScanOutcome::kMapped) {
      const auto& f = run().mapper().filter();
      report->add({scan.points(setup.time_base).start_utime,
                   std::chrono::duration<double, std::milli>(Clock::now() - began).count(), f.memoryBytes(),
                   f.allocatedCells() + run().pagedBlocks().blocks * f.cellsPerBlock()});
    }
    if (setup.is_static) return;
    if (outcome == mio::ScanOutcome::kUncovered && uncovered_told++ < kUncoveredWarnings)
      spdlog::warn("{}",
                   mio::uncoveredScanNote(scan, setup.time_base, odometry_source, run().odometrySpan()));
  }
  std::function<void(const mio::ScanRecord&)> scanSink() {
    return [this](const mio::ScanRecord& scan) { addScan(scan); };
  }
  std::function<void(double)> progress() {
    return [this](double f) { bar.update(f, run().counts().scans_in); };
  }
  const auto& measurement() const { return setup.mapping.mapper().config().fusion.measurement; }
  // The driver's decoder for raw packets, with --calib and the mapper's minimum range.
  mio::PcapScanConfig decoderConfig() const {
    mio::PcapScanConfig pc;
    if (!request.calib.empty()) pc.calibration = request.calib;
    pc.min_range_m = measurement().min_range_m;
    return pc;
  }
};

// The input files are there and a bag's topics are chosen, before anything is read.
Stop openInputs(Session& s) {
  if (auto st = mio::checkInputFilesExist(s.request); !st) {
    spdlog::error("{}", st.error().message);
    return kExitNothingMapped;
  }
  if (s.request.rosbag2.empty()) return std::nullopt;
  return openBag(s.request, s.setup.is_static, s.bag);
}

// --page-dir, and the settings line.
Stop startPaging(Session& s) {
  const auto& r = s.request;
  const auto& m = s.measurement();
  if (!r.page_dir.empty()) {
    if (auto st = s.run().setPaging(r.page_dir, r.page_out_distance); !st) {
      spdlog::error("--page-dir: {}", st.error().message);
      return kExitUsage;
    }
    const double reach = ogf::persistence::MapPager::churnDistance(m.max_range_m, m.resolution_m);
    if (r.page_out_distance < reach)
      spdlog::warn(
          "--page-out-distance {} m is within the scans' reach (max range plus two regions, {:.1f} m): "
          "regions will go out and come back scan after scan (the same map, more disk traffic)",
          r.page_out_distance, reach);
  }
  spdlog::info("resolution {} m, range {} .. {} m, filter threads {}", m.resolution_m, m.min_range_m,
               m.max_range_m, s.run().mapper().filter().config().threads);
  return std::nullopt;
}

// The odometry of a capture or an LCM log (from --odometry, else the log's POSE); false when unreadable.
bool loadLogOdometry(Session& s) {
  if (s.setup.is_static) return true;
  s.odometry_source = s.request.odometry.empty() ? s.request.lcm_log : s.request.odometry;
  return loadOdometry(s.odometry_source, s.request.pose_channel, s.run());
}

// The odometry of a bag: its own poses, or --odometry; false when unreadable.
bool loadBagOdometry(Session& s) {
  if (s.setup.is_static) return true;
  const auto& poses = s.bag->poses;
  s.odometry_source = poses ? s.request.rosbag2 + " " + poses->topic : s.request.odometry;
  return poses ? loadBagPoses(s.bag->bag, *poses, s.odometry_source, s.run())
               : loadOdometry(s.request.odometry, s.request.pose_channel, s.run());
}

void readPcap(Session& s) {
  const auto& path = s.request.pcap;
  auto counts = mio::readPcapScans(path, s.decoderConfig(), s.scanSink(), s.progress());
  if (!reportPacketProblems(counts)) {
    s.input_failed = true;
    return;
  }
  spdlog::info("{}: {} scans, {} points, {} data packets, {} lost, {} bad", path, counts->scans,
               counts->points, counts->data_packets, counts->packets_lost, counts->bad_packets);
}

// An LCM log's scans; a log of the raw packets only is decoded as the driver did live.
void readLcmLog(Session& s) {
  const auto& r = s.request;
  auto counts = mio::readLcmLogScans(r.lcm_log, r.scan_channel, s.scanSink(), s.progress());
  if (!counts) {
    spdlog::error("{}", counts.error().message);
    s.input_failed = true;
    return;
  }
  logProblems(counts->problems, counts->skipped);
  if (!counts->gaps.empty()) spdlog::warn("{}", counts->gaps);
  spdlog::info("{}: {} events, {} scans on {}", r.lcm_log, counts->events, counts->scans, r.scan_channel);
  if (counts->scans != 0) return;
  auto decoded =
      mio::readLcmLogPacketScans(r.lcm_log, r.packets_channel, s.decoderConfig(), s.scanSink(), s.progress());
  if (!reportPacketProblems(decoded)) {
    s.input_failed = true;
    return;
  }
  spdlog::info(
      "{}: no scans on {}; {} scans decoded from the packets on {} ({} data packets, {} lost, {} bad)",
      r.lcm_log, r.scan_channel, decoded->scans, r.packets_channel, decoded->data_packets,
      decoded->packets_lost, decoded->bad_packets);
}

void readBag(Session& s) {
  const auto& topic = s.bag->packets_topic;
  auto counts = mio::readRosbagPacketScans(s.bag->bag, topic, s.decoderConfig(), s.scanSink(), s.progress());
  if (!reportPacketProblems(counts)) {
    s.input_failed = true;
    return;
  }
  spdlog::info("{}: {} scans decoded from {} ({} data packets, {} lost, {} bad)", s.request.rosbag2,
               counts->scans, topic, counts->data_packets, counts->packets_lost, counts->bad_packets);
}

// Each PCD file is one scan with rays from its viewpoint; a file that cannot be read is skipped.
void readPcdFiles(Session& s) {
  const auto& files = s.request.pcd;
  const auto progress = s.progress();
  for (std::size_t i = 0; i < files.size(); ++i) {
    auto cloud = mio::readPcdFile(files[i]);
    if (!cloud) {
      spdlog::error("{}; file skipped", cloud.error().message);
      continue;
    }
    if (cloud->non_finite > 0) spdlog::info("{}: {} non-finite points dropped", files[i], cloud->non_finite);
    s.run().addCloud(cloud->viewpoint_translation, cloud->points);
    progress(static_cast<double>(i + 1) / static_cast<double>(files.size()));
  }
}

// Maps every scan of the input; stops when the odometry cannot be read.
Stop mapInput(Session& s) {
  const auto& r = s.request;
  if (r.report_every > 0.0) s.report.emplace(r.report_every, stdout);
  if (!r.pcap.empty() || !r.lcm_log.empty()) {
    if (!loadLogOdometry(s)) return kExitNothingMapped;
    if (!r.pcap.empty())
      readPcap(s);
    else
      readLcmLog(s);
  } else if (s.bag) {
    if (!loadBagOdometry(s)) return kExitNothingMapped;
    readBag(s);
  } else {
    readPcdFiles(s);
  }
  s.bar.finish();
  return std::nullopt;
}

// Says which scans were left out and why; stops when none was mapped.
Stop checkSomethingMapped(Session& s) {
  const mio::OfflineCounts& c = s.run().counts();
  if (c.scans_uncovered > 0)
    spdlog::warn("{} of {} scans not covered by the odometry of {}: left out (never extrapolated)",
                 c.scans_uncovered, c.scans_in, s.odometry_source);
  if (c.scans_empty > 0) spdlog::info("{} scans gave no measurement (no return within range)", c.scans_empty);
  // No scan covered and the scans far from the odometry: the two are on different clocks; say which
  // --time or time_base fixes it.
  const auto& mismatch = s.run().clockMismatch();
  const bool other_clocks = c.scans_mapped + c.scans_empty == 0 && mismatch.has_value();
  if (other_clocks) spdlog::warn("clocks: {}", mismatch->describe("--time"));
  if (c.scans_mapped != 0) return std::nullopt;
  spdlog::error(
      "nothing could be mapped ({} scans read{}{})", c.scans_in, s.input_failed ? ", input unreadable" : "",
      other_clocks ? "; scans and odometry are on different clocks: see the clocks line above" : "");
  return kExitNothingMapped;
}

// The map file and the exports hold the whole map: the paged-out regions come back first.
Stop bringInPagedRegions(Session& s) {
  const auto* pager = s.run().pager();
  if (pager == nullptr) return std::nullopt;
  const auto pc = pager->counts();
  spdlog::info(
      "paging: {} regions written, {} read back; {} regions ({} blocks, {:.1f} MB) on disk at the end",
      pc.pages_written, pc.pages_read, pc.regions_out, pc.blocks_out,
      static_cast<double>(pc.bytes_out) / 1e6);
  if (auto st = s.run().bringInAll(); !st) {
    spdlog::error("--page-dir: {}", st.error().message);
    return kExitNothingMapped;
  }
  return std::nullopt;
}

// The map file, the exports and --corrected-out; the exit code (1 when one could not be written).
int writeOutputs(Session& s) {
  const auto& r = s.request;
  int rc = kExitOk;
  const auto& filter = s.run().mapper().filter();
  if (auto st = ogf::filter::saveMapFile(filter, r.out); !st) {
    spdlog::error("--out: {}", st.error().message);
    rc = kExitNothingMapped;
  }
  if (!writeExports(filter, r.exports)) rc = kExitNothingMapped;
  if (r.corrected_out.empty()) return rc;
  const auto& corrected = s.run().correctedPoses();
  if (auto st = mio::writeOdometryCsv(r.corrected_out, corrected); !st) {
    spdlog::error("--corrected-out: {}", st.error().message);
    return kExitNothingMapped;
  }
  spdlog::info("{}: {} corrected poses ({})", r.corrected_out, corrected.size(), s.setup.pose_correction);
  return rc;
}

// A map from the input, written with its exports; the closing line on stdout.
int mapFromInput(mio::MapRequest r) {
  if (auto st = mio::checkMappingRequest(r); !st) {
    spdlog::error("{}", st.error().message);
    return kExitUsage;
  }
  std::optional<mio::OfflineConfig> config;
  if (const Stop stop = readConfig(r, config)) return *stop;
  if (config) r.exports.nav_band = config->options.nav.band;
  auto setup = mio::prepareOfflineMapping(r, config ? &*config : nullptr);
  if (!setup) {
    spdlog::error("{}", setup.error().message);
    return kExitUsage;
  }
  Session s{r, std::move(*setup)};
  if (const Stop stop = openInputs(s)) return *stop;
  if (const Stop stop = startPaging(s)) return *stop;
  const auto start = Clock::now();
  if (const Stop stop = mapInput(s)) return *stop;
  if (const Stop stop = checkSomethingMapped(s)) return *stop;
  mio::createParentFolder(r.out);  // as the exports' folders are
  if (const Stop stop = bringInPagedRegions(s)) return *stop;
  const int rc = writeOutputs(s);
  if (s.report) s.report->finish();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::printf("%s\n", mio::mapSummaryLine(s.run().counts(), s.run().mapper().filter(), seconds).c_str());
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  ogf::map_program::MapOptions o;
  CLI::App app;
  ogf::map_program::defineCommandLine(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  ogf::map_program::noteGivenFlags(app, o.request);
  if (!ogf::transport::setupLoggingAt("ogf-map", "--log-level", o.log_level)) return kExitUsage;
  if (!o.request.from_map.empty()) return exportMapFile(o.request);
  return mapFromInput(o.request);
}
