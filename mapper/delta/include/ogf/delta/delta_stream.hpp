// The publishing side of OGF_MAP_DELTA: turns the cells an update touched into map_delta_t messages that
// each fit one UDP datagram, numbered so a client can tell a gap from a quiet map, and cuts keyframes
// (the whole published map in parts) on request. Which changes go out is the publishing rule
// (publishing_rule.hpp); how many bytes an update may carry is its allowance (set from the channel's
// LinkBudget by ogf-mapper); cells worth sending beyond it wait in DeferredCells for later updates, and
// those beyond the waiting set's capacity leave their slab in StaleSlabs, read again from the map later.
#pragma once

#include <ogf/map_delta_t.hpp>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "ogf/delta/deferred_cells.hpp"
#include "ogf/delta/link_budget.hpp"
#include "ogf/delta/published_map.hpp"
#include "ogf/delta/publishing_rule.hpp"
#include "ogf/delta/stale_slabs.hpp"
#include "ogf/messages/limits.hpp"

namespace ogf::delta {

struct DeltaStreamConfig {
  double resolution = 0.2;         // metres per cell
  std::int64_t map_id = 0;         // identifies this map; a new map (restart) gets a new id
  std::int32_t max_cells_per_message = ogf::messages::kMaxDeltaCellsPerMessage;
};

// What one update did.
struct UpdateFigures {
  std::size_t worth = 0;     // candidates found worth sending under the rule (those of waiting cells, and
                             // those that joined stale slabs, not counted)
  std::size_t sent = 0;      // cells the update carried
  std::size_t deferred = 0;  // cells waiting after it
  std::size_t overflowed = 0;  // changes worth sending that went to a stale slab since the update before:
                               // they found the waiting set full (refreshStale's included), or slabs were
                               // stale already
  std::size_t stale = 0;     // stale slabs after it
  std::int64_t bytes = 0;    // encoded bytes of its messages
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
  explicit DeltaStream(const DeltaStreamConfig& config, const PublishingRule& rule = {});

  // Update seq()+1. The candidates (cells whose state changed) the rule finds worth sending against what
  // was published (a cell never published counts as the prior), and the waiting cells, go out within the
  // allowance: waiting class changes, new class changes, waiting other changes, new other changes, each
  // oldest first. Those sent go into the published map and the returned messages (at least one, possibly
  // with no cells, so every update number is seen by clients); the rest wait, each with its latest state.
  // While slabs are stale (stale()), a new change worth sending does not wait but joins them as its slab.
  // Each message carries the checksum of the published map after the whole update. Candidates name each
  // cell once (ScanMapper::apply reports each changed cell once).
  std::vector<ogf::map_delta_t> update(std::int64_t utime, std::span<const PublishedCell> candidates);

  // The rule of the updates to come.
  void setRule(const PublishingRule& rule) { rule_ = rule; }
  const PublishingRule& rule() const { return rule_; }
  // The encoded bytes each update to come may carry (LinkBudget::kUnbounded: no bound). An update's first
  // message goes out whatever the allowance.
  void allow(std::int64_t bytes) { allowance_ = bytes; }
  const UpdateFigures& lastUpdate() const { return figures_; }
  // Cells worth sending that wait for an allowance.
  const DeferredCells& deferred() const { return deferred_; }
  // The most cells that may wait; a change worth sending beyond it marks its slab stale instead (a waiting
  // probability move makes way for a class change, its own slab marked). Unbounded unless set.
  void limitWaiting(std::size_t cells) { deferred_.setCapacity(cells); }
  // limitWaiting to the cells `seconds` of a `bytes_per_s` budget carry (ogf-mapper: deltas.max_wait_s of
  // deltas.max_bytes_per_s).
  void limitWaitingTo(double bytes_per_s, double seconds);
  // Slabs whose changes found the waiting set full.
  const StaleSlabs& stale() const { return stale_; }
  // Changes that went to a stale slab (UpdateFigures::overflowed), since the stream began.
  std::size_t overflowed() const { return overflowed_; }

