// The sources a configuration names, resolved against the top-level keys and checked as a whole
// (source_options.hpp).
#include "ogf/mapper_daemon/source_options.hpp"

#include <algorithm>
#include <map>

#include "ogf/mapper_daemon/mapper_options.hpp"

namespace ogf::mapper_daemon {
namespace {

constexpr std::size_t kMaxNameLength = 32;
constexpr std::size_t kMaxChannelLength = 63;  // LCM's limit on a channel name
// Each source keeps its own queue of scans and subscription: a bound keeps a typo'd generated file from
// subscribing hundreds of channels.
constexpr std::size_t kMaxSources = 16;

bool validName(const std::string& name) {
  return !name.empty() && name.size() <= kMaxNameLength && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

Result<ResolvedSource> resolveOne(const SourceOptions& s, const MapperOptions& o, const std::string& at) {
  const auto fail = [&](const std::string& why) { return Error::configuration(at + ": " + why); };
  if (!validName(s.name)) return fail("name '" + s.name + "' must be 1 to 32 letters, digits, '_' or '-'");
  if (!validName(s.robot)) return fail("robot '" + s.robot + "' must be 1 to 32 letters, digits, '_' or '-'");
  if (s.scan_channel.empty() == s.packet_channel.empty())
    return fail("needs exactly one of scan_channel (ogf.lidar_scan_t) and packet_channel (ogf.velodyne_packets_t)");
  if (!s.calibration.empty() && s.packet_channel.empty())
    return fail("calibration is for a packet_channel: the scans on scan_channel are decoded already");
  ResolvedSource r;
  r.name = s.name;
  r.robot = s.robot;
  r.packets = !s.packet_channel.empty();
  r.channel = r.packets ? s.packet_channel : s.scan_channel;
  r.calibration = s.calibration;
  r.pose_channel = s.pose_channel.empty() ? o.pose_channel : s.pose_channel;
  for (const auto* ch : {&r.channel, &r.pose_channel})
    if (ch->size() > kMaxChannelLength) return fail("channel '" + *ch + "' must be 1 to 63 characters");
  r.time_base = s.time_base.value_or(o.time_base);
  const fusion::ExtrinsicConfig& extrinsic = s.extrinsic ? *s.extrinsic : o.map.fusion.extrinsic;
  if (auto st = extrinsic.validate(); !st) return fail("extrinsic: " + st.error().message);
  r.body_from_sensor = extrinsic.bodyFromSensor();
  return r;
}

// Every robot moves with one odometry stream, and every stream moves one robot.
Status checkRobots(const std::vector<ResolvedSource>& sources, bool static_pose) {
  std::map<std::string, std::string> channel_of_robot, robot_of_channel;
  for (const auto& s : sources) {
    const auto [r, robot_new] = channel_of_robot.emplace(s.robot, s.pose_channel);
    if (!robot_new && r->second != s.pose_channel)
      return Error::configuration("sources: robot '" + s.robot + "' has its odometry on both " + r->second + " and " +
                                  s.pose_channel + ": the sources of one robot share its pose_channel");
    if (static_pose) continue;  // one fixed pose for every source: no odometry to tell robots apart
    const auto [c, channel_new] = robot_of_channel.emplace(s.pose_channel, s.robot);
    if (!channel_new && c->second != s.robot)
      return Error::configuration("sources: robots '" + c->second + "' and '" + s.robot + "' both take their odometry from " +
                                  s.pose_channel + ": each robot needs its own pose_channel");
  }
  return okStatus();
}

}  // namespace

Result<std::vector<ResolvedSource>> resolveSources(const MapperOptions& o) {
  std::vector<SourceOptions> configured = o.sources;
  if (configured.empty()) {
    SourceOptions one;
    one.name = kDefaultSourceName;
    one.robot = kDefaultRobotName;
    one.scan_channel = o.scan_channel;
    configured.push_back(one);
  }
  if (configured.size() > kMaxSources)
    return Error::configuration("sources: " + std::to_string(configured.size()) + " sources, at most " +
                                std::to_string(kMaxSources));
  std::vector<ResolvedSource> sources;
  for (std::size_t i = 0; i < configured.size(); ++i) {
    auto r = resolveOne(configured[i], o, "sources[" + std::to_string(i) + "] (" + configured[i].name + ")");
    if (!r) return r.error();
    for (const auto& earlier : sources) {
      if (earlier.name == r->name) return Error::configuration("sources: the name '" + r->name + "' is used twice");
      if (earlier.channel == r->channel)
        return Error::configuration("sources: '" + earlier.name + "' and '" + r->name + "' both read " + r->channel +
                                    ": each source needs its own channel");
    }
    sources.push_back(std::move(*r));
  }
  if (auto st = checkRobots(sources, o.pose_source == PoseSource::kStatic); !st) return st.error();
  return sources;
}

}  // namespace ogf::mapper_daemon
