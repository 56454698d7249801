#include "ogf/map_io/odometry_file.hpp"

#include <lcm/lcm-cpp.hpp>

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "ogf/map_io/pose_message.hpp"

namespace ogf::map_io {
namespace {

constexpr std::size_t kMaxProblems = 50;  // messages kept; the count is exact
constexpr std::array<std::uint8_t, 4> kLcmSync = {0xED, 0xA1, 0xDA, 0x01};

void addProblem(OdometryFile& out, std::string message) {
  ++out.skipped;
  if (out.problems.size() < kMaxProblems) out.problems.push_back(std::move(message));
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

template <class T>
bool parseNumber(std::string_view field, T& value) {
  field = trim(field);
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  return ec == std::errc() && ptr == end && !field.empty();
}

constexpr std::array<const char*, 8> kColumns = {"utime", "x", "y", "z", "qw", "qx", "qy", "qz"};

// One data line into a pose, or a message saying which field is wrong.
Result<fusion::Pose> parseLine(std::string_view line) {
  std::array<std::string_view, 8> fields;
  std::size_t n = 0;
  while (true) {
    const std::size_t comma = line.find(',');
    if (n == fields.size()) return Error{"more than 8 fields (expected utime,x,y,z,qw,qx,qy,qz)"};
    fields[n++] = line.substr(0, comma);
    if (comma == std::string_view::npos) break;
    line.remove_prefix(comma + 1);
  }
  if (n != fields.size()) return Error{fmt::format("{} fields, expected 8 (utime,x,y,z,qw,qx,qy,qz)", n)};
  fusion::Pose pose;
  if (!parseNumber(fields[0], pose.utime))
    return Error{fmt::format("utime '{}' is not an integer (microseconds)", trim(fields[0]))};
  std::array<double, 7> v{};
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!parseNumber(fields[i + 1], v[i]))
      return Error{fmt::format("{} '{}' is not a number", kColumns[i + 1], trim(fields[i + 1]))};
  pose.position = {v[0], v[1], v[2]};
  pose.orientation = Eigen::Quaterniond(v[3], v[4], v[5], v[6]);
  return pose;
}

}  // namespace

OdometryFile parseOdometryCsv(std::string_view text, std::string_view source) {
  OdometryFile out;
  int line_no = 0;
  bool seen_data_or_header = false;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    const std::string_view raw = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    ++line_no;
    const std::string_view line = trim(raw);
    if (line.empty() || line.front() == '#') continue;
    // The first non-comment line may be the header (the column names, whatever their spacing).
    if (!seen_data_or_header) {
      seen_data_or_header = true;
      if (line.substr(0, 5) == "utime") continue;
    }
    auto pose = parseLine(line);
    if (!pose) {
      addProblem(out, fmt::format("{}:{}: {}; line skipped", source, line_no, pose.error().message));
      continue;
    }
    out.poses.push_back(*pose);
  }
  return out;
}

Result<OdometryFile> readOdometryCsv(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{fmt::format("{}: cannot open odometry file", path.string())};
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Error{fmt::format("{}: read error", path.string())};
  return parseOdometryCsv(text.str(), path.string());
}

bool isLcmLog(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 4> head{};
  if (!in.read(head.data(), head.size())) return false;
  for (std::size_t i = 0; i < head.size(); ++i)
    if (static_cast<std::uint8_t>(head[i]) != kLcmSync[i]) return false;
  return true;
}

Result<OdometryFile> readOdometryLcmLog(const std::filesystem::path& path, const std::string& channel) {
  if (!std::filesystem::is_regular_file(path)) return Error{fmt::format("{}: no such file", path.string())};
  lcm::LogFile log(path.string(), "r");
  if (!log.good()) return Error{fmt::format("{}: cannot open as an LCM log", path.string())};
  OdometryFile out;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    if (event->channel != channel) continue;
    const std::span<const std::uint8_t> bytes(static_cast<const std::uint8_t*>(event->data),
                                              static_cast<std::size_t>(std::max(event->datalen, 0)));
    auto pose = decodePoseMessage(bytes);
    if (!pose) {
      addProblem(out, fmt::format("{}: event {} on {}: {}; skipped", path.string(), event->eventnum, channel,
                                  pose.error().message));
      continue;
    }
    out.poses.push_back(*pose);
  }
  return out;
}

Result<OdometryFile> readOdometry(const std::filesystem::path& path, const std::string& lcm_channel) {
  if (isLcmLog(path)) return readOdometryLcmLog(path, lcm_channel);
  return readOdometryCsv(path);
}

Status writeOdometryCsv(const std::filesystem::path& path, const std::vector<fusion::Pose>& poses) {
  std::ofstream out(path);
  if (!out) return Error{path.string() + ": cannot create"};
  out << "utime,x,y,z,qw,qx,qy,qz\n";
  for (const fusion::Pose& p : poses) {
    const Eigen::Quaterniond q = p.orientation.normalized();
    out << fmt::format("{},{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f},{:.9f}\n", p.utime, p.position.x(),
                       p.position.y(), p.position.z(), q.w(), q.x(), q.y(), q.z());
  }
  out.flush();
  if (!out) return Error{path.string() + ": write failed"};
  return Ok{};
}

}  // namespace ogf::map_io
