// The publishing side of OGF_MAP_DELTA: turns the cells an update touched into map_delta_t messages that
// each fit one UDP datagram, numbered so a client can tell a gap from a quiet map, and cuts keyframes
// (the whole published map in parts) on request.
#pragma once

#include <ogf/map_delta_t.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "ogf/delta/published_map.hpp"
#include "ogf/messages/limits.hpp"

namespace ogf::delta {

struct DeltaStreamConfig {
  double resolution = 0.2;         // metres per cell
  std::int64_t map_id = 0;         // identifies this map; a new map (restart) gets a new id
  std::int32_t max_cells_per_message = ogf::messages::kMaxDeltaCellsPerMessage;
};

// What every part of one update or keyframe carries besides its cells.
struct PartHeader {
  std::int64_t utime = 0;
  std::int64_t map_id = 0;
  std::int64_t seq = 0;
  std::int64_t base_seq = 0;  // seq − 1 for an update, −1 for a keyframe
  std::int8_t kind = 0;
  double resolution = 0.0;
  std::int64_t checksum = 0;  // of the published map at seq
  std::int32_t part_count = 1;
};

// Part `index` of the update or keyframe `header` describes, holding `cells`.
ogf::map_delta_t makePart(const PartHeader& header, std::int32_t index, std::span<const PublishedCell> cells);

class DeltaStream {
 public:
  explicit DeltaStream(const DeltaStreamConfig& config);

  // Update seq()+1: the candidates whose quantised probability or class differs from what was published
  // (a cell never published counts as the prior) go into the published map and into the returned
  // messages (at least one, possibly with no cells, so every update number is seen by clients). Each
  // message carries the checksum of the published map after the whole update.
  std::vector<ogf::map_delta_t> update(std::int64_t utime, std::span<const PublishedCell> candidates);

  // The whole published map at seq() as a keyframe (kind KEYFRAME, base_seq -1), in parts, in CellKey
  // order, when all of it is in memory; a map with cells held elsewhere (PublishedMap::evict) is sent with
  // a KeyframeWriter.
  std::vector<ogf::map_delta_t> keyframe(std::int64_t utime) const;

  // Replaces the published map wholesale (after a restart from a snapshot) and continues numbering after
  // `seq`, without publishing; clients learn it from the next keyframe.
  void reset(std::span<const PublishedCell> cells, std::int64_t seq);

  std::int64_t seq() const { return seq_; }
  std::int64_t mapId() const { return config_.map_id; }
  const DeltaStreamConfig& config() const { return config_; }
  // The header of an update or keyframe of `cells` cells at seq(), with the published map's checksum.
  PartHeader header(std::int64_t utime, std::int8_t kind, std::int64_t base_seq, std::size_t cells) const;
  const PublishedMap& map() const { return map_; }
  // For paging the published cells with the filter's regions (persistence/map_pager.hpp).
  PublishedMap& map() { return map_; }

 private:
  std::vector<ogf::map_delta_t> split(std::int64_t utime, std::int8_t kind, std::int64_t base_seq,
                                      std::span<const PublishedCell> cells) const;

  DeltaStreamConfig config_;
  PublishedMap map_;
  std::int64_t seq_ = 0;
  std::vector<PublishedCell> changed_;  // reused between updates
};

}  // namespace ogf::delta
