// What the receivers of ogf's numbered streams (OGF_MAP_DELTA's MapReceiver, OGF_NAV_GRID's
// navigation::NavReceiver) share: updates numbered seq, each applying on top of seq - 1, and keyframes that
// replace the whole, both sent in parts. UpdateSequence assembles the parts, applies updates strictly in
// sequence, holds later ones until the earlier arrive, declares a gap when a later update is complete while
// the next one is not (the sender sends an update's parts back to back, so the missing parts are gone), and
// then needs a keyframe, as it does at start and when the sender starts a new map (a new map id). It never
// guesses. What a part carries (cells, tiles) and how it is applied is the receiver's: UpdateSequence hands it
// whole assemblies, in order.
//
// What it holds waiting is bounded twice, because anyone on the bus can send parts that never complete: by
// count (updates; keyframes) and by bytes. The parts held may take the receiver's byte floor plus as much as
// what the receiver already holds applied (a keyframe of the map a client follows fits beside that map; a
// keyframe of a larger map than the floor, to a client holding nothing, does not: the floor is the
// program's flag). Past it the assembly whose first part came first is dropped, complete or not, and
// counted; the receiver then needs a keyframe as after any loss.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <map>
#include <optional>
#include <string>
#include <utility>

namespace ogf::delta {

enum class SequenceOutcome {
  kApplied,          // an update (and any buffered ones after it) is now applied
  kPartial,          // part of an update or keyframe, waiting for the rest
  kBuffered,         // a later update, held until the receiver catches up (or a keyframe arrives)
  kKeyframeApplied,  // a keyframe replaced everything
  kGap,              // an update was lost: stale until a keyframe arrives
  kStale,            // an update already applied, or one of an old map id: ignored
  kMalformed,        // inconsistent message: ignored
  kDropped,          // this part's update or keyframe, the oldest held, dropped for the byte bound (dropped())
};

std::string toString(SequenceOutcome o);

// Where a part belongs, as every message of the streams says it.
struct PartPlace {
  bool keyframe = false;
  std::int64_t map_id = 0;
  std::int64_t seq = 0;
  std::int64_t base_seq = 0;  // seq - 1 for an update; a keyframe's is not looked at
  std::int32_t part_index = 0;
  std::int32_t part_count = 1;
  std::uint64_t checksum = 0;  // the sender's, of the whole after this update
};

// Part: what one message carries, converted; Meta: what the receiver keeps of an update's first part besides
// (resolution, band).
template <class Part, class Meta>
class UpdateSequence {
 public:
  struct Assembly {
    Meta meta{};
    std::int64_t map_id = 0;
    std::int32_t part_count = 0;
    std::uint64_t checksum = 0;
    // Parts by index, only those that arrived (a part count claims no memory): applied in part order
    // whatever order they arrived in.
    std::map<std::int32_t, Part> parts;
    std::size_t bytes = 0;      // what its parts hold, as the receiver counts them
    std::uint64_t arrival = 0;  // the order of its first part among all assemblies
    bool complete() const { return static_cast<std::int32_t>(parts.size()) == part_count; }
  };

  // At most `max_buffered_updates` complete or partial updates and 4 keyframes are held while waiting (older
  // ones are discarded), and their parts hold at most `min_held_bytes` plus what the sink holds applied.
  UpdateSequence(std::size_t max_buffered_updates, std::size_t min_held_bytes)
      : max_buffered_(max_buffered_updates), min_held_bytes_(min_held_bytes) {}

  // Takes one part, which holds `part_bytes` once converted. `make_part()` converts the message's content,
  // called only for a part not seen before. `sink` applies whole assemblies: sink.applyKeyframe(const
  // Assembly&) replaces everything, sink.applyUpdate(const Assembly&) applies an update on top;
  // sink.appliedBytes() is what it holds applied.
  template <class MakePart, class Sink>
  SequenceOutcome accept(const PartPlace& place, const Meta& meta, MakePart&& make_part, Sink& sink,
                         std::size_t part_bytes) {
    if (place.keyframe) {
      if (map_id_ && *map_id_ == place.map_id && !need_keyframe_ && place.seq <= applied_seq_)
        return SequenceOutcome::kStale;
      if (!addPart(keyframes_, place, meta, make_part, part_bytes)) return malformedPart(keyframes_, place.seq);
      if (!holdWithin(keyframes_, place.seq, sink.appliedBytes())) return SequenceOutcome::kDropped;
      Assembly& a = keyframes_[place.seq];
      if (!a.complete()) {
        trim();
        return SequenceOutcome::kPartial;
      }
      applyKeyframe(place.seq, a, sink);
      drain(sink);  // buffered updates after the keyframe
      holdWithin(keyframes_, place.seq, sink.appliedBytes());  // a smaller map than before lowers the bound
      return need_keyframe_ ? SequenceOutcome::kGap : SequenceOutcome::kKeyframeApplied;
    }
    if (map_id_ && *map_id_ != place.map_id && !need_keyframe_) {
      // The sender started a new map (a restart): only a keyframe can tell its state.
      need_keyframe_ = true;
      ++gaps_;
      while (!updates_.empty()) erase(updates_, updates_.begin());
    }
    if (!need_keyframe_ && place.seq <= applied_seq_) return SequenceOutcome::kStale;
    if (place.base_seq != place.seq - 1) return countMalformed();
    if (!addPart(updates_, place, meta, make_part, part_bytes)) return malformedPart(updates_, place.seq);
    trim();
    if (!holdWithin(updates_, place.seq, sink.appliedBytes())) return SequenceOutcome::kDropped;
    if (need_keyframe_) return SequenceOutcome::kBuffered;
    return drain(sink);
  }

