// Decodes every real capture in ../shared/data/real and checks what must hold: scans from azimuth wraps,
// points per scan, ring order, dual-return types, GPS fix and PPS state, range limits, monotonic time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "capture_decoding.hpp"
#include "support/shared_data.hpp"

namespace ov = ogf::velodyne;
using ogf::testing::decodeCapture;

namespace {

constexpr const char* kVlp16Strongest = "data/real/vlp-16-test-90deg-1-50-frames.pcap";
constexpr const char* kVlp16Moving = "data/real/sampleShort.pcap";
constexpr const char* kVlp16Dual = "data/real/derived/nebula_vlp16_dual_1673400471837873222.DERIVED.pcap";
constexpr const char* kHdl32 = "data/real/monterey-first-100-packets.pcap";

ov::StreamConfig allReturns() {
  ov::StreamConfig c;
  c.min_range_m = 0.0;
  return c;
}

// Azimuth relative to the cut, [0, 360).
double relative(double azimuth, double cut) { return std::fmod(azimuth - cut + 720.0, 360.0); }

void expectFullScansCoverOneTurn(const std::vector<ov::Scan>& scans, double cut) {
  int full = 0;
  for (const ov::Scan& s : scans) {
    if (!s.starts_at_cut || !s.ends_at_cut || s.points.empty()) continue;
    ++full;
    // Points in firing order advance clockwise from the cut to just before it, never a second time round.
    double covered = 0.0, prev = relative(s.points.front().azimuth_deg, cut);
    EXPECT_LT(prev, 2.0) << "scan " << s.seq << " starts away from the cut";
    for (const ov::ScanPoint& p : s.points) {
      const double r = relative(p.azimuth_deg, cut);
      EXPECT_GE(r, prev - 0.5) << "scan " << s.seq << " goes back past the cut";
      covered += std::max(0.0, r - prev);
      prev = r;
    }
    EXPECT_LE(covered, 360.0);
    EXPECT_GT(prev, 357.0) << "scan " << s.seq << " ends early";
  }
  EXPECT_GT(full, 0);
}

void expectMonotonicTime(const std::vector<ov::Scan>& scans) {
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const ov::Scan& s = scans[i];
    std::int32_t prev = 0;
    for (const ov::ScanPoint& p : s.points) {
      EXPECT_GE(p.time_offset_ns, prev) << "scan " << s.seq;
      prev = p.time_offset_ns;
    }
    EXPECT_LE(static_cast<std::int64_t>(prev) / 1000, s.device_utime_end - s.device_utime_start + 200);
    if (i > 0) {
      EXPECT_GT(s.device_utime_start, scans[i - 1].device_utime_end - 1);
    }
    EXPECT_LE(s.host_utime_start, s.host_utime_end);
  }
}

// Mean elevation of each ring rises with the ring number.
void expectRingOrder(const std::vector<ov::Scan>& scans, int lasers) {
  std::map<int, std::pair<double, int>> sum;
  for (const ov::Scan& s : scans)
    for (const ov::ScanPoint& p : s.points) {
      if (p.distance_m < 2.0f) continue;  // the beam origin offsets matter at very short range
      auto& e = sum[p.ring];
      e.first += static_cast<double>(std::atan2(p.z, std::hypot(p.x, p.y)));
      ++e.second;
    }
  ASSERT_EQ(static_cast<int>(sum.size()), lasers);
  double prev = -10.0;
  for (const auto& [ring, e] : sum) {
    const double mean = e.first / e.second;
    EXPECT_GT(mean, prev) << "ring " << ring;
    prev = mean;
  }
}

}  // namespace

