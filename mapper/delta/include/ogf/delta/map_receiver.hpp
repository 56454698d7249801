// The receiving side of OGF_MAP_DELTA: rebuilds the published map from deltas and keyframes, applies
// updates strictly in sequence, and says when it needs a keyframe (at start, after a gap, after the
// mapper restarted with a new map id) instead of guessing. A client answers needsKeyframe() by publishing
// map_request_t on OGF_MAP_REQUEST.
#pragma once

#include <ogf/map_delta_t.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ogf/delta/published_map.hpp"

namespace ogf::delta {

class MapReceiver {
 public:
  enum class Outcome {
    kApplied,          // an update (and any buffered ones after it) is now in the map
    kPartial,          // part of an update or keyframe, waiting for the rest
    kBuffered,         // a later update, held until the map catches up (or a keyframe arrives)
    kKeyframeApplied,  // a keyframe replaced the map
    kGap,              // an update was lost: the map is stale until a keyframe arrives
    kStale,            // an update the map already has, or one of an old map id: ignored
    kMalformed,        // inconsistent message (part index, sizes, kind): ignored
  };

  // At most this many complete or partial updates are held while waiting; older ones are discarded.
  explicit MapReceiver(std::size_t max_buffered_updates = 256) : max_buffered_(max_buffered_updates) {}

  Outcome accept(const ogf::map_delta_t& msg);

  // Called with every cell a delta sets, in the order it goes into map(), when the update is applied (a
  // viewer follows the map without diffing it). Keyframes replace the map without calling it: a
  // follower rebuilds from map() when keyframesApplied() grows.
  using CellSink = std::function<void(const PublishedCell&)>;
  void onDeltaCell(CellSink sink) { cell_sink_ = std::move(sink); }

  bool needsKeyframe() const { return need_keyframe_; }
  // The last update applied, -1 before the first keyframe.
  std::int64_t appliedSeq() const { return applied_seq_; }
  std::optional<std::int64_t> mapId() const { return map_id_; }
  double resolution() const { return resolution_; }
  const PublishedMap& map() const { return map_; }

  // The mapper's checksum of its published map after appliedSeq(); equals map().checksum() when nothing
  // was missed.
  std::optional<std::uint64_t> serverChecksum() const { return server_checksum_; }
  bool consistent() const { return server_checksum_ && *server_checksum_ == map_.checksum(); }

  std::uint64_t gaps() const { return gaps_; }
  std::uint64_t keyframesApplied() const { return keyframes_applied_; }
  std::uint64_t malformed() const { return malformed_; }

 private:
  struct Assembly {
    std::int8_t kind = 0;
    std::int64_t map_id = 0;
    std::int32_t part_count = 0;
    // Cells by part index, only for the parts that arrived (a part count claims no memory): applied in
    // part order whatever order the parts arrived in, so a cell that appears twice in one update ends as
    // the mapper left it.
    std::map<std::int32_t, std::vector<PublishedCell>> parts;
    std::uint64_t checksum = 0;
    bool complete() const { return static_cast<std::int32_t>(parts.size()) == part_count; }
  };

  static bool wellFormed(const ogf::map_delta_t& m);
  // Adds the message's part to the assembly of its (kind, seq); false on a part count mismatch.
  bool addPart(std::map<std::int64_t, Assembly>& table, const ogf::map_delta_t& m);
  void applyKeyframe(std::int64_t seq, Assembly& a);
  // Applies complete buffered deltas in order; declares a gap when a later update is complete while the
  // next one is not (the mapper sends an update's parts back to back, so the missing parts are gone).
  Outcome drain();
  void trim();

  std::size_t max_buffered_;
  CellSink cell_sink_;
  PublishedMap map_;
  std::optional<std::int64_t> map_id_;
  double resolution_ = 0.0;
  std::int64_t applied_seq_ = -1;
  bool need_keyframe_ = true;
  std::optional<std::uint64_t> server_checksum_;
  std::map<std::int64_t, Assembly> deltas_;     // by seq
  std::map<std::int64_t, Assembly> keyframes_;  // by seq
  std::uint64_t gaps_ = 0;
  std::uint64_t keyframes_applied_ = 0;
  std::uint64_t malformed_ = 0;
};

std::string toString(MapReceiver::Outcome o);

}  // namespace ogf::delta
