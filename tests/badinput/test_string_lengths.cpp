// Messages whose string length fields lie: lcm-gen's decode trusts them, and a length of -2^31 wraps to
// 2^31 - 1, so a 37-byte map_request_t (which ogf-mapper receives on OGF_MAP_REQUEST) made it allocate and
// read 2 GiB past the buffer. The safe decode must refuse every such message of every type with a string,
// and still decode the valid ones.
#include <gtest/gtest.h>

#include <ogf/driver_status_t.hpp>
#include <ogf/map_command_t.hpp>
#include <ogf/map_query_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/odometry_t.hpp>

#include <cstdint>
#include <limits>

#include "lcm_bytes.hpp"
#include "ogf/messages/decode_message.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;

using ogf::testing::withInt32At;

// Every lying length at string-length offset `at` is refused; the valid message decodes.
template <class Message>
void expectLyingLengthsRefused(const Message& valid, std::size_t at) {
  const Bytes good = ogf::testing::encodeMessage(valid);
  Message out;
  EXPECT_FALSE(ogf::messages::decodeMessage(good.data(), good.size(), out).has_value());
  for (const std::int32_t lie : {std::numeric_limits<std::int32_t>::min(), -1, 0, 1 << 20,
                                 std::numeric_limits<std::int32_t>::max()}) {
    const Bytes bad = withInt32At(good, at, lie);
    Message m;
    EXPECT_TRUE(ogf::messages::decodeMessage(bad.data(), bad.size(), m).has_value())
        << Message::getTypeName() << " with a string length " << lie << " at byte " << at;
  }
}

TEST(StringLengths, LyingLengthsAreRefusedInEveryTypeWithAString) {
  ogf::map_request_t request{};
  request.requester = "client";
  expectLyingLengthsRefused(request, 16);

  ogf::odometry_t odometry{};
  odometry.frame_id = "odom";
  odometry.child_frame_id = "base";
  expectLyingLengthsRefused(odometry, 16);
  expectLyingLengthsRefused(odometry, 16 + 4 + 5);

  ogf::driver_status_t driver{};
  driver.source = "udp";
  driver.nmea = "$GPRMC";
  expectLyingLengthsRefused(driver, 16);
  expectLyingLengthsRefused(driver, 16 + 4 + 4 + 1 + 1 + 12 + 72 + 1 + 1);

  ogf::mapper_status_t mapper{};
  mapper.persistence_error = "disk full";
  mapper.last_requester = "planner";
  expectLyingLengthsRefused(mapper, 8 + 80 + 12 + 40 + 1);
  expectLyingLengthsRefused(mapper, 8 + 80 + 12 + 40 + 1 + 4 + 10 + 9 * 8 + 2 + 8 + 7 * 8);

  ogf::map_query_t query{};
  query.requester = "planner";
  expectLyingLengthsRefused(query, 24);

  ogf::map_command_t command{};
  command.requester = "planner";
  command.command = "save";
  command.format = "ply";
  command.path = "map.ply";
  expectLyingLengthsRefused(command, 24);
  expectLyingLengthsRefused(command, 24 + 4 + 8);
  expectLyingLengthsRefused(command, 24 + 4 + 8 + 4 + 5);
  expectLyingLengthsRefused(command, 24 + 4 + 8 + 4 + 5 + 4 + 4);
}

}  // namespace
