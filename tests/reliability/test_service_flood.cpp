// ogf-mapper under traffic that needs no key, as real processes on udpm loopback: a 10 s drive at the
// VLP-16's 10 scans a second, once on a quiet bus and once beside a process that floods it.
// - Cell queries of the largest allowed size (10 000 points, 120 kB) at 1 000 a second, and 1 M-point
//   queries (12 MB, over the point limit) among them: every scan of the drive is mapped (one may drop), the
//   map deltas keep coming and the mapper's memory stays small, because service traffic has its own thread
//   and a queue bounded by bytes, and an oversized query is refused from its length.
// - A second source forging 390 000-point scans dated 8 s before the real ones: the real source maps every
//   scan but one, because the worker shares its time between sources and a scan larger than any sensor's
//   revolution is throttled.
#include <gtest/gtest.h>

#include <ogf/lidar_scan_t.hpp>
#include <ogf/map_query_t.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <thread>

#include "integration/scan_feeder.hpp"
#include "sensor_rate_replay.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using ogf::testing::ReplayFigures;
using ogf::testing::SensorRateReplay;

constexpr int kScans = 100;
constexpr std::int64_t kScanPeriodUs = 100'000;

class ServiceFloodTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    dir_ = ogf::testing::emptyTestDirectory("ogf-service-flood");
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  SensorRateReplay run(int slot, const std::string& name, const std::string& config = "") const {
    SensorRateReplay r;
    r.dir = dir_;
    r.url = ogf::testing::loopbackUdpmUrl(slot);
    r.name = name;
    r.config = config;
    r.scans = kScans;
    return r;
  }
  fs::path dir_;
};

// `n` points spread over the feeder's room (10 m x 8 m x 3 m about the origin).
ogf::map_query_t cellQuery(int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> x(-5.f, 5.f), y(-4.f, 4.f), z(-0.5f, 2.5f);
  ogf::map_query_t q{};
  q.requester = "flood";
  q.kind = ogf::map_query_t::KIND_CELLS;
  q.num_points = n;
  q.points.resize(static_cast<std::size_t>(n));
  for (auto& p : q.points) p = {x(rng), y(rng), z(rng)};
  return q;
}

TEST_F(ServiceFloodTest, LargestCellQueriesAtAThousandASecondLeaveEveryScanMappedAndTheMapperSmall) {
  const auto quiet = ogf::testing::replayAtSensorRate(run(290, "quiet"));
  auto flooded = run(291, "flood");
  flooded.attack = [](lcm::LCM& bus, Clock::time_point first_scan) {
    std::mt19937 rng(11);
    auto q = cellQuery(10'000, rng);
    auto huge = cellQuery(1'000'000, rng);
    const auto start = first_scan - 200ms;
    for (std::int64_t i = 0;; ++i) {
      std::this_thread::sleep_until(start + std::chrono::microseconds(i * 1000));
      auto& sent = i % 500 == 250 ? huge : q;  // two oversized queries a second among the thousand
      sent.request_id = i;
      bus.publish("OGF_MAP_QUERY", &sent);
    }
  };
  const auto flood = ogf::testing::replayAtSensorRate(flooded);
  std::printf("%s\n%s\n", figuresLine("without flood", quiet).c_str(), figuresLine("with flood", flood).c_str());
  // The flood reached the mapper: thousands of queries heard, the oversized ones refused.
  EXPECT_GE(flood.status.service_requests_in, 2000);
  EXPECT_GE(flood.status.queries_refused, 5);
  // Mapping did not wait behind it: every scan mapped but one at most, no more dropped than on the quiet
  // bus give or take one, and the deltas kept coming (the largest gap within 1 s, or within three scan
  // periods of the quiet run's when the shared machine makes that one longer).
  EXPECT_GE(flood.source.scans_mapped, kScans - 1);
  EXPECT_LE(flood.source.scans_dropped_behind, quiet.source.scans_dropped_behind + 1);
  EXPECT_LE(flood.largest_gap_s, std::max(1.0, quiet.largest_gap_s + 0.3));
  // Nothing the flood sent is held beyond the service queue's bound.
  EXPECT_LT(flood.peak_rss_bytes, 100'000'000) << "first " << flood.first_rss_bytes;
}

TEST_F(ServiceFloodTest, AForgedSecondSourceOfHugeOldScansLeavesTheRealSourceMappingEveryScan) {
  const std::string two_sources =
      "sources:\n"
      "  - {name: lidar, scan_channel: VELODYNE_SCAN}\n"
      "  - {name: forged, scan_channel: SCAN_FORGED}\n";
  auto forged = run(292, "forged", two_sources);
  forged.attack = [](lcm::LCM& bus, Clock::time_point first_scan) {
    const std::int64_t drive_start = ogf::testing::feedStep(0, 1).scan.device_utime_start;
    auto scan = ogf::testing::feedStep(0, 390'000).scan;
    std::this_thread::sleep_until(first_scan);
    for (std::int64_t k = 0;; ++k) {
      // Eight seconds before the real scan of this moment, and never before the drive (whose poses the
      // mapper holds), so oldest-first would always take the forged scan.
      const auto real = static_cast<std::int64_t>((Clock::now() - first_scan) / 100ms);
      const std::int64_t t0 = std::max(drive_start + k * 10'000, drive_start + real * kScanPeriodUs - 8'000'000);
      scan.seq = k;
      scan.utime = scan.device_utime_start = scan.host_utime_start = t0;
      scan.device_utime_end = scan.host_utime_end = t0 + kScanPeriodUs - 1000;
      // Half claim a VLP-16, whose revolution holds far fewer points (throttled at once); half name no
      // model, so only the worker's fair share stands between them and the real source.
      scan.model = k % 2 == 0 ? ogf::lidar_scan_t::MODEL_VLP16 : ogf::lidar_scan_t::MODEL_UNKNOWN;
      bus.publish("SCAN_FORGED", &scan);
      std::this_thread::sleep_for(100ms);
    }
  };
  const auto f = ogf::testing::replayAtSensorRate(forged);
  std::printf("%s\n", figuresLine("forged source", f).c_str());
  const ogf::source_status_t* bad = nullptr;
  for (const auto& s : f.status.sources)
    if (s.name == "forged") bad = &s;
  ASSERT_NE(bad, nullptr);
  std::printf("[ figures  ] forged source: scans in %lld, mapped %lld, throttled %lld, dropped behind %lld\n",
              static_cast<long long>(bad->scans_in), static_cast<long long>(bad->scans_mapped),
              static_cast<long long>(bad->scans_throttled), static_cast<long long>(bad->scans_dropped_behind));
  // The attack happened: forged scans came, those claiming a VLP-16 throttled and named in the status.
  EXPECT_GE(bad->scans_in, 20);
  EXPECT_GE(bad->scans_throttled, 10);
  // The real source lost at most one scan to it.
  EXPECT_GE(f.source.scans_mapped, kScans - 1);
}

}  // namespace
