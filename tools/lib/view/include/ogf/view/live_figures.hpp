// What the page shows beside the map: the delta stream's state (seq, cells, gaps, keyframes, whether the
// map equals the mapper's), the mapper's and the driver's status (scan rate, lag, drops), the mapper's
// sources (robot, sensor, state, counts and the sensor's trail in the map frame), and the robot's poses
// with their trails, as one JSON text frame. Figures not yet known are null.
#pragma once

#include <ogf/driver_status_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <cstdint>
#include <optional>
#include <string>

#include "ogf/view/pose_trail.hpp"

namespace ogf::view {

struct StreamFigures {
  std::string source;             // "live" or the map file's path
  std::int64_t seq = -1;          // last update applied
  std::size_t cells = 0;          // cells in the map
  std::size_t occupied = 0;       // of which occupied
  std::size_t boxes = 0;          // boxes drawn for them
  std::int32_t lod = 1;           // cells a box spans along each axis
  std::uint64_t gaps = 0;
  std::uint64_t keyframes = 0;
  std::uint64_t malformed = 0;
  std::uint64_t messages = 0;
  bool consistent = false;
  bool waiting_for_keyframe = false;
  double resolution = 0.0;
};

// The 2-D navigation grid's stream (OGF_NAV_GRID): its state as the view follows it, and its band.
struct NavFigures {
  std::int64_t seq = -1;            // last update applied
  std::size_t known_columns = 0;
  std::size_t tiles = 0;            // tiles drawn
  std::size_t tiles_not_drawn = 0;  // known tiles beyond the view's bound (nav_tiles.hpp)
  std::uint64_t gaps = 0;
  std::uint64_t keyframes = 0;
  std::uint64_t malformed = 0;      // messages that did not decode or did not agree with themselves
  std::uint64_t messages = 0;
  bool consistent = false;
  bool waiting_for_keyframe = true;
  double resolution = 0.0;
  double floor_z = 0.0;
  double min_height = 0.0;
  double max_height = 0.0;
};

class LiveFigures {
 public:
  void mapperStatus(const ogf::mapper_status_t& s);
  void driverStatus(const ogf::driver_status_t& s);
  PoseTrail& trail(bool corrected) { return corrected ? corrected_ : raw_; }

  // The JSON frame: {"type":"status", "stream":{...}, "nav":{...}|null, "mapper":{...}|null,
  // "driver":{...}|null, "pose":{...}|null, "corrected":{...}|null}; each pose object carries its trail's
  // points from the given index on (0 for a newcomer, else what the last frame ended at) and the trail's
  // length. "nav" is null without `nav` (a saved map shown).
  std::string json(const StreamFigures& stream, std::size_t raw_from, std::size_t corrected_from,
                   const NavFigures* nav = nullptr) const;

 private:
  std::optional<ogf::mapper_status_t> mapper_;
  std::optional<ogf::driver_status_t> driver_;
  double mapper_scan_rate_hz_ = -1.0;  // from two successive statuses; < 0 unknown
  PoseTrail raw_;
  PoseTrail corrected_;
};

}  // namespace ogf::view
