// CARMEN log records as the Freiburg 2-D SLAM benchmark stores them (ODOM, FLASER, ROBOTLASER1), read
// from a stream, and the result log a SLAM run writes back: every laser record with the corrected robot
// pose in both pose triples and the record's original ipc_timestamp, the form the benchmark's evaluator
// reads (docs/test-data.md §3.2 and §3.4).
#pragma once

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ogf/common/result.hpp"

namespace ogf::slam_io {

// A planar pose: metres and radians, theta normalised to (-pi, pi].
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

// The three fields every CARMEN line ends with. The timestamp text is kept verbatim so that a result log
// repeats it to the last digit (relations are matched to these stamps).
struct Stamp {
  double ipc_timestamp = 0.0;
  std::string ipc_timestamp_text;
  std::string ipc_hostname;
  double logger_timestamp = 0.0;
};

// ODOM x y theta tv rv accel
struct OdometryRecord {
  Pose2 pose;
  double tv = 0.0;
  double rv = 0.0;
  double accel = 0.0;
  Stamp stamp;
  std::size_t line = 0;  // 1-based line number in the source
};

// FLASER or ROBOTLASER1, normalised to one shape. Beam i points at start_angle + i * angular_resolution
// in the laser frame. FLASER has no angle fields: 180 degrees from -90 degrees, resolution 180/(n-1)
// degrees for n = 181 or 361, taken as 1 and 0.5 degrees for n = 180 and 360 (GMapping's convention).
struct LaserRecord {
  enum class Kind { kFlaser, kRobotLaser1 };
  Kind kind = Kind::kFlaser;
  double start_angle = 0.0;         // radians
  double angular_resolution = 0.0;  // radians
  double max_range = 0.0;           // metres; a reading at or beyond it means "no return"
  std::vector<float> ranges;        // metres
  Pose2 laser_pose;                 // FLASER's first triple, ROBOTLASER1's laser_pose
  Pose2 robot_pose;                 // FLASER's second (odom) triple, ROBOTLASER1's robot_pose
  Stamp stamp;
  std::size_t line = 0;
  std::string original_line;        // kept so the result log can rewrite only the pose fields
};

using Record = std::variant<OdometryRecord, LaserRecord>;

// FLASER lines carry no maximum range. The benchmark logs mark "no return" with 81.83 (intel), 50.00
// (aces) and 81.91 (fr079), and hold no valid reading above 50 m, so FLASER records get this maximum
// unless the log's "PARAM robot_front_laser_max" (fr079: 80.99) or setFlaserMaxRange says otherwise.
inline constexpr double kFlaserDefaultMaxRange = 50.0;

// Reads records one at a time. Comment lines (#), blank lines and other message types (PARAM, SYNC,
// TRUEPOS, ...) are skipped and counted; a malformed ODOM/FLASER/ROBOTLASER1 line is reported as an
// Error naming the source and line, counted, and reading goes on with the next line.
class CarmenReader {
 public:
  CarmenReader(std::istream& in, std::string source_name);

  // The next record; std::nullopt at end of input. A malformed line gives an Error; call again to go on.
  std::optional<Result<Record>> next();

  std::size_t linesRead() const;
  std::size_t linesSkipped() const;    // comments, blank lines and other message types
  std::size_t linesMalformed() const;

  // The maximum range given to FLASER records from now on (overrides the default and the PARAM line).
  void setFlaserMaxRange(double metres);

 private:
  std::optional<Result<Record>> parseLine(const std::string& line);

  std::istream& in_;
  std::string source_name_;
  std::size_t lines_read_ = 0;
  std::size_t lines_skipped_ = 0;
  std::size_t lines_malformed_ = 0;
  double flaser_max_range_ = kFlaserDefaultMaxRange;
  bool flaser_max_range_set_ = false;
};

// Writes one result record: the laser record with `corrected` in both pose triples (FLASER) or in
// laser_pose and robot_pose (ROBOTLASER1; the laser pose keeps its offset from the robot), its ranges and
// its original stamp, one line.
void writeResultRecord(std::ostream& out, const LaserRecord& record, const Pose2& corrected);

}  // namespace ogf::slam_io
