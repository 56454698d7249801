// libFuzzer target: the CDR reader and the ROS message decoders (VelodyneScan, Odometry, TFMessage) on
// arbitrary bytes, as a damaged bag hands them over; every packet a VelodyneScan yields is read whole.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "ogf/rosbag/cdr_reader.hpp"
#include "ogf/rosbag/ros_messages.hpp"

namespace rb = ogf::rosbag;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  if (auto scan = rb::decodeVelodyneScan(bytes)) {
    unsigned sum = 0;
    for (const auto& p : scan->packets) {
      if (p.data.size() != rb::kVelodynePacketBytes) __builtin_trap();
      sum += p.data.front() + p.data.back();
      (void)p.stamp.utime();
    }
    (void)sum;
  }
  if (auto odo = rb::decodeOdometry(bytes)) (void)odo->header.stamp.utime();
  if (auto tf = rb::decodeTfMessage(bytes))
    for (const auto& t : tf->transforms) (void)t.header.stamp.utime();
  // The primitives in an order no message has, to reach every alignment.
  if (auto r = rb::CdrReader::open(bytes)) {
    std::uint8_t u8 = 0;
    std::uint32_t n = 0;
    double d = 0;
    std::string s;
    std::span<const std::uint8_t> o;
    while (r->u8(u8, "u8") && r->string(s, "s") && r->f64(d, "d") && r->sequenceLength(n, 1, "n") &&
           r->octets(n % 64, o, "o")) {
    }
  }
  return 0;
}