  // The stale slabs to read from the map now, oldest first, taken off the stale set: as many as the
  // waiting set has room for at a whole slab's cells each, at most `max`; none while it is full. The
  // caller reads the cells of each as the map holds them now (allocated cells only) and hands them to
  // refreshStale before the next update.
  static constexpr std::size_t kStaleSlabsPerUpdate = 256;
  std::vector<CellKey> staleSlabsToRead(std::size_t max = kStaleSlabsPerUpdate);
  // Judges `cells` (each named once) against the published map like an update's candidates: a waiting
  // cell takes the state, one worth sending waits for the next updates (or marks its slab stale again).
  void refreshStale(std::span<const PublishedCell> cells);

  // The encoded size of a message of `cells` cells, and of messages.
  static std::int64_t partBytes(std::size_t cells);
  static std::int64_t bytesOf(std::span<const ogf::map_delta_t> messages);
  // The most cells one update can carry in `bytes` (split into parts of max_cells_per_message).
  std::size_t cellsWithin(std::int64_t bytes) const;

  // The whole published map at seq() as a keyframe (kind KEYFRAME, base_seq -1), in parts, in CellKey
  // order, when all of it is in memory; a map with cells held elsewhere (PublishedMap::evict) is sent with
  // a KeyframeWriter.
  std::vector<ogf::map_delta_t> keyframe(std::int64_t utime) const;

  // Replaces the published map wholesale (after a restart from a snapshot) and continues numbering after
  // `seq`, without publishing; clients learn it from the next keyframe. No cell waits after it.
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
  // Candidates come in runs of one slab: each new slab's slot is asked for kAhead candidates ahead, so its
  // look-up finds it in cache.
  static constexpr std::size_t kAhead = 128;
  void prefetchAhead(std::span<const PublishedCell> candidates, std::size_t i) const;
  // The worth of sending `c` against the published map, and whether the map holds the cell.
  std::pair<Worth, bool> judge(const PublishedCell& c, std::int32_t step, double variance_step);
  // An update under an allowance or with cells waiting (update() takes a one-pass path otherwise).
  void chooseWithin(std::span<const PublishedCell> candidates);
  // While slabs are stale the client is further behind than the waiting cells can hold: a change joins
  // the stale slabs as its slab, which is read again from the map in its turn, oldest first, and costs
  // one judgement a run of candidates in the slab instead of one each; a waiting cell still takes its
  // newest state.
  void joinStale(std::span<const PublishedCell> candidates);
  // Moves waiting cells of that worth into chosen_ while room is left; cells whose published copy left
  // with its region (PublishedMap::evict), or no longer worth sending, are dropped.
  void takeDeferred(Worth worth, std::size_t& room);
  // Puts a cell worth sending into the waiting set, or marks its slab stale when the set is full.
  void wait(const DeferredCells::Entry& entry);

  DeltaStreamConfig config_;
  PublishingRule rule_;
  PublishedMap map_;
  std::int64_t seq_ = 0;
  std::int64_t allowance_ = LinkBudget::kUnbounded;
  DeferredCells deferred_;
  StaleSlabs stale_;
  std::size_t overflowed_ = 0;
  std::size_t overflowed_reported_ = 0;  // overflowed_ at the last update's figures
  UpdateFigures figures_;
  // Reused between updates.
  std::vector<PublishedCell> changed_;
  // A candidate worth sending, by its index in the update's candidates: a scan far over its budget has a
  // million of them, and a copy of each would be a third of the update's memory traffic.
  struct Wanted {
    std::uint32_t index = 0;
    Worth worth = Worth::kNothing;
    bool present = false;  // whether the published map held the cell
  };
  std::vector<Wanted> wanted_;
  std::vector<DeferredCells::Entry> chosen_;
  std::vector<DeferredCells::Entry> evicted_;
};

}  // namespace ogf::delta
