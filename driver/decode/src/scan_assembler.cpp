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

void ScanAssembler::begin(std::int64_t start_ns, const PacketTime& time, Model model, ReturnMode mode, bool at_cut) {
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
  first_packet_utime_ = time.device.utime;
  advance_units_ = 0;
  packet_counted_ = false;
}

void ScanAssembler::countPacket(const PacketTime& time) {
  if (packet_counted_) return;
  packet_counted_ = true;
  ++scan_.packets_received;
  last_packet_utime_ = time.device.utime;
  scan_.host_utime_end = time.host_utime;
}

void ScanAssembler::finish(const Sink& sink, bool at_cut) {
  if (!open_) return;
  open_ = false;
  scan_.ends_at_cut = at_cut;
  scan_.device_utime_end = last_firing_ns_ / 1000;
  scan_.packets_expected =
      static_cast<std::int32_t>(std::llround(static_cast<double>(last_packet_utime_ - first_packet_utime_) / period_us_)) + 1;
  const double span_us = static_cast<double>(last_firing_ns_ - start_ns_) / 1000.0;
  scan_.rpm = span_us > 0 ? static_cast<float>(static_cast<double>(advance_units_) / kTurn / (span_us / 60e6)) : 0.0f;
  if (scan_.rpm > 0) last_rpm_ = scan_.rpm;
  ++next_seq_;
  if (sink) sink(scan_);
}

void ScanAssembler::add(const DecodedPacket& packet, const PacketTime& time, Model model, const Sink& sink) {
  period_us_ = packetPeriodUs(model, packet.dual_layout ? ReturnMode::Dual : ReturnMode::Strongest);
  // Loss from the device-time gap to the previous packet.
  if (prev_packet_utime_) {
    const double gap = static_cast<double>(time.device.utime - *prev_packet_utime_);
    if (gap > config_.long_gap_us || gap < -period_us_ / 2) {
      finish(sink, false);
      prev_azimuth_.reset();
    } else if (gap > 1.5 * period_us_) {
      const auto lost = static_cast<std::int32_t>(std::llround(gap / period_us_) - 1);
      if (open_) scan_.packets_lost += lost;
      lost_total_ += lost;
    }
  }
  prev_packet_utime_ = time.device.utime;
  if (open_ && (scan_.model != model || scan_.return_mode != packet.return_mode)) {
    finish(sink, false);
    prev_azimuth_.reset();
  }
  packet_counted_ = false;

  const std::int64_t packet_ns = time.device.utime * 1000;
  // Every laser firing, in time order, may be the one that crosses the cut: the first firing of each
  // sequence (so a sequence without returns still counts) and then each point of it.
  auto step = [&](int az, std::int64_t t_ns) {
    bool cut = false;
    if (prev_azimuth_ && open_) {
      const int d = (az - *prev_azimuth_ + kTurn) % kTurn;
      const int advance = d > kTurn / 2 ? 0 : d;  // a backwards jitter is no advance
      const int before = (*prev_azimuth_ - cut_units_ + kTurn) % kTurn;
      if (advance > 0 && before + advance >= kTurn) cut = true;  // this firing passed the cut angle
      else if (advance_units_ + advance >= kTurn) cut = true;    // never more than one turn
      else advance_units_ += advance;
    }
    prev_azimuth_ = az;
    if (cut) finish(sink, true);
    if (!open_) begin(t_ns, time, model, packet.return_mode, cut);
    countPacket(time);
    last_firing_ns_ = std::max(last_firing_ns_, t_ns);
  };
  int point = 0;
  for (int f = 0; f < packet.firing_count; ++f) {
    step(packet.firing_azimuth[static_cast<std::size_t>(f)],
         packet_ns + std::llround(packet.firing_time_us[static_cast<std::size_t>(f)] * 1000.0f));
    for (; point < packet.point_count && packet.points[static_cast<std::size_t>(point)].firing == f; ++point) {
      const Point& p = packet.points[static_cast<std::size_t>(point)];
      const std::int64_t t_ns = packet_ns + std::llround(p.time_offset_us * 1000.0f);
      step(static_cast<int>(std::lround(p.azimuth_deg * 100.0f)) % kTurn, t_ns);
      const std::int64_t offset = t_ns - scan_.device_utime_start * 1000;
      scan_.points.push_back(ScanPoint{p.x, p.y, p.z, p.distance_m, p.azimuth_deg,
                                       static_cast<std::int32_t>(std::clamp<std::int64_t>(offset, 0, INT32_MAX)),
                                       p.intensity, p.ring, p.laser_id, p.return_type});
    }
  }
}

void ScanAssembler::flush(const Sink& sink) {
  finish(sink, false);
  prev_azimuth_.reset();
  prev_packet_utime_.reset();
}

}  // namespace ogf::velodyne
