// Reading CARMEN log records (ODOM, FLASER, ROBOTLASER1) and writing the benchmark's result records. The
// field layouts are the logs' own header comments (docs/test-data.md §3.2).
#include "ogf/slam_io/carmen_log.hpp"

#include <array>
#include <charconv>
#include <cstdio>
#include <istream>
#include <numbers>
#include <ostream>
#include <span>
#include <string_view>

#include "pose2_math.hpp"
#include "text_fields.hpp"

namespace ogf::slam_io {

namespace {

using detail::parseCount;
using detail::parseDouble;
using detail::splitFields;
using Fields = std::vector<std::string_view>;

constexpr double kDegree = std::numbers::pi / 180.0;

// Every line ends with "ipc_timestamp ipc_hostname logger_timestamp".
constexpr std::size_t kStampFields = 3;
// ODOM x y theta tv rv accel + stamp.
constexpr std::size_t kOdomFields = 1 + 6 + kStampFields;
// FLASER n [n ranges] x y theta odom_x odom_y odom_theta + stamp.
constexpr std::size_t kFlaserFixedFields = 2 + 6 + kStampFields;
// ROBOTLASER1 type start fov res max accuracy remission_mode n [n] m [m] laser(3) robot(3) tv rv fwd side
// turn_axis + stamp.
constexpr std::size_t kRobotLaserFixedFields = 1 + 7 + 1 + 1 + 6 + 5 + kStampFields;

// Builds the error for a line; `what` says which field or count was wrong.
Error lineError(const std::string& source, std::size_t line, std::string_view kind, const std::string& what) {
  return Error{source + ":" + std::to_string(line) + ": " + std::string(kind) + ": " + what};
}

// Parses fields [first, first + out.size()) as doubles, naming the first bad one in `bad`.
bool parseDoubles(const Fields& f, std::size_t first, std::span<double> out, std::size_t& bad) {
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto v = parseDouble(f[first + i]);
    if (!v) {
      bad = first + i;
      return false;
    }
    out[i] = *v;
  }
  return true;
}

std::string badField(const Fields& f, std::size_t i) {
  return "field " + std::to_string(i + 1) + " '" + std::string(f[i]) + "' is not a finite number";
}

Pose2 pose(double x, double y, double theta) { return {x, y, detail::normalizeAngle(theta)}; }

// The three stamp fields starting at `first`.
std::optional<Stamp> parseStamp(const Fields& f, std::size_t first) {
  const auto ipc = parseDouble(f[first]);
  const auto logger = parseDouble(f[first + 2]);
  if (!ipc || !logger) return std::nullopt;
  return Stamp{*ipc, std::string(f[first]), std::string(f[first + 1]), *logger};
}

// FLASER's angles (GMapping's CARMEN reader; docs/test-data.md §3.2): 180 degrees from -90 degrees; 1 and 0.5
// degree steps for 180 and 360 beams, 180/(n-1) degrees otherwise (181, 361, ...).
double flaserResolution(std::size_t n) {
  if (n == 180) return 1.0 * kDegree;
  if (n == 360) return 0.5 * kDegree;
  return n > 1 ? 180.0 * kDegree / static_cast<double>(n - 1) : 0.0;
}

std::string formatFixed(double v) {
  std::array<char, 64> buf{};
  const int n = std::snprintf(buf.data(), buf.size(), "%.6f", v);
  return std::string(buf.data(), static_cast<std::size_t>(n));
}

std::string formatShortest(double v) {
  std::array<char, 64> buf{};
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return ec == std::errc{} ? std::string(buf.data(), end) : formatFixed(v);
}

void putPose(std::vector<std::string>& fields, std::size_t first, const Pose2& p) {
  fields[first] = formatFixed(p.x);
  fields[first + 1] = formatFixed(p.y);
  fields[first + 2] = formatFixed(p.theta);
}

}  // namespace

CarmenReader::CarmenReader(std::istream& in, std::string source_name)
    : in_(in), source_name_(std::move(source_name)) {}

std::size_t CarmenReader::linesRead() const { return lines_read_; }
std::size_t CarmenReader::linesSkipped() const { return lines_skipped_; }
std::size_t CarmenReader::linesMalformed() const { return lines_malformed_; }

void CarmenReader::setFlaserMaxRange(double metres) {
  flaser_max_range_ = metres;
  flaser_max_range_set_ = true;
}

