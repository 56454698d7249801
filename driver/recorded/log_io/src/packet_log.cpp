#include "ogf/log_io/packet_log.hpp"

#include <ogf/velodyne_packets_t.hpp>

#include <fmt/format.h>

#include "ogf/log_io/log_events.hpp"
#include "ogf/messages/decode_message.hpp"

namespace ogf::log_io {
namespace {

// Why a decoded batch cannot be split into its packets, or "" when it can.
std::string inconsistency(const ogf::velodyne_packets_t& b) {
  std::int64_t sum = 0;
  for (int i = 0; i < b.num_packets; ++i) {
    if (b.length[static_cast<std::size_t>(i)] < 0) return fmt::format("length[{}] is negative", i);
    sum += b.length[static_cast<std::size_t>(i)];
  }
  if (sum != b.num_bytes) return fmt::format("lengths add up to {} bytes, num_bytes is {}", sum, b.num_bytes);
  return {};
}

}  // namespace

Result<PacketLogCounts> readPacketLog(const std::filesystem::path& path, const std::string& channel,
                                      const std::function<void(const LoggedPacket&)>& visit,
                                      const std::function<void(double)>& progress) {
  auto log = LogEvents::open(path);
  if (!log) return log.error();
  PacketLogCounts counts;
  ogf::velodyne_packets_t batch;
  const auto skip = [&](const lcm::LogEvent& e, const std::string& why) {
    ++counts.skipped;
    if (counts.problems.size() < 20)
      counts.problems.push_back(
          fmt::format("{}: event {} on {}: {}; skipped", path.string(), e.eventnum, channel, why));
  };
  while (const lcm::LogEvent* event = log->next()) {
    ++counts.events;
    if (event->channel != channel) continue;
    if (auto why = ogf::messages::decodeMessage(event->data, static_cast<std::size_t>(event->datalen), batch)) {
      skip(*event, "not an ogf.velodyne_packets_t that decodes (" + *why + ")");
      continue;
    }
    if (const auto why = inconsistency(batch); !why.empty()) {
      skip(*event, why);
      continue;
    }
    ++counts.batches;
    counts.gaps.add(batch.utime);
    std::size_t at = 0;
    for (std::size_t i = 0; i < static_cast<std::size_t>(batch.num_packets); ++i) {
      const auto n = static_cast<std::size_t>(batch.length[i]);
      visit({batch.host_utime[i], batch.port[i], std::span<const std::uint8_t>(batch.data.data() + at, n)});
      at += n;
      ++counts.packets;
    }
    if (progress) progress(log->fractionRead());
  }
  return counts;
}

}  // namespace ogf::log_io