TEST(RealCaptures, Vlp16StrongestGivesOneScanPerAzimuthWrap) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Strongest);
  const auto d = decodeCapture(path, allReturns());
  EXPECT_EQ(d.read_error, "");
  // 51 wraps of the azimuth give 52 scans (docs/test-data.md §2.1), the first and last partial.
  ASSERT_EQ(d.scans.size(), 52u);
  EXPECT_EQ(d.counters.data_packets, 1902);
  EXPECT_EQ(d.counters.position_packets, 367);
  EXPECT_EQ(d.counters.bad_other + d.counters.bad_size + d.counters.bad_block_flag, 0);
  // The product byte says 0x21 (HDL-32E); the packet period says VLP-16.
  EXPECT_EQ(d.model, ov::Model::Vlp16);
  EXPECT_EQ(d.return_mode, ov::ReturnMode::Strongest);
  EXPECT_FALSE(d.scans.front().starts_at_cut);
  for (std::size_t i = 1; i + 1 < d.scans.size(); ++i) {
    const ov::Scan& s = d.scans[i];
    EXPECT_TRUE(s.starts_at_cut && s.ends_at_cut);
    // 1200 rpm: 754 / 20 = 37.7 packets a turn; 4.1 % of returns are zero range.
    EXPECT_GE(s.packets_received, 37);
    EXPECT_LE(s.packets_received, 39);
    EXPECT_GT(s.points.size(), 12000u);
    EXPECT_LT(s.points.size(), 39u * 384u);
    EXPECT_EQ(s.packets_lost, 0);
    EXPECT_NEAR(s.rpm, 1200.0, 30.0);
    for (const ov::ScanPoint& p : s.points) EXPECT_EQ(p.return_type, ov::ReturnType::Strongest);
  }
  expectFullScansCoverOneTurn(d.scans, 0.0);
  expectMonotonicTime(d.scans);
  expectRingOrder(d.scans, 16);
}

TEST(RealCaptures, MovingVlp16HasLockedPpsValidFixAndGpsTime) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Moving);
  const auto d = decodeCapture(path, allReturns());
  // The file is cut mid-record: reported, and the 347 complete records are all used.
  EXPECT_NE(d.read_error.find("truncated"), std::string::npos) << d.read_error;
  EXPECT_EQ(d.records, 347);
  EXPECT_EQ(d.counters.data_packets, 291);
  EXPECT_EQ(d.counters.position_packets, 56);
  ASSERT_EQ(d.scans.size(), 5u);  // 4 wraps at 600 rpm
  ASSERT_TRUE(d.last_position);
  EXPECT_EQ(d.last_position->pps, ov::PpsState::Locked);
  EXPECT_TRUE(d.last_position->gpsFixValid());
  ASSERT_TRUE(d.last_position->fix);
  EXPECT_NEAR(*d.last_position->fix->speed_knots, 10.3, 1e-9);
  EXPECT_NEAR(*d.last_position->fix->latitude_deg, 37.0 + 7.8178 / 60.0, 1e-9);
  EXPECT_NEAR(*d.last_position->fix->longitude_deg, -(121.0 + 39.2690 / 60.0), 1e-9);
  // After the first position packet, device time is GPS time: 2015-07-23 21:41:07 UTC (TOH 2467 s), which
  // leads the capture's host clock by about 1.4 s.
  const ov::Scan& last = d.scans.back();
  EXPECT_EQ(last.time_source, ov::TimeSource::PpsNmea);
  constexpr std::int64_t k2015_07_23_21h = 1437685200LL * 1'000'000;
  EXPECT_GE(last.device_utime_start, k2015_07_23_21h + 2467'000'000LL);
  EXPECT_LT(last.device_utime_start, k2015_07_23_21h + 2468'000'000LL);
  EXPECT_NEAR(static_cast<double>(last.device_utime_start - last.host_utime_start), 1.4e6, 0.2e6);
  for (std::size_t i = 1; i + 1 < d.scans.size(); ++i) {
    EXPECT_GE(d.scans[i].packets_received, 75);
    EXPECT_LE(d.scans[i].packets_received, 77);
    EXPECT_NEAR(d.scans[i].rpm, 600.0, 20.0);
  }
  expectFullScansCoverOneTurn(d.scans, 0.0);
  expectMonotonicTime(d.scans);
  expectRingOrder(d.scans, 16);
}

TEST(RealCaptures, DualReturnCaptureTypesEveryPoint) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Dual);
  const auto d = decodeCapture(path, allReturns());
  EXPECT_EQ(d.return_mode, ov::ReturnMode::Dual);
  EXPECT_EQ(d.counters.data_packets, 603);
  ASSERT_EQ(d.scans.size(), 5u);  // 4 wraps
  std::map<ov::ReturnType, std::int64_t> types;
  for (const ov::Scan& s : d.scans) {
    EXPECT_EQ(s.return_mode, ov::ReturnMode::Dual);
    EXPECT_EQ(s.packets_lost, 0);
    // Per laser firing: at most a last and a strongest, or one point for both.
    std::map<std::pair<std::int32_t, int>, std::set<ov::ReturnType>> per_firing;
    for (const ov::ScanPoint& p : s.points) {
      ++types[p.return_type];
      auto& set = per_firing[{p.time_offset_ns, p.laser_id}];
      EXPECT_TRUE(set.insert(p.return_type).second) << "two points of one type in one firing";
    }
    for (const auto& [key, set] : per_firing)
      if (set.count(ov::ReturnType::Both)) {
        EXPECT_EQ(set.size(), 1u);
      }
  }
  EXPECT_GT(types[ov::ReturnType::Both], 0);
  EXPECT_GT(types[ov::ReturnType::Last], 0);
  EXPECT_GT(types[ov::ReturnType::Strongest], 0);
  EXPECT_EQ(types[ov::ReturnType::SecondStrongest], 0);
  // A dual packet is one firing per block pair: 12 sequences, 663.552 us; a full turn at 600 rpm ~151
  // packets.
  for (std::size_t i = 1; i + 1 < d.scans.size(); ++i) {
    EXPECT_GE(d.scans[i].packets_received, 150);
    EXPECT_LE(d.scans[i].packets_received, 153);
    EXPECT_NEAR(d.scans[i].rpm, 600.0, 20.0);
  }
  expectFullScansCoverOneTurn(d.scans, 0.0);
  expectMonotonicTime(d.scans);
}

