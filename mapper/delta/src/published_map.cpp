#include "ogf/delta/published_map.hpp"

#include <algorithm>
#include <bit>

namespace ogf::delta {
namespace {

// splitmix64's finaliser: every input bit affects every output bit.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace

std::uint64_t cellChecksum(const PublishedCell& c) {
  std::uint64_t h = mix(static_cast<std::uint32_t>(c.key.x));
  h = mix(h ^ static_cast<std::uint32_t>(c.key.y));
  h = mix(h ^ static_cast<std::uint32_t>(c.key.z));
  h = mix(h ^ (static_cast<std::uint64_t>(static_cast<std::uint16_t>(c.probability)) |
               static_cast<std::uint64_t>(static_cast<std::uint8_t>(c.cell_class)) << 16 |
               static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(c.variance)) << 24));
  return h;
}

void PublishedMap::set(const PublishedCell& cell) {
  auto [it, inserted] = cells_.try_emplace(cell.key, cell);
  if (!inserted) {
    checksum_ -= cellChecksum(it->second);
    it->second = cell;
  }
  checksum_ += cellChecksum(cell);
}

const PublishedCell* PublishedMap::find(const CellKey& key) const {
  const auto it = cells_.find(key);
  return it == cells_.end() ? nullptr : &it->second;
}

void PublishedMap::clear() {
  cells_.clear();
  checksum_ = 0;
}

std::vector<PublishedCell> PublishedMap::sortedCells() const {
  std::vector<PublishedCell> out;
  out.reserve(cells_.size());
  for (const auto& [key, cell] : cells_) out.push_back(cell);
  std::sort(out.begin(), out.end(), [](const PublishedCell& a, const PublishedCell& b) { return a.key < b.key; });
  return out;
}

}  // namespace ogf::delta