std::optional<Result<Record>> CarmenReader::next() {
  std::string line;
  while (std::getline(in_, line)) {
    ++lines_read_;
    auto parsed = parseLine(line);
    if (!parsed) {
      ++lines_skipped_;
      continue;
    }
    if (!parsed->ok()) ++lines_malformed_;
    return parsed;
  }
  return std::nullopt;
}

std::optional<Result<Record>> CarmenReader::parseLine(const std::string& line) {
  const Fields f = splitFields(line);
  if (f.empty() || f[0].front() == '#') return std::nullopt;
  const std::string_view kind = f[0];
  const std::size_t ln = lines_read_;
  std::size_t bad = 0;

  if (kind == "PARAM") {
    // PARAM robot_front_laser_max <metres> ...: the front laser's maximum range (fr079).
    if (f.size() >= 3 && f[1] == "robot_front_laser_max" && !flaser_max_range_set_) {
      if (const auto v = parseDouble(f[2]); v && *v > 0.0) flaser_max_range_ = *v;
    }
    return std::nullopt;
  }

  if (kind == "ODOM") {
    if (f.size() != kOdomFields) {
      return Result<Record>(
          lineError(source_name_, ln, kind,
                    "expected " + std::to_string(kOdomFields) + " fields, got " + std::to_string(f.size())));
    }
    std::array<double, 6> v{};
    if (!parseDoubles(f, 1, v, bad))
      return Result<Record>(lineError(source_name_, ln, kind, badField(f, bad)));
    const auto stamp = parseStamp(f, 7);
    if (!stamp) return Result<Record>(lineError(source_name_, ln, kind, "bad timestamp fields"));
    OdometryRecord r;
    r.pose = pose(v[0], v[1], v[2]);
    r.tv = v[3];
    r.rv = v[4];
    r.accel = v[5];
    r.stamp = *stamp;
    r.line = ln;
    return Result<Record>(Record(std::move(r)));
  }

  if (kind == "FLASER") {
    const auto n = f.size() >= 2 ? parseCount(f[1]) : std::nullopt;
    if (!n) return Result<Record>(lineError(source_name_, ln, kind, "missing or bad num_readings"));
    if (*n > f.size() || f.size() != kFlaserFixedFields + *n) {
      return Result<Record>(lineError(source_name_, ln, kind,
                                      "num_readings " + std::to_string(*n) + " needs " +
                                          std::to_string(kFlaserFixedFields + *n) + " fields, got " +
                                          std::to_string(f.size())));
    }
    LaserRecord r;
    r.kind = LaserRecord::Kind::kFlaser;
    r.ranges.resize(*n);
    for (std::size_t i = 0; i < *n; ++i) {
      const auto v = parseDouble(f[2 + i]);
      if (!v) return Result<Record>(lineError(source_name_, ln, kind, badField(f, 2 + i)));
      r.ranges[i] = static_cast<float>(*v);
    }
    std::array<double, 6> p{};
    if (!parseDoubles(f, 2 + *n, p, bad))
      return Result<Record>(lineError(source_name_, ln, kind, badField(f, bad)));
    const auto stamp = parseStamp(f, 8 + *n);
    if (!stamp) return Result<Record>(lineError(source_name_, ln, kind, "bad timestamp fields"));
    r.start_angle = -90.0 * kDegree;
    r.angular_resolution = flaserResolution(*n);
    r.max_range = flaser_max_range_;
    r.laser_pose = pose(p[0], p[1], p[2]);
    r.robot_pose = pose(p[3], p[4], p[5]);
    r.stamp = *stamp;
    r.line = ln;
    r.original_line = line;
    return Result<Record>(Record(std::move(r)));
  }

  if (kind == "ROBOTLASER1") {
    const auto n = f.size() >= 9 ? parseCount(f[8]) : std::nullopt;
    if (!n || *n > f.size())
      return Result<Record>(lineError(source_name_, ln, kind, "missing or bad num_readings"));
    const auto m = f.size() >= 10 + *n ? parseCount(f[9 + *n]) : std::nullopt;
    if (!m || *m > f.size())
      return Result<Record>(lineError(source_name_, ln, kind, "missing or bad num_remissions"));
    if (f.size() != kRobotLaserFixedFields + *n + *m) {
      return Result<Record>(lineError(
          source_name_, ln, kind,
          "num_readings " + std::to_string(*n) + " and num_remissions " + std::to_string(*m) + " need " +
              std::to_string(kRobotLaserFixedFields + *n + *m) + " fields, got " + std::to_string(f.size())));
    }
    std::array<double, 6> header{};  // laser_type start_angle fov angular_resolution max_range accuracy
    if (!parseDoubles(f, 1, header, bad))
      return Result<Record>(lineError(source_name_, ln, kind, badField(f, bad)));
    LaserRecord r;
    r.kind = LaserRecord::Kind::kRobotLaser1;
    r.ranges.resize(*n);
    for (std::size_t i = 0; i < *n; ++i) {
      const auto v = parseDouble(f[9 + i]);
      if (!v) return Result<Record>(lineError(source_name_, ln, kind, badField(f, 9 + i)));
      r.ranges[i] = static_cast<float>(*v);
    }
    for (std::size_t i = 0; i < *m; ++i) {
      if (!parseDouble(f[10 + *n + i]))
        return Result<Record>(lineError(source_name_, ln, kind, badField(f, 10 + *n + i)));
    }
    const std::size_t p0 = 10 + *n + *m;
    std::array<double, 11> tail{};  // laser pose, robot pose, tv rv forward side turn_axis
    if (!parseDoubles(f, p0, tail, bad))
      return Result<Record>(lineError(source_name_, ln, kind, badField(f, bad)));
    const auto stamp = parseStamp(f, p0 + 11);
    if (!stamp) return Result<Record>(lineError(source_name_, ln, kind, "bad timestamp fields"));
    r.start_angle = header[1];
    r.angular_resolution = header[3];
    r.max_range = header[4];
    r.laser_pose = pose(tail[0], tail[1], tail[2]);
    r.robot_pose = pose(tail[3], tail[4], tail[5]);
    r.stamp = *stamp;
    r.line = ln;
    r.original_line = line;
    return Result<Record>(Record(std::move(r)));
  }

  return std::nullopt;  // PARAM, SYNC, RLASER, TRUEPOS, ...: not needed here
}

