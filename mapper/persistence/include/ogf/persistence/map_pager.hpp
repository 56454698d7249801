// The far parts of a long mission's map held on disk. The map is cut into regions of 4×4×4 blocks (32 cells
// on a side); sendAway() writes every region whose nearest point lies farther than a distance from the
// sensor to a page file (page_file.hpp) and drops its blocks from the filter; bringIn(), called before an
// update, reads back every paged-out region the update can reach. The filter's update of a measurement
// writes only the blocks within one block of the measured cell's (the stencil's reach, banded_ogf.hpp), so
// a map mapped with paging is bit-identical to one mapped without, whatever the distance (tested).
//
// With a published map (the delta stream's, delta/published_map.hpp) the region's published cells go to the
// page with its blocks and come back with them, so the daemon's memory follows the resident map for both;
// they still count in the published map's size and checksum while out, and a keyframe reads them from
// their pages (heldPublishedPages, publishedCellsOf).
//
// Page files are never rewritten: a region paged out again gets a new file, so a snapshot can name the
// pages that hold the rest of its map (state_directory.hpp), and they stay valid after the region has come
// back; collect() deletes the files that neither the pager nor a kept snapshot names.
#pragma once

#include <ogf/filter/banded_ogf.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/core/measurement.hpp"
#include "ogf/delta/published_map.hpp"

namespace ogf::persistence {

struct PagerCounts {
  std::size_t regions_out = 0;   // regions on disk now
  std::size_t blocks_out = 0;    // their blocks
  std::uint64_t bytes_out = 0;   // their page files' bytes
  std::size_t pages_written = 0;  // regions paged out so far
  std::size_t pages_read = 0;     // regions brought back so far
};

// A page that could not be read back (missing, truncated, corrupt, of another map's layout): its region is
// lost, the rest of the map is not.
struct PageDamage {
  std::filesystem::path file;
  std::string reason;
};

class MapPager {
 public:
  static constexpr int kRegionShift = 2;  // a region is 2^kRegionShift blocks on a side
  // A region's side, metres.
  static double regionSide(double resolution_m) { return resolution_m * filter::kBlockSide * (1 << kRegionShift); }
  // Below this page-out distance (the scans' reach plus two regions), regions go out and come back scan
  // after scan: the map is the same, the disk busier.
  static double churnDistance(double max_range_m, double resolution_m) {
    return max_range_m + 2 * regionSide(resolution_m);
  }

  // Pages in `dir`, created when missing. Error (with the system's reason) when it cannot be.
  static Result<MapPager> open(const std::filesystem::path& dir);

  // Takes over the pages a snapshot names (file names in dir): their regions count as paged out. Each file
  // is read once, to check it and to learn its blocks' and published cells' checksum terms; the damaged
  // ones are returned and their regions left to the prior.
  std::vector<PageDamage> adopt(std::span<const std::string> names, const filter::BandedOgf& map);
  // A restart, after adopt() and the journal's replay: bringInUnpublished() reads back the regions whose
  // pages hold no published cells (version 1), so that the published map built from the filter's cells in
  // memory has theirs; holdPublished() then counts the published cells of the other adopted pages in it
  // (PublishedMap::hold). The rest of the map stays on disk.
  std::vector<PageDamage> bringInUnpublished(filter::BandedOgf& map);
  void holdPublished(delta::PublishedMap& published);

  // Reads back every paged-out region an update with `measurements` can reach, and its published cells into
  // `published` when they went out from it. Damaged pages are returned (their regions are then prior, and
  // no longer paged out; their published cells are forgotten).
  std::vector<PageDamage> bringIn(filter::BandedOgf& map, std::span<const Measurement> measurements,
                                  delta::PublishedMap* published = nullptr);
  // Reads back every paged-out region that holds cells of the box [lo, hi] (map frame, metres).
  std::vector<PageDamage> bringInBox(filter::BandedOgf& map, const std::array<double, 3>& lo,
                                     const std::array<double, 3>& hi, delta::PublishedMap* published = nullptr);
  // Reads back every region (before a save or export of the whole map).
  std::vector<PageDamage> bringInAll(filter::BandedOgf& map, delta::PublishedMap* published = nullptr);

