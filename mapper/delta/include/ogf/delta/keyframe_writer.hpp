// A keyframe cut at one sequence number and written a part at a time, for a published map that is not all
// in memory: the cells in memory are copied when the keyframe is cut, the cells held in pages are read
// later, page by page, while updates go on (ogf-mapper sends keyframes from a thread of their own).
//
// Why cells read later still make a correct keyframe: a cell read at any sequence number s ≥ seq() holds
// its value at s, and the updates after seq() set every cell they change to its value after them, so a
// client that applies the keyframe and then the updates after seq() (MapReceiver does) ends with the
// mapper's map. A page holds its region's cells as they were when the region left memory, unchanged until
// it comes back, so a page named when the keyframe is cut has the cells' values at seq().
//
// The part count is fixed when the keyframe is cut, from the published map's size: cells beyond it are
// dropped and parts no cell reaches go out empty (a damaged page), so a client always sees every part,
// and the keyframe's checksum then tells it the map is not the mapper's.
#pragma once

#include <ogf/map_delta_t.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/delta/published_cell.hpp"

namespace ogf::delta {

class KeyframeWriter {
 public:
  // The keyframe of `stream`'s published map at its current seq(): its size, the paged-out cells included.
  KeyframeWriter(const DeltaStream& stream, std::int64_t utime);

  std::int64_t seq() const { return header_.seq; }
  std::size_t cells() const { return cells_; }
  std::int32_t partCount() const { return header_.part_count; }

  // Adds cells (in any order); each part they fill is appended to `out`.
  void add(std::span<const PublishedCell> cells, std::vector<ogf::map_delta_t>& out);
  // Appends the last part and an empty one for each part no cell reached.
  void finish(std::vector<ogf::map_delta_t>& out);

  // Cells added beyond the published map's size (dropped), and cells the parts lack.
  std::size_t surplus() const { return surplus_; }
  std::size_t missing() const { return cells_ > written_ ? cells_ - written_ : 0; }

 private:
  PartHeader header_;
  std::size_t per_;
  std::size_t cells_;
  std::size_t written_ = 0;
  std::size_t surplus_ = 0;
  std::int32_t next_ = 0;
  std::vector<PublishedCell> pending_;
};

}  // namespace ogf::delta
