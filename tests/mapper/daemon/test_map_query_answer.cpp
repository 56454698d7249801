// Map queries answered from a small hand-built map: the cells holding points, a box's known and unknown
// volume and entropy, and every limit refused with a message and no partial answer.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ogf/mapper_daemon/map_query_answer.hpp"

namespace ogf::mapper_daemon {
namespace {

filter::BandedOgf mapWithAWall() {
  filter::FilterConfig config;  // 3-D, 0.2 m
  auto map = filter::BandedOgf::create(config);
  EXPECT_TRUE(map.ok());
  std::vector<Measurement> batch;
  for (int y = 0; y < 5; ++y) {
    batch.push_back({CellKey{10, y, 0}, Measurement::kOccupied});  // a wall at x = 2.0–2.2 m
    for (int x = 0; x < 10; ++x) batch.push_back({CellKey{x, y, 0}, Measurement::kFree});
  }
  for (int i = 0; i < 5; ++i) map->update(batch);
  return std::move(*map);
}

ogf::map_query_t cellsQuery(std::vector<std::vector<float>> points) {
  ogf::map_query_t q{};
  q.request_id = 42;
  q.kind = ogf::map_query_t::KIND_CELLS;
  q.num_points = static_cast<std::int32_t>(points.size());
  q.points = std::move(points);
  return q;
}

TEST(MapQueryAnswer, CellsAreAnsweredInOrderWithTheirClassesAndEntropy) {
  const auto map = mapWithAWall();
  const auto r = answerQuery(cellsQuery({{2.1f, 0.5f, 0.1f}, {1.0f, 0.5f, 0.1f}, {-30.f, 0.f, 0.f}}), map, 7, 5, 99);
  ASSERT_EQ(r.status, ogf::map_query_reply_t::STATUS_OK) << r.message;
  EXPECT_EQ(r.request_id, 42);
  EXPECT_EQ(r.map_id, 7);
  EXPECT_EQ(r.seq, 5);
  ASSERT_EQ(r.num_cells, 3);
  EXPECT_EQ(r.cell_class[0], 1);
  EXPECT_GT(r.probability[0], 0.65f);
  EXPECT_EQ(r.cell_class[1], -1);
  EXPECT_LT(r.probability[1], 0.35f);
  EXPECT_EQ(r.cell_class[2], 0);  // never measured: the prior
  EXPECT_FLOAT_EQ(r.probability[2], 0.5f);
  EXPECT_FLOAT_EQ(r.entropy[2], 1.0f);
  EXPECT_LT(r.entropy[0], 1.0f);
  EXPECT_GT(r.variance[2], r.variance[0]);
}

TEST(MapQueryAnswer, ABoxSumsKnownAndUnknownVolume) {
  const auto map = mapWithAWall();
  ogf::map_query_t q{};
  q.kind = ogf::map_query_t::KIND_BOX;
  // Cell centres x 0.1..2.1 (11), y 0.1..0.9 (5), z 0.1 (1): the measured slab, 55 cells.
  const float lo[3] = {0.0f, 0.0f, 0.0f}, hi[3] = {2.2f, 1.0f, 0.2f};
  std::copy(lo, lo + 3, q.box_min);
  std::copy(hi, hi + 3, q.box_max);
  const auto r = answerQuery(q, map, 7, 5, 99);
  ASSERT_EQ(r.status, ogf::map_query_reply_t::STATUS_OK) << r.message;
  EXPECT_EQ(r.box_cells, 55);
  EXPECT_EQ(r.box_occupied, 5);
  EXPECT_EQ(r.box_free, 50);
  EXPECT_EQ(r.box_unknown, 0);
  EXPECT_NEAR(r.known_volume_m3, 55 * 0.008, 1e-9);
  EXPECT_NEAR(r.unknown_volume_m3, 0.0, 1e-12);
  EXPECT_LT(r.mean_entropy_bits, 0.9);
  // The same box one layer up holds nothing measured directly.
  q.box_min[2] = 0.2f;
  q.box_max[2] = 0.4f;
  const auto up = answerQuery(q, map, 7, 5, 99);
  ASSERT_EQ(up.status, ogf::map_query_reply_t::STATUS_OK);
  EXPECT_GT(up.unknown_volume_m3, 0.0);
}

TEST(MapQueryAnswer, EveryLimitIsRefusedWithAMessage) {
  const auto map = mapWithAWall();
  const auto refused = [&](const ogf::map_query_t& q, const char* text) {
    const auto r = answerQuery(q, map, 7, 5, 99);
    EXPECT_EQ(r.status, ogf::map_query_reply_t::STATUS_REFUSED);
    EXPECT_NE(r.message.find(text), std::string::npos) << r.message;
    EXPECT_EQ(r.num_cells, 0);
    EXPECT_EQ(r.request_id, q.request_id);
  };
  refused(cellsQuery({}), "num_points");
  refused(cellsQuery(std::vector<std::vector<float>>(kMaxQueryPoints + 1, {0.f, 0.f, 0.f})), "num_points");
  refused(cellsQuery({{0.f, std::numeric_limits<float>::quiet_NaN(), 0.f}}), "not finite");
  refused(cellsQuery({{1e30f, 0.f, 0.f}}), "beyond");
  auto lying = cellsQuery({{0.f, 0.f, 0.f}});
  lying.num_points = 2;
  refused(lying, "rows");
  ogf::map_query_t box{};
  box.kind = ogf::map_query_t::KIND_BOX;
  box.box_min[0] = box.box_min[1] = box.box_min[2] = -1000.f;
  box.box_max[0] = box.box_max[1] = box.box_max[2] = 1000.f;
  refused(box, "exceed the limit");
  box.box_max[0] = std::numeric_limits<float>::infinity();
  refused(box, "finite");
  box.box_min[0] = 0.05f;
  box.box_max[0] = 0.06f;  // no cell centre between
  box.box_max[1] = box.box_max[2] = 1.f;
  refused(box, "no cell centre");
  ogf::map_query_t odd{};
  odd.kind = 9;
  refused(odd, "kind 9");
}

}  // namespace
}  // namespace ogf::mapper_daemon
