// Answers to map queries: see map_query_answer.hpp.
#include "ogf/mapper_daemon/map_query_answer.hpp"

#include <ogf/filter/map_queries.hpp>

#include <algorithm>
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

Result<KeyBox> boxKeysOf(const ogf::map_query_t& query, double res, int dimensions, std::int64_t max_cells) {
  if (!finite3(query.box_min) || !finite3(query.box_max)) return Error{"box corners must be finite"};
  KeyBox box;
  double count = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double x0 = std::min(query.box_min[a], query.box_max[a]), x1 = std::max(query.box_min[a], query.box_max[a]);
    std::int32_t& first = a == 0 ? box.lo.x : a == 1 ? box.lo.y : box.lo.z;
    std::int32_t& last = a == 0 ? box.hi.x : a == 1 ? box.hi.y : box.hi.z;
    if (!axisRange(x0, x1, res, first, last)) return Error{"box is beyond the map's reach"};
    if (first > last) return Error{"box holds no cell centre (thinner than a cell on an axis)"};
  }
  if (dimensions == 2) box.lo.z = box.hi.z = 0;
  for (int a = 0; a < 3; ++a) {
    const std::int32_t lo = a == 0 ? box.lo.x : a == 1 ? box.lo.y : box.lo.z;
    const std::int32_t hi = a == 0 ? box.hi.x : a == 1 ? box.hi.y : box.hi.z;
    count *= static_cast<double>(hi) - static_cast<double>(lo) + 1.0;
  }
  if (count > static_cast<double>(max_cells))
    return Error{"box: " + std::to_string(static_cast<long long>(count)) + " cells exceed the limit of " +
                 std::to_string(max_cells)};
  box.cells = static_cast<std::int64_t>(count);
  return box;
}

ChunkedBox::ChunkedBox(const KeyBox& box, std::int64_t chunk_cells)
    : box_(box), chunk_cells_(std::max<std::int64_t>(1, chunk_cells)), at_(box.lo) {}

std::optional<KeyBox> ChunkedBox::next() {
  if (done_) return std::nullopt;
  const std::int64_t nz = std::int64_t{box_.hi.z} - box_.lo.z + 1, ny = std::int64_t{box_.hi.y} - box_.lo.y + 1;
  KeyBox c;
  c.lo = at_;
  c.hi = at_;
  if (at_.y == box_.lo.y && at_.z == box_.lo.z && ny * nz <= chunk_cells_) {
    // Whole x planes.
    const std::int64_t planes = std::min<std::int64_t>(chunk_cells_ / (ny * nz), std::int64_t{box_.hi.x} - at_.x + 1);
    c.hi = {static_cast<std::int32_t>(at_.x + planes - 1), box_.hi.y, box_.hi.z};
  } else if (at_.z == box_.lo.z && nz <= chunk_cells_) {
    // Rows of one plane.
    const std::int64_t rows = std::min<std::int64_t>(chunk_cells_ / nz, std::int64_t{box_.hi.y} - at_.y + 1);
    c.hi = {at_.x, static_cast<std::int32_t>(at_.y + rows - 1), box_.hi.z};
  } else {
    // A run of one column.
    const std::int64_t run = std::min<std::int64_t>(chunk_cells_, std::int64_t{box_.hi.z} - at_.z + 1);
    c.hi = {at_.x, at_.y, static_cast<std::int32_t>(at_.z + run - 1)};
  }
  c.cells = (std::int64_t{c.hi.x} - c.lo.x + 1) * (std::int64_t{c.hi.y} - c.lo.y + 1) * (std::int64_t{c.hi.z} - c.lo.z + 1);
  // The first cell after the chunk, in x, y, z order.
  at_ = c.hi;
  if (at_.z < box_.hi.z) {
    ++at_.z;
  } else if (at_.y < box_.hi.y) {
    at_.z = box_.lo.z;
    ++at_.y;
  } else if (at_.x < box_.hi.x) {
    at_.z = box_.lo.z;
    at_.y = box_.lo.y;
    ++at_.x;
  } else {
    done_ = true;
  }
  return c;
}

void ChunkedBox::add(const filter::BoxSummary& chunk) {
  sum_.cells += chunk.cells;
  sum_.allocated += chunk.allocated;
  sum_.occupied += chunk.occupied;
  sum_.free += chunk.free;
  sum_.unknown += chunk.unknown;
  sum_.entropyBits += chunk.entropyBits;
  variance_sum_ += chunk.meanVariance * static_cast<double>(chunk.cells);
}

void ChunkedBox::fill(ogf::map_query_reply_t& r, double res) const {
  const double cellVolume = res * res * res;
  r.box_cells = static_cast<std::int64_t>(sum_.cells);
  r.box_occupied = static_cast<std::int64_t>(sum_.occupied);
  r.box_free = static_cast<std::int64_t>(sum_.free);
  r.box_unknown = static_cast<std::int64_t>(sum_.unknown);
  r.known_volume_m3 = static_cast<double>(sum_.occupied + sum_.free) * cellVolume;
  r.unknown_volume_m3 = static_cast<double>(sum_.unknown) * cellVolume;
  r.mean_entropy_bits = sum_.cells > 0 ? sum_.entropyBits / static_cast<double>(sum_.cells) : 0.0;
  r.mean_variance = sum_.cells > 0 ? variance_sum_ / static_cast<double>(sum_.cells) : 0.0;
  r.status = ogf::map_query_reply_t::STATUS_OK;
}

ogf::map_query_reply_t answerQuery(const ogf::map_query_t& query, const filter::BandedOgf& map, std::int64_t map_id,
                                   std::int64_t seq, std::int64_t now_utime, std::int64_t max_box_cells) {
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
    auto box = boxKeysOf(query, res, map.config().dimensions, max_box_cells);
    if (!box) return refuse(box.error().message);
    ChunkedBox chunks(*box, 1'000'000);
    while (auto chunk = chunks.next()) {
      auto part = filter::summariseBox(map, chunk->lo, chunk->hi);
      if (!part) return refuse(part.error().message);
      chunks.add(*part);
    }
    chunks.fill(r, res);
    return r;
  }
  return refuse("kind " + std::to_string(query.kind) + ": 1 (cells) or 2 (box)");
}

}  // namespace ogf::mapper_daemon
