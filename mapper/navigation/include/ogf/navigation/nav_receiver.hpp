// The receiving side of OGF_NAV_GRID: rebuilds the 2-D grid from updates and keyframes, applies updates
// strictly in sequence and says when it needs a keyframe (at start, after a gap, after the mapper started a
// new map) instead of guessing, as delta::MapReceiver does for the 3-D stream. A client answers
// needsKeyframe() by publishing map_request_t on OGF_NAV_REQUEST. Messages are checked before use: a
// message whose sizes, tile size, part numbers, kind or values do not agree is counted and ignored.
#pragma once

#include <ogf/nav_grid_t.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <ogf/delta/update_sequence.hpp>

#include "ogf/navigation/nav_grid.hpp"
#include "ogf/navigation/nav_projection.hpp"

namespace ogf::navigation {

class NavReceiver {
 public:
  // kApplied, kPartial, kBuffered, kKeyframeApplied, kGap, kStale, kMalformed, kDropped
  // (delta/update_sequence.hpp).
  using Outcome = delta::SequenceOutcome;

  // Updates held while waiting for earlier ones, at most.
  static constexpr std::size_t kDefaultBufferedUpdates = 64;

  // What the parts held waiting may take besides the grid held (delta/update_sequence.hpp): 16 MiB, a
  // keyframe of about 7 800 tiles (8 M columns) to a client that holds nothing yet.
  static constexpr std::size_t kDefaultMinHeldBytes = std::size_t{16} << 20;

  explicit NavReceiver(std::size_t max_buffered_updates = kDefaultBufferedUpdates,
                       std::size_t min_held_bytes = kDefaultMinHeldBytes)
      : sequence_(max_buffered_updates, min_held_bytes) {}

  Outcome accept(const ogf::nav_grid_t& msg);

  bool needsKeyframe() const { return sequence_.needsKeyframe(); }
  std::int64_t appliedSeq() const { return sequence_.appliedSeq(); }
  std::optional<std::int64_t> mapId() const { return sequence_.mapId(); }

  // The grid rebuilt so far (resolution and band from the last update applied): the column, and the dense
  // rectangle (denseGrid's error, naming the limit, when the known columns span more than max_columns).
  NavColumn column(const ColumnKey& key) const;
  Result<NavGrid> grid(std::int64_t max_columns = kMaxDenseColumns) const;
  // The tiles holding at least one known column, sorted, and a tile's kTileSize² values row-major from its
  // south-west column (unknown for a tile not held), as NavProjection gives them: a viewer follows the grid
  // tile by tile without building the dense rectangle, whose size tiles far apart would make unbounded.
  std::vector<TileKey> knownTiles() const;
  // The resolution and band of the last message applied (0 and the default band before any).
  double resolution() const { return meta_.resolution; }
  const NavBand& band() const { return meta_.band; }
  void tileValues(const TileKey& tile, std::span<std::int8_t> cost, std::span<std::int8_t> column_class) const;
  std::size_t knownColumns() const { return known_columns_; }
  std::uint64_t checksum() const { return checksum_; }
  // The mapper's checksum after appliedSeq().
  std::optional<std::uint64_t> serverChecksum() const { return sequence_.serverChecksum(); }
  bool consistent() const { return serverChecksum() && *serverChecksum() == checksum_; }

  std::uint64_t gaps() const { return sequence_.gaps(); }
  std::uint64_t keyframesApplied() const { return sequence_.keyframesApplied(); }
  std::uint64_t malformed() const { return sequence_.malformed(); }
  // Updates and keyframes dropped because the parts held went over their byte bound, and what they hold now.
  std::uint64_t dropped() const { return sequence_.dropped(); }
  std::size_t heldBytes() const { return sequence_.heldBytes(); }
  // What they may hold now: the byte floor plus appliedBytes().
  std::size_t heldBytesLimit() const { return sequence_.heldBytesLimit(appliedBytes()); }
  // What the grid held takes, as the byte bound counts it.
  std::size_t appliedBytes() const;

 private:
  struct TileValues {
    std::vector<std::int8_t> cost, column_class;  // kTileSize² each
  };
  struct GridMeta {
    double resolution = 0.0;
    NavBand band;
  };
  using Sequence = delta::UpdateSequence<std::vector<std::pair<TileKey, TileValues>>, GridMeta>;
  friend Sequence;

  static bool wellFormed(const ogf::nav_grid_t& m);
  // UpdateSequence's sink.
  void applyKeyframe(const Sequence::Assembly& a);
  void applyUpdate(const Sequence::Assembly& a);
  void setTile(const TileKey& key, const TileValues& values);

  Sequence sequence_;
  std::map<TileKey, TileValues> tiles_;
  GridMeta meta_;
  std::size_t known_columns_ = 0;
  std::uint64_t checksum_ = 0;
};

}  // namespace ogf::navigation
