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
  // kApplied, kPartial, kBuffered, kKeyframeApplied, kGap, kStale, kMalformed, kDropped
  // (update_sequence.hpp).
  using Outcome = SequenceOutcome;

  // Updates held while waiting for earlier ones, at most.
  static constexpr std::size_t kDefaultBufferedUpdates = 256;

  // What the parts held waiting may take besides the map held (update_sequence.hpp): 64 MiB, a keyframe of
  // about 3 M cells to a client that holds nothing yet.
  static constexpr std::size_t kDefaultMinHeldBytes = std::size_t{64} << 20;

  // At most `max_buffered_updates` complete or partial updates are held while waiting (older ones are
  // discarded), and their parts hold at most `min_held_bytes` plus what map() holds.
  explicit MapReceiver(std::size_t max_buffered_updates = kDefaultBufferedUpdates,
                       std::size_t min_held_bytes = kDefaultMinHeldBytes)
      : sequence_(max_buffered_updates, min_held_bytes) {}

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
  // Updates and keyframes dropped because the parts held went over their byte bound, and what they hold now.
  std::uint64_t dropped() const { return sequence_.dropped(); }
  std::size_t heldBytes() const { return sequence_.heldBytes(); }
  // What they may hold now: the byte floor plus appliedBytes().
  std::size_t heldBytesLimit() const { return sequence_.heldBytesLimit(appliedBytes()); }
  // What map() takes, as the byte bound counts it.
  std::size_t appliedBytes() const;

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
