// Words for the codes of a mapper status and its sources (messages/lcmtypes/ogf_mapper_status_t.lcm,
// ogf_source_status_t.lcm), as the tools print them, and the scans a source dropped, all reasons summed.
#pragma once

#include <ogf/mapper_status_t.hpp>
#include <ogf/source_status_t.hpp>

#include <cstdint>

namespace ogf::messages {

inline const char* inputsName(std::int8_t inputs) {
  switch (inputs) {
    case mapper_status_t::INPUTS_OK: return "ok";
    case mapper_status_t::INPUTS_WAITING_FOR_POSES: return "waiting_for_poses";
    case mapper_status_t::INPUTS_WAITING_FOR_SCANS: return "waiting_for_scans";
    default: return "silent";  // INPUTS_NONE: neither scans nor poses arrive
  }
}

inline const char* clocksName(std::int8_t clocks) {
  switch (clocks) {
    case mapper_status_t::CLOCKS_AGREE: return "agree";
    case mapper_status_t::CLOCKS_DISAGREE: return "disagree";
    default: return "unknown";
  }
}

// Scans that arrived and were not mapped for lack of time, pose or order, or throttled (not counting the
// rejected, whose content was bad).
inline std::int64_t scansDropped(const source_status_t& s) {
  return s.scans_dropped_behind + s.scans_dropped_no_pose + s.scans_late + s.scans_refused_time +
         s.scans_dropped_pose_jump + s.scans_throttled;
}

}  // namespace ogf::messages
