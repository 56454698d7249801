// The publishing rule of OGF_MAP_DELTA (publishing_rule.hpp): a class change always goes out, a probability
// move only once it reaches the step from the value last published (so slow drifts go out once they add
// up), a variance move only beyond its relative step; and a client that applies every message holds, for
// every cell, the mapper's class and a probability within the step of the mapper's.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/delta/map_receiver.hpp"

namespace {

using namespace ogf::delta;

constexpr std::int8_t kFree = ogf::map_delta_t::CLASS_FREE;
constexpr std::int8_t kUnknown = ogf::map_delta_t::CLASS_UNKNOWN;
constexpr std::int8_t kOccupied = ogf::map_delta_t::CLASS_OCCUPIED;

// The class eq. (3) gives with r_o = 0.65, r_f = 0.35.
std::int8_t classOf(double p) { return p > 0.65 ? kOccupied : (p < 0.35 ? kFree : kUnknown); }

PublishedCell cellAt(int x, double p, float var = 0.5f) { return {{x, 0, 0}, quantiseProbability(p), classOf(p), var}; }

int cellsOf(const std::vector<ogf::map_delta_t>& msgs) {
  int n = 0;
  for (const auto& m : msgs) n += m.num_cells;
  return n;
}

TEST(PublishingRule, ClassChangeGoesOutWhateverTheProbabilityMove) {
  const PublishedCell published = cellAt(0, 0.649);
  const PublishedCell now = cellAt(0, 0.651);  // 0.002 apart, across r_o
  EXPECT_EQ(worthSending(now, published, PublishingRule{0.02, 0.0}.quantisedStep(), 0.0), Worth::kClass);
}

TEST(PublishingRule, ProbabilityMoveGoesOutOnlyFromTheStepOn) {
  const std::int32_t step = PublishingRule{0.02, 0.0}.quantisedStep();
  EXPECT_EQ(step, 200);
  EXPECT_EQ(worthSending(cellAt(0, 0.219), cellAt(0, 0.2), step, 0.0), Worth::kNothing);
  EXPECT_EQ(worthSending(cellAt(0, 0.22), cellAt(0, 0.2), step, 0.0), Worth::kProbability);
  EXPECT_EQ(worthSending(cellAt(0, 0.18), cellAt(0, 0.2), step, 0.0), Worth::kProbability);
}

TEST(PublishingRule, StepZeroSendsEveryVisibleChange) {
  const std::int32_t step = PublishingRule{0.0, 0.0}.quantisedStep();
  EXPECT_EQ(step, 1);
  const PublishedCell a = cellAt(0, 0.2);
  PublishedCell b = a;
  b.probability += 1;
  EXPECT_EQ(worthSending(b, a, step, 0.0) != Worth::kNothing, b.visiblyDiffers(a));
  b = a;
  b.variance = 0.01f;
  EXPECT_EQ(worthSending(b, a, step, 0.0), Worth::kNothing);
}

TEST(PublishingRule, VarianceMoveGoesOutBeyondItsRelativeStepOfAPublishedCell) {
  const std::int32_t step = PublishingRule{0.02, 0.0}.quantisedStep();
  EXPECT_EQ(worthSending(cellAt(0, 0.2, 0.6f), cellAt(0, 0.2, 1.0f), step, 0.5), Worth::kNothing);
  EXPECT_EQ(worthSending(cellAt(0, 0.2, 0.4f), cellAt(0, 0.2, 1.0f), step, 0.5), Worth::kProbability);
  // A cell never published (the prior, variance 0) does not go out for its variance alone.
  const PublishedCell prior{{0, 0, 0}, kPriorProbability, kUnknown, 0.0f};
  EXPECT_EQ(worthSending({{0, 0, 0}, kPriorProbability, kUnknown, 0.3f}, prior, step, 0.5), Worth::kNothing);
}

TEST(DeltaStream, SlowDriftGoesOutOnceItAddsUpToTheStep) {
  DeltaStream s({0.2, 1, 100}, PublishingRule{0.02, 0.0});
  EXPECT_EQ(cellsOf(s.update(1, std::vector{cellAt(0, 0.2)})), 1);  // free: a class change from the prior
  // 0.005 per update: each move alone is below the step; the fourth takes the cell 0.02 from what was sent.
  std::vector<int> sent;
  for (int i = 1; i <= 8; ++i) sent.push_back(cellsOf(s.update(1 + i, std::vector{cellAt(0, 0.2 - 0.005 * i)})));
  EXPECT_EQ(sent, (std::vector<int>{0, 0, 0, 1, 0, 0, 0, 1}));
  EXPECT_EQ(s.map().find({0, 0, 0})->probability, quantiseProbability(0.16));
}

// Cells random-walking through the classes, a step of 0.05: after every update the client's map has the
// checksum stamped on the messages, the mapper's class for every cell and a probability within the step.
TEST(DeltaStream, ClientHoldsTheMappersClassAndProbabilityWithinTheStep) {
  const PublishingRule rule{0.05, 0.0};
  DeltaStream s({0.2, 4, 64}, rule);
  MapReceiver r;
  for (const auto& m : s.keyframe(0)) r.accept(m);
  std::mt19937 rng(21);
  std::normal_distribution<double> move(0.0, 0.01);
  std::uniform_int_distribution<int> pick(0, 499);
  std::map<int, double> truth;  // the mapper's probability per cell
  std::size_t published_cells = 0, candidates = 0;
  for (int scan = 0; scan < 300; ++scan) {
    std::vector<PublishedCell> changed;
    for (int k = 0; k < 100; ++k) {
      const int x = pick(rng);
      auto [it, fresh] = truth.try_emplace(x, 0.5);
      it->second = std::clamp(it->second + move(rng), 0.0, 1.0);
      changed.push_back(cellAt(x, it->second));
    }
    const auto msgs = s.update(scan, changed);
    candidates += changed.size();
    published_cells += static_cast<std::size_t>(cellsOf(msgs));
    for (const auto& m : msgs) r.accept(m);
    ASSERT_TRUE(r.consistent());
    for (const auto& [x, p] : truth) {
      const PublishedCell mapper = cellAt(x, p);
      const PublishedCell client = r.map().find({x, 0, 0}).value_or(PublishedCell{{x, 0, 0}});
      ASSERT_EQ(client.cell_class, mapper.cell_class) << "cell " << x << " scan " << scan;
      ASSERT_LT(std::abs(client.probability - mapper.probability), rule.quantisedStep()) << "cell " << x;
    }
  }
  EXPECT_LT(published_cells, candidates / 2);  // the rule holds back most of the small moves
}

}  // namespace
