// The per-scan path allocates nothing once warm: MeasurementSet and Deskew reuse their buffers from scan
// to scan (a VLP-16 at 10 Hz would otherwise allocate megabytes ten times a second). Counted by replacing
// the global operator new in this test binary.
#include <ogf/fusion/deskew.hpp>
#include <ogf/fusion/measurement_set.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <vector>

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace ogf::fusion {
namespace {

TEST(SteadyState, MeasurementSetAndDeskewDoNotAllocateOnceWarm) {
  // A ring of returns around a sensor moving along x, in the sensor frame.
  std::vector<float> x;
  std::vector<float> y;
  std::vector<float> z;
  std::vector<std::int32_t> offsets;
  for (int i = 0; i < 4000; ++i) {
    const double a = 0.0016 * i;
    x.push_back(static_cast<float>(6.0 * std::cos(a)));
    y.push_back(static_cast<float>(6.0 * std::sin(a)));
    z.push_back(static_cast<float>(0.3 * std::sin(7.0 * a)));
    offsets.push_back((i / 16) * 55'296);
  }
  const std::int64_t start = 1'000'000;
  PoseBuffer poses(PoseBufferConfig{});
  for (std::int64_t t = 900'000; t <= 1'200'000; t += 10'000) {
    ASSERT_TRUE(poses.insert({t, Eigen::Vector3d(1e-6 * static_cast<double>(t), 0.0, 0.0),
                              Eigen::Quaterniond::Identity()}).accepted());
  }
  const ScanPoints scan{start, x, y, z, offsets};
  Deskew deskew(Eigen::Isometry3d::Identity());
  MeasurementSet set(MeasurementConfig{});
  std::vector<Eigen::Vector3d> origins;
  std::vector<Eigen::Vector3d> endpoints;
  ASSERT_EQ(deskew.place(scan, poses, origins, endpoints), PoseCoverage::kCovered);
  const std::size_t warm = set.build(origins, endpoints).size();
  ASSERT_GT(warm, 0U);

  const long before = g_allocations.load();
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(deskew.place(scan, poses, origins, endpoints), PoseCoverage::kCovered);
    ASSERT_EQ(set.build(origins, endpoints).size(), warm);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
}

}  // namespace
}  // namespace ogf::fusion
