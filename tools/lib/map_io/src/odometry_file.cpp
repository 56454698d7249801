#include "ogf/map_io/odometry_file.hpp"

#include <lcm/lcm-cpp.hpp>

#include <fmt/format.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "ogf/map_io/pose_message.hpp"
#include "ogf/tools/pose_csv.hpp"

namespace ogf::map_io {
namespace {

constexpr std::size_t kMaxOdometryProblems = 50;  // messages kept; the count is exact
constexpr std::array<std::uint8_t, 4> kLcmSync = {0xED, 0xA1, 0xDA, 0x01};

void addProblem(OdometryFile& out, std::string message) {
  ++out.skipped;
  if (out.problems.size() < kMaxOdometryProblems) out.problems.push_back(std::move(message));
}

}  // namespace

OdometryFile parseOdometryCsv(std::string_view text, std::string_view source) {
  tools::PoseCsv csv = tools::parsePoseCsv(text, source);
  OdometryFile out;
  out.skipped = csv.skipped;
  out.problems = std::move(csv.problems);
  for (const tools::PoseCsvRow& row : csv.rows) {
    fusion::Pose pose;
    pose.utime = row.utime;
    pose.position = {row.values[0], row.values[1], row.values[2]};
    pose.orientation = Eigen::Quaterniond(row.values[3], row.values[4], row.values[5], row.values[6]);
    out.poses.push_back(pose);
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
  out << tools::kPoseCsvHeader << '\n';
  for (const fusion::Pose& p : poses) {
    const Eigen::Quaterniond q = p.orientation.normalized();
    out << tools::formatPoseCsvRow(p.utime, {p.position.x(), p.position.y(), p.position.z(), q.w(), q.x(), q.y(),
                                             q.z()})
        << '\n';
  }
  out.flush();
  if (!out) return Error{path.string() + ": write failed"};
  return Ok{};
}

}  // namespace ogf::map_io
