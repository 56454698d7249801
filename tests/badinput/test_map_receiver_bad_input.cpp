// The map client's receiver (MapReceiver, in ogf-map-client) on OGF_MAP_DELTA messages that claim much and
// carry nothing: updates whose part_count is the largest accepted (2^16) while each brings one empty part.
// A receiver that reserved room for every claimed part would turn 256 such 70-byte messages into ~400 MB;
// the peak RSS of this process (VmHWM) must stay within a few MB of where it was, and the receiver must
// still rebuild a map from a valid keyframe after them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <ogf/map_delta_t.hpp>

#include "ogf/delta/map_receiver.hpp"
#include "support/process_memory.hpp"

namespace {

ogf::map_delta_t update(std::int8_t kind, std::int64_t seq, std::int32_t part_count) {
  ogf::map_delta_t m{};
  m.map_id = 42;
  m.seq = seq;
  m.base_seq = seq - 1;
  m.kind = kind;
  m.part_index = 0;
  m.part_count = part_count;
  m.resolution = 0.2;
  m.num_cells = 0;
  return m;
}

TEST(MapReceiverBadInput, ClaimedPartsCostNothingUntilTheyArrive) {
  ogf::delta::MapReceiver receiver;  // the client's default: up to 256 updates held
  const auto before = ogf::testing::peakResidentKiB(::getpid());
  ASSERT_TRUE(before);
  for (std::int64_t seq = 1; seq <= 256; ++seq)
    EXPECT_EQ(receiver.accept(update(ogf::map_delta_t::KIND_DELTA, seq, 1 << 16)),
              ogf::delta::MapReceiver::Outcome::kBuffered);
  for (std::int64_t seq = 300; seq < 304; ++seq)
    EXPECT_EQ(receiver.accept(update(ogf::map_delta_t::KIND_KEYFRAME, seq, 1 << 16)),
              ogf::delta::MapReceiver::Outcome::kPartial);
  const auto after = ogf::testing::peakResidentKiB(::getpid());
  ASSERT_TRUE(after);
  EXPECT_LT(*after - *before, 16 * 1024) << "VmHWM grew from " << *before << " to " << *after << " kB";

  // A valid one-part keyframe with one cell still lands.
  auto kf = update(ogf::map_delta_t::KIND_KEYFRAME, 400, 1);
  kf.num_cells = 1;
  kf.key_x = {1};
  kf.key_y = {2};
  kf.key_z = {3};
  kf.probability = {9000};
  kf.cell_class = {ogf::map_delta_t::CLASS_OCCUPIED};
  kf.variance = {0.01f};
  EXPECT_EQ(receiver.accept(kf), ogf::delta::MapReceiver::Outcome::kKeyframeApplied);
  EXPECT_EQ(receiver.map().size(), 1u);
  EXPECT_EQ(receiver.appliedSeq(), 400);
}

}  // namespace
