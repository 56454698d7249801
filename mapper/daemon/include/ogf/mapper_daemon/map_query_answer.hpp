// The answers of ogf-mapper's map services (OGF_MAP_QUERY): a map_query_t asked of the banded filter
// becomes a map_query_reply_t, the exploration queries of the paper's motivation: per cell probability,
// class, mean, variance and entropy; per box the known and unknown volume and the mean entropy. A query
// beyond the limits (more than kMaxQueryPoints points, more than kMaxQueryBoxCells cells, non-finite
// coordinates, an unknown kind) is refused with a message, never answered in part.
#pragma once

#include <ogf/filter/banded_ogf.hpp>
#include <ogf/filter/map_queries.hpp>
#include <ogf/map_query_reply_t.hpp>
#include <ogf/map_query_t.hpp>

#include <cstdint>
#include <optional>
#include <string>

#include "ogf/common/result.hpp"

namespace ogf::mapper_daemon {

inline constexpr std::int32_t kMaxQueryPoints = 10'000;
inline constexpr std::int64_t kMaxQueryBoxCells = 4'000'000;

ogf::map_query_reply_t answerQuery(const ogf::map_query_t& query, const filter::BandedOgf& map, std::int64_t map_id,
                                   std::int64_t seq, std::int64_t now_utime,
                                   std::int64_t max_box_cells = kMaxQueryBoxCells);

// The cells a KIND_BOX query covers, in keys: from its corners alone, so a box beyond `max_cells` (or
// malformed) is refused before any of the map is read or paged in. The error is the refusal's message.
struct KeyBox {
  CellKey lo{}, hi{};
  std::int64_t cells = 0;
};
Result<KeyBox> boxKeysOf(const ogf::map_query_t& query, double resolution, int dimensions, std::int64_t max_cells);

// A box summarised in chunks of at most `chunk_cells` cells (whole x planes, else rows of one plane, else
// runs of one column), so a large box is answered over several steps between scans. The chunks' sums are
// the box's sums; its mean variance is the cell-weighted mean of the chunks'.
class ChunkedBox {
 public:
  ChunkedBox(const KeyBox& box, std::int64_t chunk_cells);
  // The next chunk to summarise, nullopt when the whole box has been.
  std::optional<KeyBox> next();
  void add(const filter::BoxSummary& chunk);
  // The reply's box fields and status OK.
  void fill(ogf::map_query_reply_t& reply, double resolution) const;

 private:
  KeyBox box_;
  std::int64_t chunk_cells_;
  CellKey at_;  // the first cell not yet handed out
  bool done_ = false;
  filter::BoxSummary sum_;
  double variance_sum_ = 0.0;
};

// A reply that refuses `query` with `why` (for the daemon's own refusals, e.g. a full request queue).
ogf::map_query_reply_t refuseQuery(const ogf::map_query_t& query, const std::string& why, std::int64_t now_utime);

}  // namespace ogf::mapper_daemon