  // A message the receiver's own checks refused.
  SequenceOutcome countMalformed() {
    ++malformed_;
    return SequenceOutcome::kMalformed;
  }

  bool needsKeyframe() const { return need_keyframe_; }
  std::int64_t appliedSeq() const { return applied_seq_; }
  std::optional<std::int64_t> mapId() const { return map_id_; }
  std::optional<std::uint64_t> serverChecksum() const { return server_checksum_; }
  std::uint64_t gaps() const { return gaps_; }
  std::uint64_t keyframesApplied() const { return keyframes_applied_; }
  std::uint64_t malformed() const { return malformed_; }
  // Assemblies dropped for the byte bound, and the bytes the parts held now hold.
  std::uint64_t dropped() const { return dropped_; }
  std::size_t heldBytes() const { return held_bytes_; }
  // What the parts held may take beside a sink that holds `applied_bytes` applied.
  std::size_t heldBytesLimit(std::size_t applied_bytes) const { return min_held_bytes_ + applied_bytes; }

 private:
  using Table = std::map<std::int64_t, Assembly>;

  // Adds the part to the assembly of its seq; false when its part count or map id disagrees with the parts
  // before it. A duplicate part is ignored.
  template <class MakePart>
  bool addPart(Table& table, const PartPlace& place, const Meta& meta, MakePart& make_part, std::size_t bytes) {
    Assembly& a = table[place.seq];
    if (a.part_count == 0) {
      a.meta = meta;
      a.map_id = place.map_id;
      a.part_count = place.part_count;
      a.checksum = place.checksum;
      a.arrival = arrivals_++;
    } else if (a.part_count != place.part_count || a.map_id != place.map_id) {
      return false;
    }
    if (a.parts.count(place.part_index) == 0) {
      a.parts.emplace(place.part_index, make_part());
      a.bytes += bytes;
      held_bytes_ += bytes;
    }
    return true;
  }

  SequenceOutcome malformedPart(Table& table, std::int64_t seq) {
    if (const auto it = table.find(seq); it != table.end()) erase(table, it);
    return countMalformed();
  }

  typename Table::iterator erase(Table& table, typename Table::iterator it) {
    held_bytes_ -= it->second.bytes;
    return table.erase(it);
  }

  // Drops the earliest-begun assemblies until the parts held fit their bound; false when the one of `seq` in
  // `table` (the part just taken) was among them.
  bool holdWithin(Table& table, std::int64_t seq, std::size_t applied_bytes) {
    const std::size_t limit = heldBytesLimit(applied_bytes);
    bool kept = true;
    while (held_bytes_ > limit) {
      Table* from = nullptr;
      typename Table::iterator oldest;
      for (Table* t : {&updates_, &keyframes_})
        for (auto it = t->begin(); it != t->end(); ++it)
          if (from == nullptr || it->second.arrival < oldest->second.arrival) {
            from = t;
            oldest = it;
          }
      if (from == nullptr) break;
      if (from == &table && oldest->first == seq) kept = false;
      erase(*from, oldest);
      ++dropped_;
    }
    return kept;
  }

  template <class Sink>
  void applyKeyframe(std::int64_t seq, Assembly& a, Sink& sink) {
    sink.applyKeyframe(a);
    applied_seq_ = seq;
    map_id_ = a.map_id;
    server_checksum_ = a.checksum;
    need_keyframe_ = false;
    ++keyframes_applied_;
    // Everything at or before the keyframe is in it. `a` is among the keyframes erased here, so its map id is
    // read first (reading it after the erase was a use after free, found by fuzz_map_delta_stream).
    const std::int64_t map_id = a.map_id;
    for (auto it = keyframes_.begin(); it != keyframes_.end() && it->first <= seq;) it = erase(keyframes_, it);
    for (auto it = updates_.begin(); it != updates_.end() && it->first <= seq;) it = erase(updates_, it);
    for (auto it = updates_.begin(); it != updates_.end();)
      it = (it->second.map_id != map_id) ? erase(updates_, it) : std::next(it);
  }

  // Applies complete buffered updates in order; declares a gap when a later update is complete while the
  // next one is not.
  template <class Sink>
  SequenceOutcome drain(Sink& sink) {
    bool applied = false;
    while (!need_keyframe_) {
      auto next = updates_.find(applied_seq_ + 1);
      if (next != updates_.end() && next->second.complete()) {
        sink.applyUpdate(next->second);
        server_checksum_ = next->second.checksum;
        applied_seq_ = next->first;
        erase(updates_, next);
        applied = true;
        continue;
      }
      for (const auto& [seq, a] : updates_) {
        if (seq > applied_seq_ + 1 && a.complete()) {
          need_keyframe_ = true;
          ++gaps_;
          return SequenceOutcome::kGap;
        }
      }
      break;
    }
    return applied ? SequenceOutcome::kApplied : SequenceOutcome::kPartial;
  }

  void trim() {
    while (updates_.size() > max_buffered_) erase(updates_, updates_.begin());
    while (keyframes_.size() > 4) erase(keyframes_, keyframes_.begin());
  }

  std::size_t max_buffered_;
  std::size_t min_held_bytes_;
  std::size_t held_bytes_ = 0;
  std::uint64_t arrivals_ = 0;
  std::uint64_t dropped_ = 0;
  std::optional<std::int64_t> map_id_;
  std::int64_t applied_seq_ = -1;
  bool need_keyframe_ = true;
  std::optional<std::uint64_t> server_checksum_;
  Table updates_;    // by seq
  Table keyframes_;  // by seq
  std::uint64_t gaps_ = 0;
  std::uint64_t keyframes_applied_ = 0;
  std::uint64_t malformed_ = 0;
};

}  // namespace ogf::delta
