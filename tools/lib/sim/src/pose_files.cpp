// Pose CSV and LCM log writers (and the CSV reader the tests and ogf-eval use).
#include "ogf/sim/pose_files.hpp"

#include "ogf/tools/pose_csv.hpp"

#include <fmt/format.h>
#include <lcm/lcm-cpp.hpp>
#include <ogf/odometry_t.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace ogf::sim {

Status writePoseCsv(const std::string& path, const std::vector<StampedPose>& poses) {
  std::ofstream out(path);
  if (!out) return Error{path + ": cannot create"};
  out << tools::kPoseCsvHeader << '\n';
  for (const auto& p : poses) {
    const auto& q = p.pose.orientation;
    out << tools::formatPoseCsvRow(p.utime, {p.pose.position.x(), p.pose.position.y(), p.pose.position.z(), q.w(),
                                             q.x(), q.y(), q.z()})
        << '\n';
  }
  out.flush();
  if (!out) return Error{path + ": write failed"};
  return Ok{};
}

Result<std::vector<StampedPose>> readPoseCsv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  std::ostringstream text;
  text << in.rdbuf();
  const tools::PoseCsv csv = tools::parsePoseCsv(text.str(), path);
  if (!csv.problems.empty()) return Error{csv.problems.front()};
  std::vector<StampedPose> poses;
  for (const tools::PoseCsvRow& row : csv.rows) {
    StampedPose p;
    p.utime = row.utime;
    p.pose.position = {row.values[0], row.values[1], row.values[2]};
    p.pose.orientation = Eigen::Quaterniond(row.values[3], row.values[4], row.values[5], row.values[6]);
    poses.push_back(p);
  }
  return poses;
}

Status writeOdometryLcmLog(const std::string& path, const std::vector<StampedPose>& poses) {
  lcm::LogFile log(path, "w");
  if (!log.good()) return Error{path + ": cannot create the LCM log"};
  std::vector<std::uint8_t> buffer;
  std::int64_t event = 0;
  for (const auto& p : poses) {
    ogf::odometry_t msg;
    msg.utime = p.utime;
    msg.frame_id = "odom";
    msg.child_frame_id = "base_link";
    for (int i = 0; i < 3; ++i) msg.position[i] = p.pose.position[i];
    msg.orientation[0] = p.pose.orientation.w();
    msg.orientation[1] = p.pose.orientation.x();
    msg.orientation[2] = p.pose.orientation.y();
    msg.orientation[3] = p.pose.orientation.z();
    msg.num_covariance = 0;
    const int size = msg.getEncodedSize();
    buffer.resize(static_cast<std::size_t>(size));
    if (msg.encode(buffer.data(), 0, size) != size) return Error{path + ": cannot encode odometry_t"};
    lcm::LogEvent ev;
    ev.eventnum = event++;
    ev.timestamp = p.utime;
    ev.channel = kPoseChannel;
    ev.datalen = size;
    ev.data = buffer.data();
    if (log.writeEvent(&ev) != 0) return Error{path + ": write failed at event " + std::to_string(ev.eventnum)};
  }
  return Ok{};
}

}  // namespace ogf::sim