TEST(RealCaptures, DualCaptureKeepsOnlyTheAskedReturn) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Dual);
  auto config = allReturns();
  config.return_mode = ov::ReturnMode::Last;
  const auto last = decodeCapture(path, config);
  config.return_mode = ov::ReturnMode::Strongest;
  const auto strongest = decodeCapture(path, config);
  const auto both = decodeCapture(path, allReturns());
  std::int64_t n_last = 0, n_strongest = 0, n_both = 0, n_dual_last = 0, n_dual_strongest = 0;
  for (const auto& s : last.scans)
    for (const auto& p : s.points) {
      EXPECT_NE(p.return_type, ov::ReturnType::Strongest);
      ++n_last;
    }
  for (const auto& s : strongest.scans)
    for (const auto& p : s.points) {
      EXPECT_NE(p.return_type, ov::ReturnType::Last);
      ++n_strongest;
    }
  for (const auto& s : both.scans)
    for (const auto& p : s.points) {
      n_both += p.return_type == ov::ReturnType::Both;
      n_dual_last += p.return_type == ov::ReturnType::Last;
      n_dual_strongest += p.return_type == ov::ReturnType::Strongest;
    }
  // Keeping one return does not change the packet period: no false loss.
  for (const auto* d : {&last, &strongest})
    for (const auto& s : d->scans) {
      EXPECT_EQ(s.packets_lost, 0);
      EXPECT_EQ(s.packets_expected, s.packets_received);
    }
  EXPECT_EQ(n_last, n_both + n_dual_last);
  EXPECT_EQ(n_strongest, n_both + n_dual_strongest);
}

TEST(RealCaptures, Hdl32eCaptureDecodesThirtyTwoRingsAndItsGpsFix) {
  OGF_REQUIRE_SHARED_FILE(path, kHdl32);
  const auto d = decodeCapture(path, allReturns());
  EXPECT_EQ(d.read_error, "");
  EXPECT_EQ(d.model, ov::Model::Hdl32E);
  EXPECT_EQ(d.counters.data_packets, 2702);
  EXPECT_EQ(d.counters.position_packets, 299);
  ASSERT_EQ(d.scans.size(), 19u);  // 18 wraps
  ASSERT_TRUE(d.last_position);
  EXPECT_EQ(d.last_position->pps, ov::PpsState::Absent);
  EXPECT_TRUE(d.last_position->gpsFixValid());
  EXPECT_NEAR(*d.last_position->fix->speed_knots, 0.0, 1e-9);
  // PPS absent: the hour comes from the host clock.
  EXPECT_EQ(d.scans.back().time_source, ov::TimeSource::HostHour);
  for (std::size_t i = 1; i + 1 < d.scans.size(); ++i) {
    // ~705 rpm, 552.96 us a packet: ~154 packets a turn.
    EXPECT_GE(d.scans[i].packets_received, 150);
    EXPECT_LE(d.scans[i].packets_received, 158);
    EXPECT_NEAR(d.scans[i].rpm, 705.0, 20.0);
    EXPECT_EQ(d.scans[i].packets_lost, 0);
  }
  expectFullScansCoverOneTurn(d.scans, 0.0);
  expectMonotonicTime(d.scans);
  expectRingOrder(d.scans, 32);
}

TEST(RealCaptures, ConfiguredModelWinsOverTheProductByte) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Strongest);
  auto config = allReturns();
  config.model = ov::Model::Hdl32E;  // wrong on purpose: configuration is obeyed
  const auto d = decodeCapture(path, config);
  EXPECT_EQ(d.model, ov::Model::Hdl32E);
}

