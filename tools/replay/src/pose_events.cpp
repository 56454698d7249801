// Loading the odometry to replay: see pose_events.hpp.
#include "ogf/replay/pose_events.hpp"

#include <lcm/lcm-cpp.hpp>
#include <ogf/odometry_t.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ogf::replay {
namespace {

constexpr std::size_t kMaxProblems = 10;
constexpr std::array<std::uint8_t, 4> kLcmLogSync{0xED, 0xA1, 0xDA, 0x01};

void addProblem(PoseEvents& out, std::string message) {
  ++out.skipped;
  if (out.problems.size() < kMaxProblems) out.problems.push_back(std::move(message));
}

template <class T>
bool parseField(std::string_view text, T& value) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.remove_suffix(1);
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && end == text.data() + text.size();
}

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

void sortByTime(PoseEvents& out) {
  std::stable_sort(out.events.begin(), out.events.end(),
                   [](const PoseEvent& a, const PoseEvent& b) { return a.utime < b.utime; });
}

}  // namespace

PoseEvents parsePoseCsv(const std::string& text, const std::string& source) {
  PoseEvents out;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line == "\r" || line.front() == '#') continue;
    if (line.rfind("utime", 0) == 0) continue;  // the header
    std::vector<std::string_view> fields;
    std::string_view rest(line);
    while (true) {
      const auto comma = rest.find(',');
      fields.push_back(rest.substr(0, comma));
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
    const std::string where = source + ":" + std::to_string(line_no) + ": ";
    if (fields.size() != 8) {
      addProblem(out, where + "expected 8 fields (utime,x,y,z,qw,qx,qy,qz), found " + std::to_string(fields.size()));
      continue;
    }
    std::int64_t utime = 0;
    if (!parseField(fields[0], utime)) {
      addProblem(out, where + "utime is not an integer");
      continue;
    }
    static constexpr const char* kNames[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
    std::array<double, 7> v{};
    bool good = true;
    for (std::size_t i = 0; i < 7 && good; ++i) {
      if (!parseField(fields[i + 1], v[i]) || !std::isfinite(v[i])) {
        addProblem(out, where + kNames[i] + " is not a finite number");
        good = false;
      }
    }
    if (good) out.events.push_back({utime, encodeOdometry(utime, v)});
  }
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

}  // namespace ogf::replay
