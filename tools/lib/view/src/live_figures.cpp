#include "ogf/view/live_figures.hpp"

#include <fmt/format.h>

#include <cmath>

#include "ogf/common/json_string.hpp"
#include "ogf/messages/source_status_names.hpp"

namespace ogf::view {
namespace {

std::string number(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : "null"; }

std::string poseJson(const PoseTrail& trail, std::size_t from) {
  if (!trail.latest()) return "null";
  const fusion::Pose& p = *trail.latest();
  std::string points;
  const auto& pts = trail.points();
  for (std::size_t i = from; i < pts.size(); ++i) {
    if (!points.empty()) points += ',';
    points += fmt::format("{:.3f},{:.3f},{:.3f}", pts[i][0], pts[i][1], pts[i][2]);
  }
  return fmt::format(
      R"({{"utime":{},"position":[{},{},{}],"orientation":[{},{},{},{}],"poses":{},"trail_from":{},"trail_size":{},"trail":[{}]}})",
      p.utime, number(p.position.x()), number(p.position.y()), number(p.position.z()), number(p.orientation.w()),
      number(p.orientation.x()), number(p.orientation.y()), number(p.orientation.z()), trail.posesSeen(),
      std::min(from, pts.size()), pts.size(), points);
}

// The mapper's sources: who each is (robot, sensor, channels), its state and counts, and its trail in the
// map frame (at most 64 points, so sent whole in every frame).
std::string sourcesJson(const ogf::mapper_status_t& m) {
  std::string out = "[";
  for (const auto& src : m.sources) {
    if (out.size() > 1) out += ',';
    std::string trail;
    for (const auto& p : src.trail) {
      if (!trail.empty()) trail += ',';
      trail += fmt::format("{:.3f},{:.3f},{:.3f}", p[0], p[1], p[2]);
    }
    const std::int64_t dropped = ogf::messages::scansDropped(src) + src.scans_rejected;
    out += fmt::format(
        R"({{"name":{},"robot":{},"scan_channel":{},"packets":{},"pose_channel":{},"inputs":{},"scans_in":{},"scans_mapped":{},"dropped":{},"trail":[{}]}})",
        ogf::jsonString(src.name), ogf::jsonString(src.robot), ogf::jsonString(src.scan_channel),
        src.packets ? "true" : "false", ogf::jsonString(src.pose_channel),
        ogf::jsonString(ogf::messages::inputsName(src.inputs)), src.scans_in, src.scans_mapped, dropped, trail);
  }
  return out + "]";
}

}  // namespace

void LiveFigures::mapperStatus(const ogf::mapper_status_t& s) {
  if (mapper_ && s.utime > mapper_->utime && s.scans_mapped >= mapper_->scans_mapped) {
    mapper_scan_rate_hz_ =
        static_cast<double>(s.scans_mapped - mapper_->scans_mapped) / (static_cast<double>(s.utime - mapper_->utime) * 1e-6);
  }
  mapper_ = s;
}

void LiveFigures::driverStatus(const ogf::driver_status_t& s) { driver_ = s; }

std::string LiveFigures::json(const StreamFigures& st, std::size_t raw_from, std::size_t corrected_from,
                              const NavFigures* nav) const {
  const std::string stream = fmt::format(
      R"({{"source":{},"seq":{},"cells":{},"occupied":{},"boxes":{},"lod":{},"gaps":{},"keyframes":{},"malformed":{},"messages":{},"consistent":{},"waiting_for_keyframe":{},"resolution":{}}})",
      ogf::jsonString(st.source), st.seq, st.cells, st.occupied, st.boxes, st.lod, st.gaps, st.keyframes, st.malformed, st.messages,
      st.consistent, st.waiting_for_keyframe, number(st.resolution));
  std::string nav_json = "null";
  if (nav) {
    const auto& n = *nav;
    nav_json = fmt::format(
        R"({{"seq":{},"known_columns":{},"tiles":{},"tiles_not_drawn":{},"gaps":{},"keyframes":{},"malformed":{},"messages":{},"consistent":{},"waiting_for_keyframe":{},"resolution":{},"floor_z":{},"min_height":{},"max_height":{}}})",
        n.seq, n.known_columns, n.tiles, n.tiles_not_drawn, n.gaps, n.keyframes, n.malformed, n.messages, n.consistent,
        n.waiting_for_keyframe, number(n.resolution), number(n.floor_z), number(n.min_height), number(n.max_height));
  }
  std::string mapper = "null";
  if (mapper_) {
    const auto& m = *mapper_;
    mapper = fmt::format(
        R"({{"utime":{},"scans_in":{},"scans_mapped":{},"scan_rate_hz":{},"dropped_behind":{},"dropped_no_pose":{},"late":{},"rejected":{},"lag_ms":{},"update_ms_mean":{},"cells":{},"memory_bytes":{},"delta_seq":{},"persistence_ok":{},"sources":{}}})",
        m.utime, m.scans_in, m.scans_mapped, mapper_scan_rate_hz_ < 0 ? "null" : number(mapper_scan_rate_hz_),
        m.scans_dropped_behind, m.scans_dropped_no_pose, m.scans_late, m.scans_rejected, number(m.lag_ms),
        number(m.update_ms_mean), m.cells, m.memory_bytes, m.delta_seq, m.persistence_ok, sourcesJson(m));
  }
  std::string driver = "null";
  if (driver_) {
    const auto& d = *driver_;
    driver = fmt::format(
        R"({{"utime":{},"source":{},"rpm":{},"packet_rate_hz":{},"scan_rate_hz":{},"packets_lost":{},"kernel_drops":{},"bad":{},"pps_state":{}}})",
        d.utime, ogf::jsonString(d.source), number(d.rpm), number(d.packet_rate_hz), number(d.scan_rate_hz), d.packets_lost,
        d.kernel_drops, d.bad_size + d.bad_block_flag + d.foreign_sender + d.bad_other, static_cast<int>(d.pps_state));
  }
  return fmt::format(R"({{"type":"status","stream":{},"nav":{},"mapper":{},"driver":{},"pose":{},"corrected":{}}})",
                     stream, nav_json, mapper, driver, poseJson(raw_, raw_from), poseJson(corrected_, corrected_from));
}

}  // namespace ogf::view
