// Fusion throughput: rays cast per second, the measurement set of a synthetic VLP-16 scan (16 rings at
// -15°..+15° step 2°, 0.2° azimuth step: 28,800 rays) in a room and in a street, and deskew per scan. The
// mapper's budget is a full scan at 0.2 m and 30 m at 2x real time (50 ms) including the filter update,
// so the measurement set should take a small fraction of that.
#include <ogf/fusion/deskew.hpp>
#include <ogf/fusion/measurement_set.hpp>
#include <ogf/fusion/ray_caster.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace {

using ogf::fusion::Deskew;
using ogf::fusion::MeasurementConfig;
using ogf::fusion::MeasurementSet;
using ogf::fusion::Pose;
using ogf::fusion::PoseBuffer;
using ogf::fusion::PoseBufferConfig;
using ogf::fusion::PoseCoverage;
using ogf::fusion::RayCaster;
using ogf::fusion::ScanPoints;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int kRings = 16;
constexpr int kAzimuths = 1800;  // 0.2° steps: a VLP-16 at 600 rpm

// Distance from p along unit d to the first of the axis-aligned planes a scene is made of (inside a box
// [lo, hi]; a missing side is +-inf), or +inf.
double rangeInBox(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
                  const Eigen::Vector3d& hi) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index a = 0; a < 3; ++a) {
    if (d[a] > 0.0 && std::isfinite(hi[a])) best = std::min(best, (hi[a] - p[a]) / d[a]);
    if (d[a] < 0.0 && std::isfinite(lo[a])) best = std::min(best, (lo[a] - p[a]) / d[a]);
  }
  return best;
}

enum class Scene { kRoom, kStreet };

struct SyntheticScan {
  std::vector<Eigen::Vector3d> origins;
  std::vector<Eigen::Vector3d> endpoints;
};

// A VLP-16 1 m above the floor, moving 0.1 m along x during the scan. Room: 8 m x 6 m x 3 m. Street: a
// 16 m wide canyon with 12 m walls, open along x and above (those rays are cut at max range).
SyntheticScan vlp16Scan(Scene scene) {
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d lo = scene == Scene::kRoom ? Eigen::Vector3d(-3.0, -2.5, -1.0) : Eigen::Vector3d(-inf, -8.0, -1.0);
  const Eigen::Vector3d hi = scene == Scene::kRoom ? Eigen::Vector3d(5.0, 3.5, 2.0) : Eigen::Vector3d(inf, 8.0, 11.0);
  SyntheticScan scan;
  for (int a = 0; a < kAzimuths; ++a) {
    const Eigen::Vector3d origin(0.1 * a / kAzimuths, 0.0, 0.0);
    const double azimuth = a * 0.2 * kDeg;
    for (int ring = 0; ring < kRings; ++ring) {
      const double elevation = (-15.0 + 2.0 * ring) * kDeg;
      const Eigen::Vector3d d(std::cos(elevation) * std::cos(azimuth), -std::cos(elevation) * std::sin(azimuth),
                              std::sin(elevation));
      const double range = std::min(rangeInBox(origin, d, lo, hi), 100.0);
      scan.origins.push_back(origin);
      scan.endpoints.push_back(origin + d * range);
    }
  }
  return scan;
}

void BM_CastRandomRays(benchmark::State& state) {
  const double resolution = static_cast<double>(state.range(0)) / 1000.0;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> range(0.5, 30.0);
  std::vector<Eigen::Vector3d> ends(4096);
  for (auto& e : ends) e = Eigen::Vector3d(unit(rng), unit(rng), 0.25 * unit(rng)).normalized() * range(rng);
  const Eigen::Vector3d origin(0.03, -0.07, 0.81);
  std::int64_t cells = 0;
  std::size_t i = 0;
  for (auto _ : state) {
    std::int32_t sum = 0;
    for (const ogf::CellKey c : RayCaster(origin, ends[i], resolution)) {
      sum += c.x;
      ++cells;
    }
    benchmark::DoNotOptimize(sum);
    i = (i + 1) % ends.size();
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CastRandomRays)->Arg(200)->Arg(100)->ArgName("resolution_mm");

void BM_MeasurementSetVlp16(benchmark::State& state) {
  const Scene scene = state.range(0) == 0 ? Scene::kRoom : Scene::kStreet;
  MeasurementConfig config;
  config.resolution_m = static_cast<double>(state.range(1)) / 1000.0;
  config.max_range_m = 30.0;
  const SyntheticScan scan = vlp16Scan(scene);
  MeasurementSet set(config);
  std::size_t measurements = 0;
  for (auto _ : state) {
    const auto m = set.build(scan.origins, scan.endpoints);
    measurements = m.size();
    benchmark::DoNotOptimize(m.data());
  }
  state.counters["rays"] = static_cast<double>(scan.origins.size());
  state.counters["measurements"] = static_cast<double>(measurements);
  state.counters["cut"] = static_cast<double>(set.counts().cut_at_max_range);
}
BENCHMARK(BM_MeasurementSetVlp16)
    ->ArgNames({"street", "resolution_mm"})
    ->Args({0, 200})
    ->Args({1, 200})
    ->Args({0, 100})
    ->Args({1, 100})
    ->Unit(benchmark::kMillisecond);

// Deskew of 28,800 points over 100 ms with 100 Hz odometry; arg 0: the 16 points of a firing share one
// time (1,800 interpolations), arg 1: each laser has its own time, 2.304 µs apart (28,800).
void BM_DeskewVlp16(benchmark::State& state) {
  const bool per_laser_times = state.range(0) != 0;
  const std::int64_t start = 1'700'000'000'000'000;
  PoseBufferConfig pc;
  PoseBuffer poses(pc);
  for (std::int64_t t = start - 50'000; t <= start + 150'000; t += 10'000) {
    const double s = static_cast<double>(t - start) * 1e-6;
    Pose p;
    p.utime = t;
    p.position = Eigen::Vector3d(1.0 * s, 0.2 * s, 0.0);
    p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * s, Eigen::Vector3d::UnitZ()));
    (void)poses.insert(p);
  }
  std::vector<float> x;
  std::vector<float> y;
  std::vector<float> z;
  std::vector<std::int32_t> offsets;
  for (int a = 0; a < kAzimuths; ++a) {
    for (int ring = 0; ring < kRings; ++ring) {
      x.push_back(5.0f);
      y.push_back(static_cast<float>(a) * 0.001f);
      z.push_back(static_cast<float>(ring) * 0.1f);
      offsets.push_back(a * 55'296 + (per_laser_times ? ring * 2'304 : 0));
    }
  }
  const ScanPoints points{start, x, y, z, offsets};
  Deskew deskew(Eigen::Isometry3d::Identity());
  std::vector<Eigen::Vector3d> origins;
  std::vector<Eigen::Vector3d> endpoints;
  for (auto _ : state) {
    const PoseCoverage c = deskew.place(points, poses, origins, endpoints);
    benchmark::DoNotOptimize(c);
    benchmark::DoNotOptimize(endpoints.data());
  }
  state.counters["interpolations"] = static_cast<double>(deskew.lastInterpolations());
}
BENCHMARK(BM_DeskewVlp16)->ArgName("per_laser_times")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
