#include "ogf/rosbag/bag_packets.hpp"

#include <fmt/format.h>

#include "ogf/rosbag/ros_messages.hpp"

namespace ogf::rosbag {
namespace {

constexpr std::size_t kMaxProblems = 20;

std::string topicList(const std::vector<const BagTopic*>& topics) {
  std::string out;
  for (const BagTopic* t : topics) out += (out.empty() ? "" : ", ") + t->name;
  return out;
}

}  // namespace

Result<std::optional<std::string>> choosePacketTopic(const Rosbag2Storage& bag,
                                                     const std::string& requested) {
  const auto candidates = bag.topicsOfType(kVelodyneScanType);
  if (!requested.empty()) {
    const BagTopic* t = bag.topic(requested);
    if (t == nullptr) return Error{fmt::format("{}: no topic {}", bag.path().string(), requested)};
    if (t->type != kVelodyneScanType)
      return Error{fmt::format("{}: topic {} is {}, not {}", bag.path().string(), requested, t->type,
                               kVelodyneScanType)};
    return std::optional<std::string>(requested);
  }
  if (candidates.empty()) return std::optional<std::string>();
  if (candidates.size() > 1)
    return Error{fmt::format("{}: {} topics of type {} ({}): choose one", bag.path().string(),
                             candidates.size(), kVelodyneScanType, topicList(candidates))};
  return std::optional<std::string>(candidates.front()->name);
}

Result<BagPacketCounts> readBagPackets(const Rosbag2Storage& bag, const std::string& topic,
                                       const std::function<void(const BagPacket&)>& visit,
                                       const std::function<void(double)>& progress) {
  const BagTopic* t = bag.topic(topic);
  if (t == nullptr) return Error{fmt::format("{}: no topic {}", bag.path().string(), topic)};
  if (t->serialization_format != "cdr")
    return Error{fmt::format("{}: topic {} is serialized as '{}', not cdr", bag.path().string(), topic,
                             t->serialization_format)};
  BagPacketCounts counts;
  std::int64_t seen = 0;
  auto st = bag.forEachMessage(
      {topic},
      [&](const BagMessage& m) {
        ++seen;
        auto scan = decodeVelodyneScan(m.data);
        if (!scan) {
          ++counts.skipped;
          if (counts.problems.size() < kMaxProblems)
            counts.problems.push_back(fmt::format("{}: {} on {}: {}; skipped", m.file->string(), m.where(),
                                                  topic, scan.error().message));
        } else {
          ++counts.messages;
          counts.gaps.add(m.timestamp_ns / 1000);
          for (const VelodynePacketView& p : scan->packets) {
            visit({p.stamp.utime(), p.data});
            ++counts.packets;
          }
        }
        if (progress && t->message_count > 0)
          progress(static_cast<double>(seen) / static_cast<double>(t->message_count));
      },
      [&](const std::string& damage) {
        ++counts.damaged;
        if (counts.problems.size() < kMaxProblems) counts.problems.push_back(damage);
      });
  if (!st) return st.error();
  return counts;
}

}  // namespace ogf::rosbag
