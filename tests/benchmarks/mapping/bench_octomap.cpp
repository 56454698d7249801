// ogf-bench-octomap: the OGF and OctoMap on the same scans, in one run (docs/performance.md, "The programs").
// Each scan is a list of rays from one sensor origin; both mappers get exactly those rays at the same
// resolution and max range: the OGF through pipeline::ScanMapper (measurement set + banded filter update, one
// thread), OctoMap through OcTree::insertPointCloud (Debian's liboctomap, built without OpenMP, so also one
// thread). Prints per resolution: time per scan (mean, p50, p99), the real-time factor against a 10 Hz sensor
// (100 ms per scan; times are thread CPU time), memory after the last scan and cell counts. Built with
// -DOGF_BONXAI_DIR (tests/benchmarks/mapping/CMakeLists.txt), it also runs Bonxai's ProbabilisticMap
// (OctoMap's log-odds model on a two-level sparse voxel grid) through its insertPointCloud on the same rays.
// Each mapper runs in a child process of its own (isolated()), so none reuses memory another freed.
//
// Scans: by default synthetic full VLP-16 scans (16 rings at -15°..+15°, 1800 azimuths, 2 cm range
// noise) driven 1 m apart down the simulator's "street" world (ogf::sim presets); or the scans of a
// capture (--pcap, e.g. an ogf-sim capture.pcap) placed with --odometry CSV at each scan's start time, or
// at the origin without it.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <octomap/OcTree.h>

#include <ogf/delta/delta_stream.hpp>
#include <ogf/pipeline/published_cells.hpp>
#include <ogf/fusion/pose_buffer.hpp>
#include <ogf/pipeline/scan_mapper.hpp>
#include <ogf/sim/scene.hpp>
#include <ogf/sim/vlp16_model.hpp>

#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#ifdef OGF_WITH_BONXAI
#include <bonxai_map/probabilistic_map.hpp>
#endif

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "ogf/common/command_line.hpp"
#include "ogf/map_io/map_config_file.hpp"
#include "ogf/map_io/odometry_file.hpp"
#include "ogf/map_io/pcap_scans.hpp"

namespace {

constexpr double kScanPeriodMs = 100.0;  // a VLP-16 at 600 rpm (10 Hz)

// One scan as rays: the sensor origin and the returns, map frame.
struct RayScan {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> endpoints;
};

std::vector<RayScan> syntheticStreetScans(int count, double min_range) {
  auto scene = ogf::sim::presetScene("street");
  if (!scene) {
    std::fprintf(stderr, "ogf-bench-octomap: %s\n", scene.error().message.c_str());
    std::exit(1);
  }
  constexpr int kAzimuths = 1800;
  constexpr double kDeg = std::numbers::pi / 180.0;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<RayScan> scans;
  for (int i = 0; i < count; ++i) {
    Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
    body.translation() = Eigen::Vector3d(5.0 + 1.0 * i, -1.5, 0.0);
    const Eigen::Isometry3d sensor = body * scene->sensor_to_body;
    RayScan scan;
    scan.origin = sensor.translation();
    for (int a = 0; a < kAzimuths; ++a) {
      const double az = -360.0 * a / kAzimuths * kDeg;  // clockwise seen from above
      for (double elev_deg : ogf::sim::vlp16::kElevationDeg) {
        const double el = elev_deg * kDeg;
        const Eigen::Vector3d d =
            sensor.linear() * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
        const auto hit = scene->world.firstHit({scan.origin, d}, 0.0, ogf::sim::vlp16::kMaxRangeM);
        if (!hit) continue;  // no return: the VLP-16 reports nothing
        const double r = hit->range + noise(rng);
        if (r >= min_range) scan.endpoints.push_back(scan.origin + r * d);
      }
    }
    scans.push_back(std::move(scan));
  }
  return scans;
}

std::vector<RayScan> captureScans(const std::string& pcap, const std::string& odometry, ogf::map_io::TimeBase time_base,
                                  double min_range, int limit) {
  std::optional<ogf::fusion::PoseBuffer> poses;
  if (!odometry.empty()) {
    auto odo = ogf::map_io::readOdometry(odometry);
    if (!odo) {
      std::fprintf(stderr, "ogf-bench-octomap: %s\n", odo.error().message.c_str());
      std::exit(1);
    }
    ogf::fusion::PoseBufferConfig cfg;
    cfg.capacity = std::max<std::size_t>(odo->poses.size(), 2);
    poses.emplace(cfg);
    for (const auto& p : odo->poses) poses->insert(p);
  }
  std::vector<RayScan> scans;
  ogf::map_io::PcapScanConfig pc;
  pc.min_range_m = min_range;
  auto read = ogf::map_io::readPcapScans(pcap, pc, [&](const ogf::map_io::ScanRecord& s) {
    if (static_cast<int>(scans.size()) >= limit) return;
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
    if (poses) {
      const auto at = poses->interpolate(s.startOn(s.clock(time_base)));
      if (!at.ok()) return;
      sensor = at.pose.odomFromBody();
    }
    RayScan scan;
    scan.origin = sensor.translation();
    for (std::size_t i = 0; i < s.size(); ++i) scan.endpoints.push_back(sensor * Eigen::Vector3d(s.x[i], s.y[i], s.z[i]));
    scans.push_back(std::move(scan));
  });
  if (!read) {
    std::fprintf(stderr, "ogf-bench-octomap: %s\n", read.error().message.c_str());
    std::exit(1);
  }
  return scans;
}

struct Timing {
  std::vector<double> ms;
  double mean() const {
    double s = 0.0;
    for (double v : ms) s += v;
    return ms.empty() ? 0.0 : s / static_cast<double>(ms.size());
  }
  double percentile(double q) const {
    if (ms.empty()) return 0.0;
    std::vector<double> v = ms;
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size()))) - 1;
    return v[std::min(i, v.size() - 1)];
  }
};

