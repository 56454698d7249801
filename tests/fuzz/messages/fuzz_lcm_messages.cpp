// Fuzzes what a daemon does with the bytes of one received LCM message, whatever its channel: the safe
// decode (messages::decodeMessage) of every type in the message set, then for a scan the mapper's checks
// and views (validateScan, scanPointsOf, the time span the pending queue keys on), and for POSE the
// adapter that takes either odometry type (decodePose). Any input must be refused with a reason or
// decoded whole; nothing may crash, leak, read out of bounds or allocate for a count it does not hold.
#include <bot_core/pose_t.hpp>
#include <ogf/driver_status_t.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/map_command_t.hpp>
#include <ogf/map_delta_t.hpp>
#include <ogf/map_query_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/odometry_t.hpp>
#include <ogf/velodyne_packets_t.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/messages/decode_message.hpp"

namespace {

template <class Message>
bool decodes(const std::uint8_t* data, std::size_t size) {
  Message m;
  return !ogf::messages::decodeMessage(data, size, m).has_value();
}

void scan(const std::uint8_t* data, std::size_t size) {
  ogf::lidar_scan_t s;
  if (ogf::messages::decodeMessage(data, size, s)) return;
  if (!ogf::adapters::validateScan(s)) return;
  for (const auto base : {ogf::adapters::ScanTimeBase::kDevice, ogf::adapters::ScanTimeBase::kHost,
                          ogf::adapters::ScanTimeBase::kAuto}) {
    const auto points = ogf::adapters::scanPointsOf(s, base);
    // A validated scan's views are the arrays' own lengths, and its span is ordered.
    if (points.x.size() != static_cast<std::size_t>(s.num_points) || points.time_offset_ns.size() != points.x.size())
      std::abort();
    const auto span = ogf::fusion::timeSpanOf(points);
    if (span.end_utime < span.begin_utime) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  scan(data, size);
  (void)ogf::adapters::decodePose(data, size);
  (void)decodes<ogf::odometry_t>(data, size);
  (void)decodes<bot_core::pose_t>(data, size);
  (void)decodes<ogf::map_delta_t>(data, size);
  (void)decodes<ogf::map_request_t>(data, size);
  (void)decodes<ogf::velodyne_packets_t>(data, size);
  (void)decodes<ogf::driver_status_t>(data, size);
  (void)decodes<ogf::mapper_status_t>(data, size);
  (void)decodes<ogf::map_query_t>(data, size);
  (void)decodes<ogf::map_command_t>(data, size);
  return 0;
}
