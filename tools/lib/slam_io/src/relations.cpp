// The benchmark's relations file and metricEvaluator's metric (Kümmerle et al. 2009; the Freiburg tool as
// described in docs/test-data.md §3.3 and §3.4).
#include "ogf/slam_io/relations.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <istream>
#include <numbers>

#include "pose2_math.hpp"
#include "text_fields.hpp"

namespace ogf::slam_io {

namespace {

// Fields of a relation line: t1 t2 x y z roll pitch yaw.
constexpr std::size_t kRelationFields = 8;
// z, roll and pitch must be zero in a 2-D file; the files print 6 decimals.
constexpr double kPlanarTolerance = 1e-6;

// The pose whose stamp is nearest to t, or nullptr when none is within the tolerance.
const StampedPose* nearest(const std::vector<StampedPose>& trajectory, double t, double tolerance) {
  const auto after = std::lower_bound(trajectory.begin(), trajectory.end(), t,
                                      [](const StampedPose& p, double time) { return p.t < time; });
  const StampedPose* best = nullptr;
  if (after != trajectory.end()) best = &*after;
  if (after != trajectory.begin()) {
    const StampedPose* before = &*(after - 1);
    if (best == nullptr || t - before->t <= best->t - t) best = before;
  }
  if (best == nullptr || std::abs(best->t - t) > tolerance) return nullptr;
  return best;
}

// Mean, sample standard deviation (N - 1, as metricEvaluator prints it) and maximum.
ErrorStatistics statistics(const std::vector<double>& errors) {
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) return s;
  double sum = 0.0;
  for (double e : errors) {
    sum += e;
    s.max = std::max(s.max, e);
  }
  s.mean = sum / static_cast<double>(errors.size());
  if (errors.size() > 1) {
    double sq = 0.0;
    for (double e : errors) sq += (e - s.mean) * (e - s.mean);
    s.std = std::sqrt(sq / static_cast<double>(errors.size() - 1));
  }
  return s;
}

}  // namespace

Result<std::vector<Relation>> readRelations(std::istream& in, const std::string& source_name) {
  std::vector<Relation> relations;
  std::string line;
  std::size_t ln = 0;
  while (std::getline(in, line)) {
    ++ln;
    const auto f = detail::splitFields(line);
    if (f.empty() || f[0].front() == '#') continue;
    const std::string where = source_name + ":" + std::to_string(ln) + ": ";
    if (f.size() != kRelationFields) {
      return Error{where + "expected 8 fields (t1 t2 x y z roll pitch yaw), got " + std::to_string(f.size())};
    }
    std::array<double, kRelationFields> v{};
    for (std::size_t i = 0; i < kRelationFields; ++i) {
      const auto d = detail::parseDouble(f[i]);
      if (!d)
        return Error{where + "field " + std::to_string(i + 1) + " '" + std::string(f[i]) +
                     "' is not a finite number"};
      v[i] = *d;
    }
    if (std::abs(v[4]) > kPlanarTolerance || std::abs(v[5]) > kPlanarTolerance ||
        std::abs(v[6]) > kPlanarTolerance) {
      return Error{where + "z, roll and pitch must be 0 in a 2-D relations file"};
    }
    relations.push_back(Relation{v[0], v[1], Pose2{v[2], v[3], detail::normalizeAngle(v[7])}, ln});
  }
  if (in.bad()) return Error{source_name + ": read error after line " + std::to_string(ln)};
  return relations;
}

RelationMetric evaluateRelations(const std::vector<StampedPose>& trajectory,
                                 const std::vector<Relation>& relations, double tolerance_s) {
  RelationMetric metric;
  std::vector<double> translation;
  std::vector<double> rotation;
  translation.reserve(relations.size());
  rotation.reserve(relations.size());
  for (const Relation& rel : relations) {
    const StampedPose* p1 = nearest(trajectory, rel.t1, tolerance_s);
    const StampedPose* p2 = nearest(trajectory, rel.t2, tolerance_s);
    if (p1 == nullptr || p2 == nullptr) {
      ++metric.unmatched;
      continue;
    }
    // slamRel = T(t1)^-1 T(t2); delta = slamRel - reference, component-wise, angle normalised.
    const Pose2 estimated = detail::between(p1->pose, p2->pose);
    const double dx = estimated.x - rel.motion.x;
    const double dy = estimated.y - rel.motion.y;
    const double dyaw = detail::normalizeAngle(estimated.theta - rel.motion.theta);
    translation.push_back(std::hypot(dx, dy));
    rotation.push_back(std::abs(dyaw) * 180.0 / std::numbers::pi);
  }
  metric.translation = statistics(translation);
  metric.rotation_deg = statistics(rotation);
  for (double& e : translation) e *= e;
  for (double& e : rotation) e *= e;
  metric.translation_squared = statistics(translation);
  metric.rotation_squared_deg = statistics(rotation);
  return metric;
}

}  // namespace ogf::slam_io