// Time is this thread's CPU time, not wall time: the machines this runs on are shared, and a busy
// neighbour should not make either mapper look slower. Both mappers run on this one thread; with filter
// threads (--threads above 1) the filter's work is on other threads too, and the OGF is timed in wall time.
double clockMs(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}
double cpuMs() { return clockMs(CLOCK_THREAD_CPUTIME_ID); }

struct OgfResult {
  Timing total, measure, apply;
  std::size_t memory = 0, cells = 0;
  double measurements_per_scan = 0.0;
  double applied_per_scan = 0.0;  // updates the filter applied (the rest were clamped or negligible)
  std::size_t published_cells = 0, published_memory = 0;  // the published map, with --deltas
  Timing stream;                    // DeltaStream::update per scan (outside total), with --deltas
  double published_per_scan = 0.0;  // cells the delta messages carry per scan
  std::size_t waiting = 0, stale = 0, overflowed = 0;  // after the last scan, with --delta-bytes-per-scan
  template <class F>
  void fields(F& f) {
    f(total), f(measure), f(apply), f(memory), f(cells), f(measurements_per_scan), f(applied_per_scan);
    f(published_cells), f(published_memory), f(stream), f(published_per_scan);
    f(waiting), f(stale), f(overflowed);
  }
};

// `config`'s OGF at `resolution`.
OgfResult runOgf(const std::vector<RayScan>& scans, ogf::pipeline::MapperConfig config, double resolution, bool deltas,
                 double delta_step, std::int64_t delta_bytes_per_scan, double delta_max_wait_s) {
  config.setResolution(resolution);
  const int threads = config.filter.threads;
  auto mapper = ogf::pipeline::ScanMapper::create(config);
  if (!mapper) {
    std::fprintf(stderr, "ogf-bench-octomap: %s\n", mapper.error().message.c_str());
    std::exit(1);
  }
  OgfResult r;
  std::size_t measurements = 0, applied = 0, published = 0;
  std::vector<float> x, y, z;
  std::vector<std::int32_t> t;
  ogf::pipeline::ChangedCells changes;
  // With --deltas, the published map the daemon keeps beside the filter (outside the OGF's timing).
  ogf::delta::DeltaStream stream({resolution, 1, ogf::messages::kMaxDeltaCellsPerMessage},
                                 ogf::delta::PublishingRule{delta_step, 0.0});
  // The waiting cells ogf-mapper allows: deltas.max_wait_s of its rate (the budget at 10 Hz).
  if (delta_bytes_per_scan > 0) {
    stream.limitWaitingTo(static_cast<double>(delta_bytes_per_scan) * 10.0, delta_max_wait_s);
  }
  for (const RayScan& s : scans) {
    // The rays relative to the origin, placed back with a pure translation (outside the timing, as
    // OctoMap's point cloud is built outside it).
    const std::size_t n = s.endpoints.size();
    x.resize(n);
    y.resize(n);
    z.resize(n);
    t.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d d = s.endpoints[i] - s.origin;
      x[i] = static_cast<float>(d.x());
      y[i] = static_cast<float>(d.y());
      z[i] = static_cast<float>(d.z());
    }
    const ogf::fusion::ScanPoints points{0, x, y, z, t};
    const Eigen::Isometry3d pose(Eigen::Translation3d(s.origin));
    const auto now = [clock = threads > 1 ? CLOCK_MONOTONIC : CLOCK_THREAD_CPUTIME_ID] { return clockMs(clock); };
    const double t0 = now();
    mapper->measureStatic(points, pose);
    const double t1 = now();
    // With --deltas, as ogf-mapper does: the cells whose class or quantised probability changed, collected.
    changes.clear();
    applied += mapper->apply(mapper->measurements(), deltas ? &changes : nullptr).applied;
    const double m_ms = t1 - t0, a_ms = now() - t1;
    if (deltas) {
      // The delta stream ogf-mapper keeps beside the filter: timed apart, as it is not the filter's work.
      const double s0 = now();
      ogf::pipeline::refreshStaleSlabs(mapper->filter(), stream);
      if (delta_bytes_per_scan > 0) stream.allow(delta_bytes_per_scan);
      for (const auto& m : stream.update(0, changes)) published += static_cast<std::size_t>(m.num_cells);
      r.stream.ms.push_back(now() - s0);
    }
    measurements += mapper->measurements().size();
    r.measure.ms.push_back(m_ms);
    r.apply.ms.push_back(a_ms);
    r.total.ms.push_back(m_ms + a_ms);
  }
  r.memory = mapper->filter().memoryBytes();
  r.cells = mapper->filter().allocatedCells();
  r.published_cells = stream.map().size();
  r.published_memory = stream.map().memoryBytes();
  r.waiting = stream.deferred().size();
  r.stale = stream.stale().size();
  r.overflowed = stream.overflowed();
  const auto n_scans = static_cast<double>(std::max<std::size_t>(scans.size(), 1));
  r.measurements_per_scan = static_cast<double>(measurements) / n_scans;
  r.applied_per_scan = static_cast<double>(applied) / n_scans;
  r.published_per_scan = static_cast<double>(published) / n_scans;
  return r;
}

