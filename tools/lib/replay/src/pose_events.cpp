// Loading the odometry to replay: see pose_events.hpp.
#include "ogf/replay/pose_events.hpp"

#include "ogf/tools/pose_csv.hpp"

#include <bot_core/pose_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <ogf/odometry_t.hpp>

#include "ogf/messages/decode_message.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <sstream>

namespace ogf::replay {
namespace {

constexpr std::array<std::uint8_t, 4> kLcmLogSync{0xED, 0xA1, 0xDA, 0x01};

std::vector<std::uint8_t> encodeOdometry(std::int64_t utime, const std::array<double, 7>& v) {
  ogf::odometry_t m{};
  m.utime = utime;
  m.frame_id = "odom";
  m.child_frame_id = "base_link";
  for (int i = 0; i < 3; ++i) m.position[i] = v[static_cast<std::size_t>(i)];
  for (int i = 0; i < 4; ++i) m.orientation[i] = v[static_cast<std::size_t>(3 + i)];
  m.num_covariance = 0;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

template <class Message>
Result<std::vector<std::uint8_t>> restampAs(const std::vector<std::uint8_t>& bytes, const char* type,
                                            const std::function<std::int64_t(std::int64_t)>& restamp) {
  Message m;
  if (auto why = messages::decodeMessage(bytes.data(), bytes.size(), m)) return Error{std::string(type) + " " + *why};
  m.utime = restamp(m.utime);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(out.data(), 0, static_cast<int>(out.size()));
  return out;
}

void sortByTime(PoseEvents& out) {
  std::stable_sort(out.events.begin(), out.events.end(),
                   [](const PoseEvent& a, const PoseEvent& b) { return a.utime < b.utime; });
}

}  // namespace

PoseEvents parsePoseCsv(const std::string& text, const std::string& source) {
  tools::PoseCsv csv = tools::parsePoseCsv(text, source);
  PoseEvents out;
  out.skipped = csv.skipped;
  out.problems = std::move(csv.problems);
  for (const tools::PoseCsvRow& row : csv.rows) out.events.push_back({row.utime, encodeOdometry(row.utime, row.values)});
  sortByTime(out);
  return out;
}

Result<PoseEvents> loadPoseEvents(const std::filesystem::path& path, const std::string& lcm_channel) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{path.string() + ": cannot open"};
  std::array<std::uint8_t, 4> head{};
  file.read(reinterpret_cast<char*>(head.data()), head.size());
  const bool is_log = file.gcount() == 4 && head == kLcmLogSync;
  PoseEvents out;
  if (is_log) {
    file.close();
    lcm::LogFile log(path.string(), "r");
    if (!log.good()) return Error{path.string() + ": cannot read as an LCM log"};
    while (const lcm::LogEvent* e = log.readNextEvent()) {
      if (e->channel != lcm_channel) continue;
      const auto* data = static_cast<const std::uint8_t*>(e->data);
      out.events.push_back({e->timestamp, std::vector<std::uint8_t>(data, data + e->datalen)});
    }
    sortByTime(out);
    if (out.events.empty()) return Error{path.string() + ": no event on channel " + lcm_channel};
    return out;
  }
  file.clear();
  file.seekg(0);
  std::ostringstream text;
  text << file.rdbuf();
  out = parsePoseCsv(text.str(), path.string());
  if (out.events.empty())
    return Error{path.string() + ": no pose (" + std::to_string(out.skipped) + " malformed lines" +
                 (out.problems.empty() ? std::string() : "; first: " + out.problems.front()) + ")"};
  return out;
}

Result<std::vector<std::uint8_t>> restampPose(const std::vector<std::uint8_t>& bytes,
                                              const std::function<std::int64_t(std::int64_t)>& restamp) {
  std::uint64_t fingerprint = 0;  // LCM encodes it big-endian, first
  for (std::size_t i = 0; i < 8 && i < bytes.size(); ++i) fingerprint = (fingerprint << 8) | bytes[i];
  const auto fp = static_cast<std::int64_t>(fingerprint);
  if (bytes.size() >= 8 && fp == ogf::odometry_t::getHash())
    return restampAs<ogf::odometry_t>(bytes, "ogf.odometry_t", restamp);
  if (bytes.size() >= 8 && fp == bot_core::pose_t::getHash())
    return restampAs<bot_core::pose_t>(bytes, "bot_core.pose_t", restamp);
  return Error{"a message of neither ogf.odometry_t nor bot_core.pose_t (fingerprint): its utime cannot be moved"};
}

}  // namespace ogf::replay