  // Pages out the regions of `map` whose nearest point lies farther than `distance_m` from `position` (map
  // frame, metres); a no-op until the position has moved a quarter of a region since the last call that
  // looked, or a region was brought back since. Error (nothing dropped from the map for the region that failed) when a page cannot be written.
  // A page is written under a name no file had, and not flushed: sync() makes it durable. With
  // `published`, the regions' published cells go out too (PublishedMap::evict).
  Status sendAway(filter::BandedOgf& map, const std::array<double, 3>& position, double distance_m,
                  delta::PublishedMap* published = nullptr);
  // The pages that hold the published cells of the regions paged out with a published map (for a
  // keyframe), to be read on another thread (publishedCellsOf). They stay on disk while collect() is told
  // to keep them, even after their regions come back.
  std::vector<std::filesystem::path> heldPublishedPages() const;
  // The published cells of the page at `path`; reads the file only, so any thread may call it.
  static Result<std::vector<delta::PublishedCell>> publishedCellsOf(const std::filesystem::path& path);
  // Flushes (fsync) the pages written since the last sync and still paged out, and the directory: call it
  // before a snapshot names them. A crash before leaves pages that no snapshot names; collect() removes them.
  Status sync();
  // The same in two steps, so the flush can run on another thread: takeUnsynced() names the files sync()
  // would flush (and forgets them), flushPages() flushes them and the directory (any thread; the files stay
  // until collect(), which must not run in between). When the flush fails, giveBackUnsynced() makes the
  // next sync() flush them again.
  struct PageFlush {
    std::filesystem::path dir;
    std::vector<std::string> names;
  };
  PageFlush takeUnsynced();
  static Status flushPages(const PageFlush& flush);
  void giveBackUnsynced(const PageFlush& flush);

  // The file names of the paged-out regions, sorted: what a snapshot must name with the map it holds.
  std::vector<std::string> files() const;
  // Checksum term of the paged-out blocks, for BandedOgf::checksum.
  filter::BlockHashSum heldBlocks() const { return held_; }
  std::size_t heldCells(const filter::BandedOgf& map) const { return held_.blocks * map.cellsPerBlock(); }
  PagerCounts counts() const {
    return {paged_.size(), held_.blocks, bytes_out_, pages_written_, pages_read_};
  }
  const std::filesystem::path& dir() const { return dir_; }

  // Deletes the page files in dir that are not paged out now and not in `keep` (the names a snapshot that
  // may still be restored refers to); returns how many.
  std::size_t collect(std::span<const std::string> keep);

 private:
  struct PagedRegion {
    std::string file;
    filter::BlockHashSum blocks;
    std::uint64_t bytes = 0;
    bool publishedKnown = false;          // the page holds the region's published cells
    bool publishedOut = false;            // they count in a published map as held elsewhere
    delta::PublishedMap::Held published;  // their count and checksum term
  };
  explicit MapPager(std::filesystem::path dir, std::uint64_t next) : dir_(std::move(dir)), next_(next) {}
  // Reads one region back into `map` (and `published`); on damage the region is forgotten all the same.
  void load(filter::BandedOgf& map, const CellKey& region, std::vector<PageDamage>& damage,
            delta::PublishedMap* published);
  // Counts a region as paged out, and no longer.
  void remember(const CellKey& region, PagedRegion paged);
  void forget(const CellKey& region);

  std::filesystem::path dir_;
  std::uint64_t next_ = 0;  // number of the next page file, above every one in dir
  std::unordered_map<CellKey, PagedRegion, CellKeyHash> paged_;
  std::vector<std::string> unsynced_;
  filter::BlockHashSum held_;  // the paged-out blocks
  std::uint64_t bytes_out_ = 0;  // their pages' bytes
  std::size_t pages_written_ = 0;
  std::size_t pages_read_ = 0;
  std::array<double, 3> last_position_{};
  std::size_t read_at_look_ = 0;  // pages_read_ when sendAway last looked
  bool looked_ = false;
};

}  // namespace ogf::persistence