void writeResultRecord(std::ostream& out, const LaserRecord& record, const Pose2& corrected_pose) {
  const Pose2 corrected = pose(corrected_pose.x, corrected_pose.y, corrected_pose.theta);
  const Fields original = splitFields(record.original_line);
  const std::size_t n = record.ranges.size();
  const bool flaser = record.kind == LaserRecord::Kind::kFlaser;
  const std::size_t expected =
      flaser ? kFlaserFixedFields + n
             : (original.size() > 9 + n ? kRobotLaserFixedFields + n + parseCount(original[9 + n]).value_or(0)
                                        : 0);

  std::vector<std::string> fields;
  if (!original.empty() && original.size() == expected) {
    fields.assign(original.begin(), original.end());  // everything verbatim but the poses
  } else {
    // No (usable) original line: write the record from its fields.
    fields.emplace_back(flaser ? "FLASER" : "ROBOTLASER1");
    if (!flaser) {
      for (double v : {0.0, record.start_angle, record.angular_resolution * static_cast<double>(n),
                       record.angular_resolution, record.max_range, 0.0, 0.0}) {
        fields.push_back(formatShortest(v));
      }
    }
    fields.push_back(std::to_string(n));
    for (float r : record.ranges) fields.push_back(formatShortest(r));
    if (!flaser) fields.emplace_back("0");  // no remissions
    for (int i = 0; i < 6; ++i) fields.emplace_back();
    if (!flaser) {
      for (int i = 0; i < 5; ++i) fields.emplace_back("0");
    }
    fields.push_back(record.stamp.ipc_timestamp_text.empty() ? formatFixed(record.stamp.ipc_timestamp)
                                                             : record.stamp.ipc_timestamp_text);
    fields.push_back(record.stamp.ipc_hostname.empty() ? "nohost" : record.stamp.ipc_hostname);
    fields.push_back(formatFixed(record.stamp.logger_timestamp));
  }

  if (flaser) {
    putPose(fields, 2 + n, corrected);
    putPose(fields, 5 + n, corrected);
  } else {
    const std::size_t p0 = fields.size() - kStampFields - 11;
    // The laser keeps its mounting offset from the robot: laser = corrected * (robot^-1 * laser).
    const Pose2 mount = detail::between(record.robot_pose, record.laser_pose);
    putPose(fields, p0, detail::compose(corrected, mount));
    putPose(fields, p0 + 3, corrected);
  }

  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) out << ' ';
    out << fields[i];
  }
  out << '\n';
}

}  // namespace ogf::slam_io