struct OctomapResult {
  Timing total;
  std::size_t memory = 0, nodes = 0, leaves = 0;
  template <class F>
  void fields(F& f) {
    f(total), f(memory), f(nodes), f(leaves);
  }
};

OctomapResult runOctomap(const std::vector<RayScan>& scans, double resolution, double max_range) {
  octomap::OcTree tree(resolution);
  OctomapResult r;
  for (const RayScan& s : scans) {
    octomap::Pointcloud cloud;
    cloud.reserve(s.endpoints.size());
    for (const auto& p : s.endpoints)
      cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    const octomap::point3d origin(static_cast<float>(s.origin.x()), static_cast<float>(s.origin.y()),
                                  static_cast<float>(s.origin.z()));
    const double t0 = cpuMs();
    tree.insertPointCloud(cloud, origin, max_range);
    r.total.ms.push_back(cpuMs() - t0);
  }
  r.memory = tree.memoryUsage();
  r.nodes = tree.size();
  r.leaves = tree.getNumLeafNodes();
  return r;
}

#ifdef OGF_WITH_BONXAI
struct BonxaiResult {
  Timing total;
  std::size_t memory = 0, cells = 0;
  template <class F>
  void fields(F& f) {
    f(total), f(memory), f(cells);
  }
};

BonxaiResult runBonxai(const std::vector<RayScan>& scans, double resolution, double max_range) {
  Bonxai::ProbabilisticMap map(resolution);
  BonxaiResult r;
  for (const RayScan& s : scans) {
    const std::vector<Eigen::Vector3d>& points = s.endpoints;  // the points as they are, built outside the timing
    const double t0 = cpuMs();
    map.insertPointCloud(points, s.origin, max_range);
    r.total.ms.push_back(cpuMs() - t0);
  }
  r.memory = map.grid().memUsage();
  r.cells = map.grid().activeCellsCount();
  return r;
}
#endif

