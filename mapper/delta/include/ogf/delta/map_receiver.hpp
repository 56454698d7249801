// The receiving side of OGF_MAP_DELTA: rebuilds the published map from deltas and keyframes, applies
// updates strictly in sequence, and says when it needs a keyframe (at start, after a gap, after the
// mapper restarted with a new map id) instead of guessing. A client answers needsKeyframe() by publishing
// map_request_t on OGF_MAP_REQUEST.
#pragma once

#include <ogf/map_delta_t.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ogf/delta/published_map.hpp"
#include "ogf/delta/update_sequence.hpp"

namespace ogf::delta {

class MapReceiver {
 public:
  // kApplied, kPartial, kBuffered, kKeyframeApplied, kGap, kStale, kMalformed (update_sequence.hpp).
  using Outcome = SequenceOutcome;

  // At most this many complete or partial updates are held while waiting; older ones are discarded.
  explicit MapReceiver(std::size_t max_buffered_updates = 256) : sequence_(max_buffered_updates) {}

  Outcome accept(const ogf::map_delta_t& msg);

  // Called with every cell a delta sets, in the order it goes into map(), when the update is applied (a
  // viewer follows the map without diffing it). Keyframes replace the map without calling it: a
  // follower rebuilds from map() when keyframesApplied() grows.
  using CellSink = std::function<void(const PublishedCell&)>;
  void onDeltaCell(CellSink sink) { cell_sink_ = std::move(sink); }

  bool needsKeyframe() const { return sequence_.needsKeyframe(); }
  // The last update applied, -1 before the first keyframe.
  std::int64_t appliedSeq() const { return sequence_.appliedSeq(); }
  std::optional<std::int64_t> mapId() const { return sequence_.mapId(); }
  double resolution() const { return resolution_; }
  const PublishedMap& map() const { return map_; }

  // The mapper's checksum of its published map after appliedSeq(); equals map().checksum() when nothing
  // was missed.
  std::optional<std::uint64_t> serverChecksum() const { return sequence_.serverChecksum(); }
  bool consistent() const { return serverChecksum() && *serverChecksum() == map_.checksum(); }

  std::uint64_t gaps() const { return sequence_.gaps(); }
  std::uint64_t keyframesApplied() const { return sequence_.keyframesApplied(); }
  std::uint64_t malformed() const { return sequence_.malformed(); }

 private:
  using Sequence = UpdateSequence<std::vector<PublishedCell>, double>;  // a part's cells; the resolution
  friend Sequence;

  static bool wellFormed(const ogf::map_delta_t& m);
  // UpdateSequence's sink.
  void applyKeyframe(const Sequence::Assembly& a);
  void applyUpdate(const Sequence::Assembly& a);

  Sequence sequence_;
  CellSink cell_sink_;
  PublishedMap map_;
  double resolution_ = 0.0;
};


}  // namespace ogf::delta
