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

#include "ogf/navigation/nav_grid.hpp"
#include "ogf/navigation/nav_projection.hpp"

namespace ogf::navigation {

class NavReceiver {
 public:
  enum class Outcome {
    kApplied,          // an update (and any buffered ones after it) is now in the grid
    kPartial,          // part of an update or keyframe, waiting for the rest
    kBuffered,         // a later update, held until the grid catches up (or a keyframe arrives)
    kKeyframeApplied,  // a keyframe replaced the grid
    kGap,              // an update was lost: the grid is stale until a keyframe arrives
    kStale,            // an update the grid already has, or one of an old map id: ignored
    kMalformed,        // inconsistent message: ignored
  };

  explicit NavReceiver(std::size_t max_buffered_updates = 64) : max_buffered_(max_buffered_updates) {}

  Outcome accept(const ogf::nav_grid_t& msg);

  bool needsKeyframe() const { return need_keyframe_; }
  std::int64_t appliedSeq() const { return applied_seq_; }
  std::optional<std::int64_t> mapId() const { return map_id_; }

  // The grid rebuilt so far (resolution and band from the last message applied).
  NavColumn column(const ColumnKey& key) const;
  NavGrid grid() const;
  // The tiles holding at least one known column, sorted, and a tile's kTileSize² values row-major from its
  // south-west column (unknown for a tile not held), as NavProjection gives them: a viewer follows the grid
  // tile by tile without building the dense rectangle, whose size tiles far apart would make unbounded.
  std::vector<TileKey> knownTiles() const;
  // The resolution and band of the last message applied (0 and the default band before any).
  double resolution() const { return resolution_; }
  const NavBand& band() const { return band_; }
  void tileValues(const TileKey& tile, std::span<std::int8_t> cost, std::span<std::int8_t> column_class) const;
  std::size_t knownColumns() const { return known_columns_; }
  std::uint64_t checksum() const { return checksum_; }
  // The mapper's checksum after appliedSeq().
  std::optional<std::uint64_t> serverChecksum() const { return server_checksum_; }
  bool consistent() const { return server_checksum_ && *server_checksum_ == checksum_; }

  std::uint64_t gaps() const { return gaps_; }
  std::uint64_t keyframesApplied() const { return keyframes_applied_; }
  std::uint64_t malformed() const { return malformed_; }

 private:
  struct TileValues {
    std::vector<std::int8_t> cost, column_class;  // kTileSize² each
  };
  struct Assembly {
    std::int8_t kind = 0;
    std::int64_t map_id = 0;
    std::int32_t part_count = 0;
    std::uint64_t checksum = 0;
    double resolution = 0.0;
    NavBand band;
    std::map<std::int32_t, std::vector<std::pair<TileKey, TileValues>>> parts;
    bool complete() const { return static_cast<std::int32_t>(parts.size()) == part_count; }
  };

  static bool wellFormed(const ogf::nav_grid_t& m);
  bool addPart(std::map<std::int64_t, Assembly>& table, const ogf::nav_grid_t& m);
  void applyTiles(Assembly& a);
  void applyKeyframe(std::int64_t seq, Assembly& a);
  Outcome drain();
  void trim();
  void setTile(const TileKey& key, TileValues values);

  std::size_t max_buffered_;
  std::map<TileKey, TileValues> tiles_;
  double resolution_ = 0.0;
  NavBand band_;
  std::size_t known_columns_ = 0;
  std::uint64_t checksum_ = 0;
  std::optional<std::int64_t> map_id_;
  std::int64_t applied_seq_ = -1;
  bool need_keyframe_ = true;
  std::optional<std::uint64_t> server_checksum_;
  std::map<std::int64_t, Assembly> updates_;
  std::map<std::int64_t, Assembly> keyframes_;
  std::uint64_t gaps_ = 0;
  std::uint64_t keyframes_applied_ = 0;
  std::uint64_t malformed_ = 0;
};

std::string toString(NavReceiver::Outcome o);

}  // namespace ogf::navigation
