// Answers to map queries: see map_query_answer.hpp.
#include "ogf/mapper_daemon/map_query_answer.hpp"

#include <ogf/filter/map_queries.hpp>

#include <cmath>
#include <string>

namespace ogf::mapper_daemon {
namespace {

bool finite3(const float v[3]) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// Keys of the cells whose centres lie in [lo, hi] along one axis: the first and last index.
bool axisRange(double lo, double hi, double res, std::int32_t& first, std::int32_t& last) {
  const double a = std::ceil(lo / res - 0.5), b = std::floor(hi / res - 0.5);
  if (!(std::abs(a) < 1e9 && std::abs(b) < 1e9)) return false;
  first = static_cast<std::int32_t>(a);
  last = static_cast<std::int32_t>(b);
  return true;
}

}  // namespace

ogf::map_query_reply_t refuseQuery(const ogf::map_query_t& query, const std::string& why, std::int64_t now_utime) {
  ogf::map_query_reply_t r{};
  r.utime = now_utime;
  r.request_id = query.request_id;
  r.status = ogf::map_query_reply_t::STATUS_REFUSED;
  r.message = why;
  return r;
}

ogf::map_query_reply_t answerQuery(const ogf::map_query_t& query, const filter::BandedOgf& map, std::int64_t map_id,
                                   std::int64_t seq, std::int64_t now_utime) {
  const double res = map.config().resolution;
  ogf::map_query_reply_t r{};
  r.utime = now_utime;
  r.request_id = query.request_id;
  r.map_id = map_id;
  r.seq = seq;
  r.resolution = static_cast<float>(res);
  const auto refuse = [&](const std::string& why) { return refuseQuery(query, why, now_utime); };
  if (query.kind == ogf::map_query_t::KIND_CELLS) {
    if (query.num_points < 1 || query.num_points > kMaxQueryPoints) {
      return refuse("num_points " + std::to_string(query.num_points) + ": 1 to " + std::to_string(kMaxQueryPoints));
    }
    const auto n = static_cast<std::size_t>(query.num_points);
    if (query.points.size() != n) {
      return refuse("points: " + std::to_string(query.points.size()) + " rows for num_points " + std::to_string(n));
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (query.points[i].size() != 3) return refuse("points[" + std::to_string(i) + "] has not 3 coordinates");
      if (!finite3(query.points[i].data())) return refuse("points[" + std::to_string(i) + "] is not finite");
      for (const float v : query.points[i]) {
        if (std::abs(static_cast<double>(v) / res) > 1e9) return refuse("points[" + std::to_string(i) + "] is beyond the map's reach");
      }
    }
    r.num_cells = query.num_points;
    r.probability.resize(n);
    r.cell_class.resize(n);
    r.mean.resize(n);
    r.variance.resize(n);
    r.entropy.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& p = query.points[i];
      const CellKey key = cellKeyOf(Eigen::Vector3d(p[0], p[1], p[2]), res);
      const filter::CellQuery q = filter::queryCell(map, key);
      r.probability[i] = static_cast<float>(q.predictiveProbability);
      r.cell_class[i] = q.occupancyClass;
      r.mean[i] = static_cast<float>(q.mean);
      r.variance[i] = static_cast<float>(q.variance);
      r.entropy[i] = static_cast<float>(q.entropyBits);
    }
    r.status = ogf::map_query_reply_t::STATUS_OK;
    return r;
  }
  if (query.kind == ogf::map_query_t::KIND_BOX) {
    if (!finite3(query.box_min) || !finite3(query.box_max)) return refuse("box corners must be finite");
    CellKey lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      const double x0 = std::min(query.box_min[a], query.box_max[a]), x1 = std::max(query.box_min[a], query.box_max[a]);
      std::int32_t& first = a == 0 ? lo.x : a == 1 ? lo.y : lo.z;
      std::int32_t& last = a == 0 ? hi.x : a == 1 ? hi.y : hi.z;
      if (!axisRange(x0, x1, res, first, last)) return refuse("box is beyond the map's reach");
      if (first > last) return refuse("box holds no cell centre (thinner than a cell on an axis)");
    }
    if (map.config().dimensions == 2) lo.z = hi.z = 0;
    auto box = filter::summariseBox(map, lo, hi, static_cast<std::size_t>(kMaxQueryBoxCells));
    if (!box) return refuse(box.error().message);
    const double cellVolume = res * res * res;
    r.box_cells = static_cast<std::int64_t>(box->cells);
    r.box_occupied = static_cast<std::int64_t>(box->occupied);
    r.box_free = static_cast<std::int64_t>(box->free);
    r.box_unknown = static_cast<std::int64_t>(box->unknown);
    r.known_volume_m3 = static_cast<double>(box->occupied + box->free) * cellVolume;
    r.unknown_volume_m3 = static_cast<double>(box->unknown) * cellVolume;
    r.mean_entropy_bits = box->cells > 0 ? box->entropyBits / static_cast<double>(box->cells) : 0.0;
    r.mean_variance = box->meanVariance;
    r.status = ogf::map_query_reply_t::STATUS_OK;
    return r;
  }
  return refuse("kind " + std::to_string(query.kind) + ": 1 (cells) or 2 (box)");
}

}  // namespace ogf::mapper_daemon
