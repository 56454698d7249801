// The answers of ogf-mapper's map services (OGF_MAP_QUERY): a map_query_t asked of the banded filter
// becomes a map_query_reply_t, the exploration queries of the paper's motivation: per cell probability,
// class, mean, variance and entropy; per box the known and unknown volume and the mean entropy. A query
// beyond the limits (more than kMaxQueryPoints points, more than kMaxQueryBoxCells cells, non-finite
// coordinates, an unknown kind) is refused with a message, never answered in part.
#pragma once

#include <ogf/filter/banded_ogf.hpp>
#include <ogf/map_query_reply_t.hpp>
#include <ogf/map_query_t.hpp>

#include <cstdint>

namespace ogf::mapper_daemon {

inline constexpr std::int32_t kMaxQueryPoints = 10'000;
inline constexpr std::int64_t kMaxQueryBoxCells = 4'000'000;

ogf::map_query_reply_t answerQuery(const ogf::map_query_t& query, const filter::BandedOgf& map, std::int64_t map_id,
                                   std::int64_t seq, std::int64_t now_utime);

// A reply that refuses `query` with `why` (for the daemon's own refusals, e.g. a full request queue).
ogf::map_query_reply_t refuseQuery(const ogf::map_query_t& query, const std::string& why, std::int64_t now_utime);

}  // namespace ogf::mapper_daemon