// A result's fields as bytes, in the order its `fields` visits them: how a run in a child process hands its
// figures back through a pipe.
struct Packer {
  std::string bytes;
  void operator()(const Timing& t) {
    (*this)(t.ms.size());
    bytes.append(reinterpret_cast<const char*>(t.ms.data()), t.ms.size() * sizeof(double));
  }
  template <class T>
    requires std::is_arithmetic_v<T>
  void operator()(const T& v) {
    bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
};
struct Unpacker {
  const std::string& bytes;
  std::size_t at = 0;
  bool ok = true;
  void take(void* to, std::size_t n) {
    if (bytes.size() - at < n) {
      ok = false;
      return;
    }
    std::copy_n(bytes.data() + at, n, static_cast<char*>(to));
    at += n;
  }
  void operator()(Timing& t) {
    std::size_t n = 0;
    (*this)(n);
    if (!ok || n > (bytes.size() - at) / sizeof(double)) {
      ok = false;
      return;
    }
    t.ms.resize(n);
    take(t.ms.data(), n * sizeof(double));
  }
  template <class T>
    requires std::is_arithmetic_v<T>
  void operator()(T& v) {
    take(&v, sizeof v);
  }
};

// Runs one mapper in a child process of its own and returns its result. Every mapper starts from the same
// heap (the scans) and pays for the memory it touches first: in one process a mapper reuses the pages the
// one before it freed, and where page faults are slow (virtual machines) that made the mapper run later
// look up to 1.6x faster on its first scans.
template <class Result, class Run>
Result isolated(const char* name, Run run) {
  std::fflush(stdout);
  std::fflush(stderr);
  int fds[2];
  if (pipe(fds) != 0) {
    std::perror("ogf-bench-octomap: pipe");
    std::exit(1);
  }
  const pid_t pid = fork();
  if (pid < 0) {
    std::perror("ogf-bench-octomap: fork");
    std::exit(1);
  }
  if (pid == 0) {
    close(fds[0]);
    Result r = run();
    Packer p;
    r.fields(p);
    std::size_t off = 0;
    while (off < p.bytes.size()) {
      const ssize_t n = write(fds[1], p.bytes.data() + off, p.bytes.size() - off);
      if (n <= 0) _exit(3);
      off += static_cast<std::size_t>(n);
    }
    std::fflush(stdout);
    _exit(0);
  }
  close(fds[1]);
  std::string bytes;
  char buf[65536];
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    bytes.append(buf, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  Result r;
  Unpacker u{bytes};
  r.fields(u);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !u.ok || u.at != bytes.size()) {
    std::fprintf(stderr, "ogf-bench-octomap: the %s run failed (status %d, %zu bytes of result)\n", name, status,
                 bytes.size());
    std::exit(1);
  }
  return r;
}

std::vector<double> parseList(const std::string& text) {
  std::vector<double> out;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) out.push_back(std::stod(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "The same scans through the OGF (ScanMapper, one thread) and OctoMap (insertPointCloud) at each\n"
      "resolution; prints time per scan, real-time factor against 10 Hz, memory and cells."};
  int count = 20;
  std::string pcap, odometry, resolutions = "0.2,0.1";
  double max_range = 30.0, min_range = 0.4;
  double clamp_z = ogf::filter::FilterConfig{}.clampZ;
  double free_clamp_z = ogf::filter::FilterConfig{}.freeClampZ;
  std::string covariance = ogf::filter::toString(ogf::pipeline::MapperConfig{}.filter.covariance);
  bool deltas = false;
  double delta_step = ogf::delta::PublishingRule{}.probability_step;
  std::int64_t delta_bytes_per_scan = 0;
  double delta_max_wait_s = 1.0;
  bool no_octomap = false;
  int threads = 1;
  std::string config_path;
  app.add_option("--config", config_path,
                 "ogf-mapper's configuration file: the OGF's map and filter settings (its map.resolution replaced "
                 "by each of --resolutions); the flags below override it")
      ->check(CLI::ExistingFile);
  app.add_option("--scans", count, "Scans to map (synthetic street scans 1 m apart, or the first of --pcap)")
      ->capture_default_str()
      ->check(ogf::cli::positive());
  app.add_option("--pcap", pcap, "Use the scans of this capture instead (e.g. an ogf-sim capture.pcap)");
  app.add_option("--odometry", odometry, "Odometry for --pcap (CSV or LCM log); each scan at its start pose");
  app.add_option("--resolutions", resolutions, "Comma-separated cell sizes, metres")->capture_default_str();
  auto* max_opt = app.add_option("--max-range", max_range, "Rays cut here (free only beyond), metres")->capture_default_str();
  auto* min_opt = app.add_option("--min-range", min_range, "Returns closer are dropped before either mapper sees them")
      ->capture_default_str();
  auto* clamp_opt = app.add_option("--clamp-z", clamp_z, "The OGF's clampZ (filter_config.hpp); 0 applies every update")
      ->capture_default_str();
  auto* free_clamp_opt = app.add_option("--free-clamp-z", free_clamp_z, "The OGF's freeClampZ for free measurements; 0: --clamp-z")
      ->capture_default_str();
  auto* covariance_opt = app.add_option("--covariance", covariance, "The OGF's covariance storage: compact or banded")
      ->capture_default_str()
      ->check(CLI::IsMember({"compact", "banded"}));
  app.add_flag("--deltas", deltas,
               "Also collect the changed cells per scan and publish them into a delta stream, as ogf-mapper does for "
               "OGF_MAP_DELTA; prints the published map's size and the delta stream's time (apart from the OGF's)");
  app.add_option("--delta-step", delta_step,
                 "With --deltas, the publishing rule's probability step (ogf-mapper's deltas.probability_step, "
                 "0.02 there; 0: every change of quantised probability or class)")
      ->capture_default_str();
  app.add_option("--delta-bytes-per-scan", delta_bytes_per_scan,
                 "With --deltas, the bytes each update may carry (a byte budget as ogf-mapper's deltas.max_bytes_per_s "
                 "grants it at 10 Hz; the rest wait); 0: unbounded")
      ->capture_default_str();
  app.add_option("--delta-max-wait-s", delta_max_wait_s,
                 "With --delta-bytes-per-scan, the most cells that wait, in seconds of the budget at 10 Hz "
                 "(ogf-mapper's deltas.max_wait_s); changes beyond them mark their slab stale, read again later")
      ->capture_default_str();
  auto* threads_opt = app.add_option("--threads", threads,
                 "The OGF's filter threads (filter.threads); above 1 the OGF's times are wall time, not CPU time")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  app.add_flag("--no-octomap", no_octomap, "Only the OGF's rows: quicker, for comparing two builds of the OGF");
  OGF_PARSE_COMMAND_LINE(app, argc, argv);

  // The OGF's settings: the defaults, then the file's, then the flags given.
  ogf::mapper_daemon::MapperOptions file;
  if (!config_path.empty()) {
    auto read = ogf::map_io::readOfflineConfig(config_path, ogf::mapper_daemon::kUsedByMap);
    if (!read) {
      std::fprintf(stderr, "ogf-bench-octomap: --config: %s\n", read.error().message.c_str());
      return 2;
    }
    if (const auto note = read->unusedNote("ogf-bench-octomap"); !note.empty())
      std::fprintf(stderr, "--config: %s\n", note.c_str());
    file = read->options;
  }
  ogf::pipeline::MapperConfig config = file.map;
  const bool no_file = config_path.empty();
  if (no_file || max_opt->count() > 0) config.fusion.measurement.max_range_m = max_range;
  if (no_file || min_opt->count() > 0) config.fusion.measurement.min_range_m = min_range;
  if (no_file || clamp_opt->count() > 0) config.filter.clampZ = clamp_z;
  if (no_file || free_clamp_opt->count() > 0) config.filter.freeClampZ = free_clamp_z;
  if (no_file || covariance_opt->count() > 0) config.filter.covariance = *ogf::filter::parseCovarianceStorage(covariance);
  if (no_file || threads_opt->count() > 0) config.filter.threads = threads;
  max_range = config.fusion.measurement.max_range_m;
  min_range = config.fusion.measurement.min_range_m;
  threads = config.filter.threads;

  const auto scans = pcap.empty() ? syntheticStreetScans(count, min_range) : captureScans(pcap, odometry, file.time_base, min_range, count);
  std::size_t rays = 0;
  for (const auto& s : scans) rays += s.endpoints.size();
  if (scans.empty()) {
    std::fprintf(stderr, "ogf-bench-octomap: no scans\n");
    return 1;
  }
  std::printf("%zu scans, %.0f rays per scan, max range %.1f m, %s\n", scans.size(),
              static_cast<double>(rays) / static_cast<double>(scans.size()), max_range,
              pcap.empty() ? "synthetic VLP-16 in the sim 'street' world, 1 m apart" : pcap.c_str());
  std::printf("%-6s %-8s %9s %9s %9s %8s %10s %11s %s\n", "res m", "mapper", "mean ms", "p50 ms", "p99 ms",
              "x 10 Hz", "memory MB", "cells", "notes");
  for (const double res : parseList(resolutions)) {
    const auto ogf = isolated<OgfResult>("OGF", [&] { return runOgf(scans, config, res, deltas, delta_step, delta_bytes_per_scan, delta_max_wait_s); });
    const auto row = [&](const char* name, const Timing& t, std::size_t memory, std::size_t cells, const std::string& notes) {
      std::printf("%-6.2f %-8s %9.1f %9.1f %9.1f %8.2f %10.1f %11zu %s\n", res, name, t.mean(), t.percentile(0.5),
                  t.percentile(0.99), kScanPeriodMs / t.mean(), static_cast<double>(memory) / 1e6, cells,
                  notes.c_str());
    };
    row("OGF", ogf.total, ogf.memory, ogf.cells,
        fmt::format("measure {:.1f} + filter {:.1f} ms; {:.0f} cell measurements/scan, {:.0f} applied; allocated cells",
                    ogf.measure.mean(), ogf.apply.mean(), ogf.measurements_per_scan, ogf.applied_per_scan) +
            (threads > 1 ? fmt::format("; {} filter threads, wall time", threads) : std::string()));
    if (deltas) {
      std::printf("%-6.2f published map: %zu cells, %.1f MB, %.2f bytes per cell; %.0f cells published per scan, "
                  "delta stream %.1f ms per scan (mean; not in the OGF's times)\n",
                  res, ogf.published_cells, static_cast<double>(ogf.published_memory) / 1e6,
                  static_cast<double>(ogf.published_memory) / static_cast<double>(std::max<std::size_t>(ogf.published_cells, 1)),
                  ogf.published_per_scan, ogf.stream.mean());
      if (delta_bytes_per_scan > 0) {
        std::printf("%-6.2f after the last scan: %zu cells waiting, %zu slabs stale; %zu changes went to a stale "
                    "slab\n",
                    res, ogf.waiting, ogf.stale, ogf.overflowed);
      }
    }
    if (no_octomap) {
      std::fflush(stdout);
      continue;
    }
    const auto oct = isolated<OctomapResult>("OctoMap", [&] { return runOctomap(scans, res, max_range); });
    row("OctoMap", oct.total, oct.memory, oct.leaves, fmt::format("leaves ({} nodes)", oct.nodes));
    std::printf("%-6.2f OGF/OctoMap speed %.2fx, memory %.2fx\n", res, oct.total.mean() / ogf.total.mean(),
                static_cast<double>(ogf.memory) / static_cast<double>(oct.memory));
#ifdef OGF_WITH_BONXAI
    const auto bonxai = isolated<BonxaiResult>("Bonxai", [&] { return runBonxai(scans, res, max_range); });
    row("Bonxai", bonxai.total, bonxai.memory, bonxai.cells, "active cells");
    std::printf("%-6.2f OGF/Bonxai speed %.2fx, memory %.2fx\n", res, bonxai.total.mean() / ogf.total.mean(),
                static_cast<double>(ogf.memory) / static_cast<double>(bonxai.memory));
#endif
    std::fflush(stdout);
  }
  return 0;
}
