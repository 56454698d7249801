// The map as the delta stream describes it. ogf-mapper keeps one (the state it has published) and every
// client rebuilds one; the two are equal exactly when their checksums are, which is how a client proves it
// missed nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "ogf/delta/published_cell.hpp"

namespace ogf::delta {

class PublishedMap {
 public:
  // Sets (or adds) a cell.
  void set(const PublishedCell& cell);
  // The cell, or nullptr when it was never published.
  const PublishedCell* find(const CellKey& key) const;
  void clear();
  std::size_t size() const { return cells_.size(); }

  // Order-independent checksum of every cell (the wrapping sum of a 64-bit hash of key, probability,
  // class and the variance's bits), kept up to date in O(1) per change. 0 for an empty map.
  std::uint64_t checksum() const { return checksum_; }

  // Every cell in CellKey order (deterministic; for keyframes and exports).
  std::vector<PublishedCell> sortedCells() const;

 private:
  std::unordered_map<CellKey, PublishedCell, CellKeyHash> cells_;
  std::uint64_t checksum_ = 0;
};

// The hash one cell contributes to PublishedMap::checksum().
std::uint64_t cellChecksum(const PublishedCell& cell);

}  // namespace ogf::delta
