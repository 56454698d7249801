// Pose CSV and LCM log writers (and the CSV reader the tests and ogf-eval use).
#include "ogf/sim/pose_files.hpp"

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
  out << kPoseCsvHeader << '\n';
  for (const auto& p : poses) {
    const auto& q = p.pose.orientation;
    // "+ 0.0" turns -0.0 into 0.0, so a level pose reads 0 rather than -0.
    out << fmt::format("{},{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f},{:.9f}\n", p.utime, p.pose.position.x() + 0.0,
                       p.pose.position.y() + 0.0, p.pose.position.z() + 0.0, q.w() + 0.0, q.x() + 0.0,
                       q.y() + 0.0, q.z() + 0.0);
  }
  out.flush();
  if (!out) return Error{path + ": write failed"};
  return Ok{};
}

Result<std::vector<StampedPose>> readPoseCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open"};
  std::string line;
  if (!std::getline(in, line) || line != kPoseCsvHeader) {
    return Error{path + ":1: expected the header '" + std::string(kPoseCsvHeader) + "'"};
  }
  std::vector<StampedPose> poses;
  int n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    std::istringstream ls(line);
    StampedPose p;
    double v[7] = {};
    char comma = 0;
    bool ok = static_cast<bool>(ls >> p.utime);
    for (double& x : v) ok = ok && (ls >> comma >> x) && comma == ',';
    if (!ok) return Error{path + ":" + std::to_string(n) + ": expected 8 comma-separated numbers"};
    p.pose.position = {v[0], v[1], v[2]};
    p.pose.orientation = Eigen::Quaterniond(v[3], v[4], v[5], v[6]);
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
