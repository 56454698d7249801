#include "ogf/velodyne/scan_assembler.hpp"

#include <algorithm>
#include <cmath>

namespace ogf::velodyne {
namespace {
constexpr int kTurn = wire::kAzimuthUnitsPerTurn;
}

ScanAssembler::ScanAssembler(ScanAssemblerConfig config) : config_(config) {
  const double cut = std::fmod(std::fmod(config_.cut_angle_deg, 360.0) + 360.0, 360.0);
  cut_units_ = static_cast<int>(std::lround(cut * 100.0)) % kTurn;
  scan_.points.reserve(config_.reserve_points);
}

void ScanAssembler::begin(std::int64_t start_ns, const PacketTime& time, Model model, ReturnMode mode,
                          bool at_cut) {
  scan_.clear();
  open_ = true;
  scan_.seq = next_seq_;
  scan_.model = model;
  scan_.return_mode = mode;
  scan_.cut_angle_deg = static_cast<float>(cut_units_ / 100.0);
  scan_.time_source = time.device.source;
  scan_.starts_at_cut = at_cut;
  start_ns_ = start_ns;
  last_firing_ns_ = start_ns;
  scan_.device_utime_start = start_ns / 1000;
  scan_.host_utime_start = time.host_utime;
  advance_units_ = 0;
  packet_counted_ = false;
}

void ScanAssembler::countPacket(const PacketTime& time) {
  if (packet_counted_) return;
  packet_counted_ = true;
  ++scan_.packets_received;
  scan_.packets_lost += pending_lost_;
  pending_lost_ = 0;
  scan_.host_utime_end = time.host_utime;
}

void ScanAssembler::finish(const Sink& sink, bool at_cut) {
  if (!open_) return;
  open_ = false;
  scan_.ends_at_cut = at_cut;
  scan_.device_utime_end = last_firing_ns_ / 1000;
  // The packets the scan's span should hold at the fixed packet period: those that came and those lost.
  scan_.packets_expected = scan_.packets_received + scan_.packets_lost;
  const double span_us = static_cast<double>(last_firing_ns_ - start_ns_) / 1000.0;
  scan_.rpm =
      span_us > 0 ? static_cast<float>(static_cast<double>(advance_units_) / kTurn / (span_us / 60e6)) : 0.0f;
  if (scan_.rpm > 0) last_rpm_ = scan_.rpm;
  ++next_seq_;
  if (sink) sink(scan_);
}

void ScanAssembler::add(const DecodedPacket& packet, const PacketTime& time, Model model, const Sink& sink) {
  period_us_ = packetPeriodUs(model, packet.dual_layout ? ReturnMode::Dual : ReturnMode::Strongest);
  if (prev_host_utime_ && static_cast<double>(time.host_utime - *prev_host_utime_) > config_.pause_us) {
    // A pause: the open scan is dropped, not emitted late (see the header), and the time since is no loss.
    if (open_) {
      open_ = false;
      ++dropped_at_pause_;
      packets_dropped_at_pause_ += scan_.packets_received;
    }
    prev_azimuth_.reset();
    prev_packet_utime_.reset();
    pending_lost_ = 0;
  }
  prev_host_utime_ = time.host_utime;
  // Loss from the device-time gap to the previous packet.
  if (prev_packet_utime_) {
    const double gap = static_cast<double>(time.device.utime - *prev_packet_utime_);
    if (gap > config_.long_gap_us || gap < -period_us_ / 2) {
      finish(sink, false);
      prev_azimuth_.reset();
    } else if (gap > 1.5 * period_us_) {
      // Counted in the scan that receives the packet after the gap.
      pending_lost_ = static_cast<std::int32_t>(std::llround(gap / period_us_) - 1);
      lost_total_ += pending_lost_;
    }
  }
  prev_packet_utime_ = time.device.utime;
  if (open_ && (scan_.model != model || scan_.return_mode != packet.return_mode)) {
    finish(sink, false);
    prev_azimuth_.reset();
  }
  packet_counted_ = false;

  const std::int64_t packet_ns = time.device.utime * 1000;
  // Azimuth advance from the previous firing, and whether that passes the cut angle or a full turn.
  auto advanceTo = [this](int az) {
    const int d = (az - *prev_azimuth_ + kTurn) % kTurn;
    return d > kTurn / 2 ? 0 : d;  // a backwards jitter is no advance
  };
  auto passesCut = [this](int from, int advance) {
    const int before = (from - cut_units_ + kTurn) % kTurn;
    return advance > 0 && before + advance >= kTurn;
  };
  // Every laser firing, in time order, may be the one that crosses the cut: the first firing of each
  // sequence (so a sequence without returns still counts) and then each point of it.
  auto step = [&](int az, std::int64_t t_ns) {
    bool cut = false;
    if (prev_azimuth_ && open_) {
      const int advance = advanceTo(az);
      if (passesCut(*prev_azimuth_, advance))
        cut = true;
      else if (advance_units_ + advance >= kTurn)
        cut = true;  // never more than one turn
      else
        advance_units_ += advance;
    }
    prev_azimuth_ = az;
    if (cut) finish(sink, true);
    if (!open_) begin(t_ns, time, model, packet.return_mode, cut);
    countPacket(time);
    last_firing_ns_ = std::max(last_firing_ns_, t_ns);
  };
  auto append = [this](const Point& p, std::int64_t t_ns) __attribute__((always_inline)) {
    const std::int64_t offset = t_ns - scan_.device_utime_start * 1000;
    scan_.points.push_back(
        ScanPoint{p.x, p.y, p.z, p.distance_m, p.azimuthDeg(),
                  static_cast<std::int32_t>(std::clamp<std::int64_t>(offset, 0, INT32_MAX)), p.intensity,
                  p.ring, p.laser_id, p.return_type});
  };
  int point = 0;
  for (int f = 0; f < packet.firing_count; ++f) {
    const int firing_az = packet.firing_azimuth[static_cast<std::size_t>(f)];
    const std::int64_t firing_ns = packet_ns + packet.firing_time_ns[static_cast<std::size_t>(f)];
    int end = point;
    while (end < packet.point_count && packet.points[static_cast<std::size_t>(end)].firing == f) ++end;
    // Fast path: a firing whose start and last return neither pass the cut nor complete a turn cannot
    // hold the crossing (azimuths rise within a firing), so its points are appended without checks.
    if (open_ && prev_azimuth_) {
      const int last_az = end > point ? packet.points[static_cast<std::size_t>(end) - 1].azimuth : firing_az;
      const int to_start = advanceTo(firing_az);
      const int d = (last_az - firing_az + kTurn) % kTurn;
      const int within = d > kTurn / 2 ? 0 : d;
      if (!passesCut(*prev_azimuth_, to_start) && !passesCut(firing_az, within) &&
          advance_units_ + to_start + within < kTurn) {
        advance_units_ += to_start + within;
        prev_azimuth_ = last_az;
        countPacket(time);
        // One size change per firing, then plain stores (the capacity is reserved up front).
        const std::size_t first = scan_.points.size();
        scan_.points.resize(first + static_cast<std::size_t>(end - point));
        ScanPoint* out = scan_.points.data() + first;
        const std::int64_t base_ns = packet_ns - scan_.device_utime_start * 1000;
        for (; point < end; ++point, ++out) {
          const Point& p = packet.points[static_cast<std::size_t>(point)];
          const std::int64_t offset = base_ns + p.time_offset_ns;
          *out = ScanPoint{p.x,
                           p.y,
                           p.z,
                           p.distance_m,
                           p.azimuthDeg(),
                           static_cast<std::int32_t>(std::clamp<std::int64_t>(offset, 0, INT32_MAX)),
                           p.intensity,
                           p.ring,
                           p.laser_id,
                           p.return_type};
        }
        const std::int64_t last_ns =
            end > 0 && packet.points[static_cast<std::size_t>(end) - 1].firing == f
                ? packet_ns + packet.points[static_cast<std::size_t>(end) - 1].time_offset_ns
                : firing_ns;
        last_firing_ns_ = std::max(last_firing_ns_, std::max(firing_ns, last_ns));
        continue;
      }
    }
    step(firing_az, firing_ns);
    for (; point < end; ++point) {
      const Point& p = packet.points[static_cast<std::size_t>(point)];
      const std::int64_t t_ns = packet_ns + p.time_offset_ns;
      step(p.azimuth, t_ns);
      append(p, t_ns);
    }
  }
}

void ScanAssembler::flush(const Sink& sink) {
  finish(sink, false);
  prev_azimuth_.reset();
  prev_packet_utime_.reset();
  prev_host_utime_.reset();
  pending_lost_ = 0;
}

}  // namespace ogf::velodyne
