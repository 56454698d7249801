// The binary cell frame the page decodes: the layout (header, aligned arrays), a round trip, the split of a
// large map into frames with only the first one full, and refusal of bytes that are not a frame.
#include <gtest/gtest.h>

#include <cstring>

#include "ogf/view/cell_frame.hpp"

namespace {

using namespace ogf::view;

OccupiedSlots sample(int n) {
  OccupiedSlots s;
  for (int i = 0; i < n; ++i)
    s.set({{i, -i, i % 7}, static_cast<std::int16_t>(6600 + i % 3000), ogf::map_delta_t::CLASS_OCCUPIED,
           0.01f * static_cast<float>(i % 50)});
  return s;
}

TEST(CellFrame, LayoutIsTheDocumentedOne) {
  auto s = sample(3);
  s.set({{1, -1, 1}, 100, ogf::map_delta_t::CLASS_FREE, 0.0f});  // slot 1 emptied
  const std::vector<std::uint32_t> which{0, 1, 2};
  const auto bytes = encodeCellFrame(s, which, true, 0.2);
  ASSERT_EQ(bytes.size(), 24u + 3 * 22 + 2);  // padded to 4
  std::uint32_t u = 0;
  std::memcpy(&u, bytes.data(), 4);
  EXPECT_EQ(u, 0x3156474Fu);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(bytes.data()), 4), "OGV1");
  std::memcpy(&u, bytes.data() + 4, 4);
  EXPECT_EQ(u, 1u);  // full
  std::memcpy(&u, bytes.data() + 8, 4);
  EXPECT_EQ(u, 3u);  // slot count
  std::memcpy(&u, bytes.data() + 12, 4);
  EXPECT_EQ(u, 3u);  // n
  float res = 0;
  std::memcpy(&res, bytes.data() + 16, 4);
  EXPECT_FLOAT_EQ(res, 0.2f);
  std::int32_t key_y2 = 0;  // slot 2's y, in the key array after the 3 slot numbers
  std::memcpy(&key_y2, bytes.data() + 24 + 12 + 2 * 12 + 4, 4);
  EXPECT_EQ(key_y2, -2);
  std::uint16_t p1 = 0;  // slot 1's probability: empty
  std::memcpy(&p1, bytes.data() + 24 + 3 * 20 + 2, 2);
  EXPECT_EQ(p1, kEmptySlot);
}

TEST(CellFrame, RoundTripsEverySlot) {
  const auto s = sample(1000);
  const auto which = s.filledSlots();
  const auto f = decodeCellFrame(encodeCellFrame(s, which, false, 0.05));
  ASSERT_TRUE(f.has_value());
  EXPECT_FALSE(f->full);
  EXPECT_EQ(f->slot_count, 1000u);
  EXPECT_FLOAT_EQ(f->resolution, 0.05f);
  ASSERT_EQ(f->slot, which);
  for (std::size_t i = 0; i < which.size(); ++i) {
    EXPECT_EQ(f->cells[i].key, s.slot(which[i]).key);
    EXPECT_EQ(f->cells[i].probability, s.slot(which[i]).probability);
    EXPECT_EQ(f->cells[i].variance, s.slot(which[i]).variance);
  }
}

TEST(CellFrame, LargeUpdatesAreSplitAndOnlyTheFirstFrameIsFull) {
  const auto s = sample(1000);
  const auto which = s.filledSlots();
  const auto frames = encodeCellFrames(s, which, true, 0.2, 300);
  ASSERT_EQ(frames.size(), 4u);
  std::vector<std::uint32_t> seen;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto f = decodeCellFrame(frames[i]);
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->full, i == 0);
    seen.insert(seen.end(), f->slot.begin(), f->slot.end());
  }
  EXPECT_EQ(seen, which);
  // An empty map still clears the page; no change sends nothing.
  const OccupiedSlots empty;
  const auto cleared = encodeCellFrames(empty, {}, true, 0.2);
  ASSERT_EQ(cleared.size(), 1u);
  EXPECT_TRUE(decodeCellFrame(cleared[0])->full);
  EXPECT_TRUE(encodeCellFrames(empty, {}, false, 0.2).empty());
}

TEST(CellFrame, RefusesBytesThatAreNotAFrame) {
  const auto s = sample(10);
  auto bytes = encodeCellFrame(s, s.filledSlots(), false, 0.2);
  EXPECT_FALSE(decodeCellFrame(std::span(bytes).first(bytes.size() - 4)).has_value());  // truncated
  auto bad_magic = bytes;
  bad_magic[0] ^= 1;
  EXPECT_FALSE(decodeCellFrame(bad_magic).has_value());
  auto bad_slot = bytes;
  const std::uint32_t beyond = 10;
  std::memcpy(bad_slot.data() + 24, &beyond, 4);  // slot 10 of 10
  EXPECT_FALSE(decodeCellFrame(bad_slot).has_value());
  EXPECT_FALSE(decodeCellFrame(std::span<const std::uint8_t>()).has_value());
}

}  // namespace
