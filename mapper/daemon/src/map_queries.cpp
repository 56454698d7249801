// ogf-mapper's answers to map queries (map_services.hpp): cells and rays at once, a box in chunks over
// several turns of the worker (map_query_answer.hpp), the regions they read brought back from their pages.
#include <ogf/map_query_reply_t.hpp>
#include <spdlog/spdlog.h>

#include <cmath>

#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/log_text.hpp"
#include "ogf/mapper_daemon/map_query_answer.hpp"
#include "ogf/mapper_daemon/map_services.hpp"

namespace ogf::mapper_daemon {

void MapServices::answer(const ogf::map_query_t& q) {
  const double res = options_.map.filter.resolution;
  if (q.kind == ogf::map_query_t::KIND_BOX) {
    // The limit from the corners alone: nothing of the map is read or paged in for a refused box.
    auto box = boxKeysOf(q, res, mapper_.filter().config().dimensions, options_.services.max_query_cells);
    if (!box) return refuseQuery(q, box.error().message);
    box_job_.emplace(BoxJob{q, ChunkedBox(*box, options_.services.box_chunk_cells), deltas_.mapId()});
    return;
  }
  persistence::MapPager* pager = persistence_.pager();
  if (pager && q.kind == ogf::map_query_t::KIND_CELLS && q.num_points >= 1 && q.num_points <= kMaxQueryPoints &&
      q.points.size() == static_cast<std::size_t>(q.num_points)) {
    // The regions holding the points, back from their pages (they go out again as the robot moves).
    for (const auto& p : q.points) {
      if (p.size() == 3 && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
        persistence_.reportPageDamage(
            pager->bringInBox(mapper_.filter(), {p[0], p[1], p[2]}, {p[0], p[1], p[2]}, &deltas_.map()));
    }
  }
  const auto reply = answerQuery(q, mapper_.filter(), deltas_.mapId(), deltas_.seq(), wallUtime());
  if (reply.status != ogf::map_query_reply_t::STATUS_OK) return refuseQuery(q, reply.message);
  spdlog::debug("map query {} from {}: answered", q.request_id, sanitisedForLog(q.requester));
  lcm_.publish(replyChannel(options_.query_channel), &reply);
}

void MapServices::stepBox() {
  BoxJob& job = *box_job_;
  if (job.map_id != deltas_.mapId()) {
    const ogf::map_query_t q = job.query;
    box_job_.reset();
    return refuseQuery(q, "the map was reset while the box was being answered; ask again");
  }
  const auto chunk = job.chunks.next();
  if (chunk) {
    const double res = options_.map.filter.resolution;
    if (persistence::MapPager* pager = persistence_.pager()) {
      // Only this chunk's regions come back from their pages.
      const auto corner = [res](const CellKey& k) {
        return Eigen::Vector3d((k.x + 0.5) * res, (k.y + 0.5) * res, (k.z + 0.5) * res);
      };
      const Eigen::Vector3d lo = corner(chunk->lo), hi = corner(chunk->hi);
      persistence_.reportPageDamage(pager->bringInBox(mapper_.filter(), {lo.x(), lo.y(), lo.z()},
                                                      {hi.x(), hi.y(), hi.z()}, &deltas_.map()));
    }
    auto part = filter::summariseBox(mapper_.filter(), chunk->lo, chunk->hi);
    if (!part) {
      const ogf::map_query_t q = job.query;
      box_job_.reset();
      return refuseQuery(q, part.error().message);
    }
    job.chunks.add(*part);
    return;
  }
  ogf::map_query_reply_t r{};
  r.utime = wallUtime();
  r.request_id = job.query.request_id;
  r.map_id = deltas_.mapId();
  r.seq = deltas_.seq();
  r.resolution = static_cast<float>(options_.map.filter.resolution);
  job.chunks.fill(r, options_.map.filter.resolution);
  spdlog::debug("map query {} from {}: answered", job.query.request_id, sanitisedForLog(job.query.requester));
  box_job_.reset();
  lcm_.publish(replyChannel(options_.query_channel), &r);
}

}  // namespace ogf::mapper_daemon