TEST(RealCaptures, RangesStayWithinTheConfiguredLimits) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Moving);
  auto config = allReturns();
  config.min_range_m = 2.5;
  config.max_range_m = 30.0;
  const auto limited = decodeCapture(path, config);
  const auto all = decodeCapture(path, allReturns());
  std::int64_t inside = 0, n = 0;
  for (const auto& s : all.scans)
    for (const auto& p : s.points) {
      EXPECT_GT(p.distance_m, 0.0f);  // zero-range returns are dropped
      inside += p.distance_m >= 2.5f && p.distance_m <= 30.0f;
    }
  for (const auto& s : limited.scans)
    for (const auto& p : s.points) {
      EXPECT_GE(p.distance_m, 2.5f);
      EXPECT_LE(p.distance_m, 30.0f);
      ++n;
    }
  EXPECT_EQ(n, inside);
  EXPECT_GT(n, 0);
}

TEST(RealCaptures, DroppedPacketsAreCountedAsLost) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Moving);
  // Drop every 10th data packet after the first ones (runs of one): each gap is one lost packet.
  std::int64_t dropped = 0;
  const auto d = decodeCapture(path, allReturns(), [&dropped](std::int64_t i) {
    const bool drop = i > 5 && i % 10 == 0 && i < 280;
    dropped += drop;
    return !drop;
  });
  std::int64_t lost = 0;
  for (const auto& s : d.scans) lost += s.packets_lost;
  EXPECT_EQ(lost, dropped);
  for (const auto& s : d.scans) EXPECT_EQ(s.packets_expected, s.packets_received + s.packets_lost) << s.seq;
}

TEST(RealCaptures, ALongGapEndsTheScan) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Moving);
  // 40 packets missing (53 ms, longer than the 20 ms long-gap limit) in the middle of scan 1.
  const auto d = decodeCapture(path, allReturns(), [](std::int64_t i) { return i < 60 || i >= 100; });
  ASSERT_GE(d.scans.size(), 2u);
  bool gap_end = false;
  for (std::size_t i = 0; i + 1 < d.scans.size(); ++i)
    gap_end |= !d.scans[i].ends_at_cut && !d.scans[i + 1].starts_at_cut;
  EXPECT_TRUE(gap_end);
}

TEST(RealCaptures, CutAngleMovesWhereScansStart) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Strongest);
  auto config = allReturns();
  config.assembler.cut_angle_deg = 90.0;
  const auto d = decodeCapture(path, config);
  expectFullScansCoverOneTurn(d.scans, 90.0);
  EXPECT_GE(d.scans.size(), 51u);
}

TEST(RealCaptures, ShippedCalibrationFilesAgreeWithTheNominalTable) {
  OGF_REQUIRE_SHARED_FILE(path, kVlp16Moving);
  OGF_REQUIRE_SHARED_FILE(xml, "data/real/calib/VLP-16.xml");
  OGF_REQUIRE_SHARED_FILE(yaml, "data/real/calib/VLP16db.yaml");
  auto with_xml = allReturns();
  with_xml.calibration = *ov::loadCalibrationFile(xml);
  auto with_yaml = allReturns();
  with_yaml.calibration = *ov::loadCalibrationFile(yaml);
  const auto a = decodeCapture(path, with_xml);
  const auto b = decodeCapture(path, with_yaml);
  const auto nominal = decodeCapture(path, allReturns());
  ASSERT_EQ(a.scans.size(), b.scans.size());
  ASSERT_EQ(a.scans.size(), nominal.scans.size());
  for (std::size_t s = 0; s < a.scans.size(); ++s) {
    ASSERT_EQ(a.scans[s].points.size(), b.scans[s].points.size());
    ASSERT_EQ(a.scans[s].points.size(), nominal.scans[s].points.size());
    for (std::size_t i = 0; i < a.scans[s].points.size(); ++i) {
      const auto& p = a.scans[s].points[i];
      const auto& q = b.scans[s].points[i];
      const auto& n = nominal.scans[s].points[i];
      EXPECT_NEAR(p.x, q.x, 1e-4);
      EXPECT_NEAR(p.z, q.z, 1e-4);
      // The files have zero offsets; the nominal table adds the per-laser vertical offset (<= 11.2 mm).
      EXPECT_NEAR(p.z, n.z, 0.0125);
      EXPECT_EQ(p.ring, n.ring);
    }
  }
}
