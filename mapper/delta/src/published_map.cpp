#include "ogf/delta/published_map.hpp"

#include <algorithm>
#include <bit>
#include <utility>

namespace ogf::delta {
namespace {

// splitmix64's finaliser: every input bit affects every output bit.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

PublishedCell cellOf(const CellKey& key, const PublishedValue& v) {
  return {key, v.probability, v.cell_class, v.variance};
}

// cellChecksum in two parts: the key's hash, then the value mixed into it. A cell that changes hashes its
// key once for the old value's term and the new one's.
std::uint64_t keyHash(const CellKey& key) {
  std::uint64_t h = mix(static_cast<std::uint32_t>(key.x));
  h = mix(h ^ static_cast<std::uint32_t>(key.y));
  return mix(h ^ static_cast<std::uint32_t>(key.z));
}

std::uint64_t valueHash(std::uint64_t key_hash, const PublishedValue& v) {
  return mix(key_hash ^ (static_cast<std::uint64_t>(static_cast<std::uint16_t>(v.probability)) |
                         static_cast<std::uint64_t>(static_cast<std::uint8_t>(v.cell_class)) << 16 |
                         static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(v.variance)) << 24));
}

PublishedValue valueOf(const PublishedCell& c) { return {c.probability, c.cell_class, c.variance}; }

}  // namespace

std::uint64_t cellChecksum(const PublishedCell& c) { return valueHash(keyHash(c.key), valueOf(c)); }

void PublishedMap::set(const PublishedCell& cell) {
  last_ = nullptr;  // obtain() may move the slabs
  put(blocks_.obtain(PublishedBlock::blockKeyOf(cell.key)), cell);
}

void PublishedMap::putAt(const PublishedCell& cell, bool present, std::size_t rank, const PublishedValue& old) {
  // Only a cell that is set allocates a slab: candidates equal to the prior leave no trace.
  if (last_ == nullptr) last_ = &blocks_.obtain(lastKey_);  // other slabs may move; only this one is kept
  const std::uint64_t key_hash = keyHash(cell.key);
  if (present) {
    last_->replaceAt(rank, valueOf(cell));
    checksum_ -= valueHash(key_hash, old);
  } else {
    stored_ += last_->insertAt(PublishedBlock::localIndexOf(cell.key), rank, valueOf(cell));
    ++size_;
  }
  checksum_ += valueHash(key_hash, valueOf(cell));
}

void PublishedMap::put(PublishedBlock& block, const PublishedCell& cell) {
  const unsigned local = PublishedBlock::localIndexOf(cell.key);
  const std::size_t rank = block.rank(local);
  const std::uint64_t key_hash = keyHash(cell.key);
  if (block.has(local)) {
    checksum_ -= valueHash(key_hash, block.valueAt(rank));
    block.replaceAt(rank, valueOf(cell));
  } else {
    stored_ += block.insertAt(local, rank, valueOf(cell));
    ++size_;
  }
  checksum_ += valueHash(key_hash, valueOf(cell));
}

std::optional<PublishedCell> PublishedMap::find(const CellKey& key) const {
  const PublishedBlock* block = blocks_.find(PublishedBlock::blockKeyOf(key));
  if (block == nullptr) return std::nullopt;
  const auto value = block->find(PublishedBlock::localIndexOf(key));
  return value ? std::optional<PublishedCell>(cellOf(key, *value)) : std::nullopt;
}

void PublishedMap::clear() {
  last_ = nullptr;
  blocks_.clear();
  size_ = 0;
  stored_ = 0;
  checksum_ = 0;
  held_ = {};
}

template <class Visit>
void PublishedMap::forEachSlabIn(const CellKey& lo, const CellKey& hi, Visit visit) const {
  if (blocks_.size() == 0) return;
  const CellKey a = PublishedBlock::blockKeyOf(lo);
  const CellKey b = PublishedBlock::blockKeyOf(hi - CellKey{1, 1, 1});
  for (std::int32_t z = a.z; z <= b.z; ++z)
    for (std::int32_t y = a.y; y <= b.y; ++y)
      for (std::int32_t x = a.x; x <= b.x; ++x) {
        const CellKey key{x, y, z};
        if (const PublishedBlock* block = blocks_.find(key)) visit(key, *block);
      }
}

std::vector<PublishedCell> PublishedMap::cellsIn(const CellKey& lo, const CellKey& hi) const {
  std::vector<PublishedCell> out;
  forEachSlabIn(lo, hi, [&](const CellKey& key, const PublishedBlock& block) {
    for (std::uint64_t rest = block.present(); rest != 0; rest &= rest - 1) {
      const auto local = static_cast<unsigned>(std::countr_zero(rest));
      out.push_back(cellOf(PublishedBlock::cellKey(key, local), block.at(local)));
    }
  });
  return out;
}

PublishedMap::Held PublishedMap::evict(const CellKey& lo, const CellKey& hi) {
  Held out;
  std::vector<CellKey> slabs;
  forEachSlabIn(lo, hi, [&](const CellKey& key, const PublishedBlock& block) {
    for (std::uint64_t rest = block.present(); rest != 0; rest &= rest - 1) {
      const auto local = static_cast<unsigned>(std::countr_zero(rest));
      out.checksum += cellChecksum(cellOf(PublishedBlock::cellKey(key, local), block.at(local)));
    }
    out.cells += block.size();
    stored_ -= block.capacity();
    slabs.push_back(key);
  });
  last_ = nullptr;
  for (const CellKey& key : slabs) blocks_.erase(key);
  held_.cells += out.cells;
  held_.checksum += out.checksum;
  return out;
}

void PublishedMap::restore(std::span<const PublishedCell> cells) {
  last_ = nullptr;  // obtain() may move the slabs
  for (const PublishedCell& cell : cells) {
    const std::uint64_t hash = cellChecksum(cell);
    --held_.cells;
    held_.checksum -= hash;
    PublishedBlock& block = blocks_.obtain(PublishedBlock::blockKeyOf(cell.key));
    const unsigned local = PublishedBlock::localIndexOf(cell.key);
    if (block.has(local)) {
      // Published again while held: the cell in memory is the newer, the held copy is dropped.
      --size_;
      checksum_ -= hash;
      continue;
    }
    const std::size_t capacity = block.capacity();
    block.put(local, {cell.probability, cell.cell_class, cell.variance});
    stored_ += block.capacity() - capacity;
  }
}

void PublishedMap::hold(const Held& held) {
  size_ += held.cells;
  checksum_ += held.checksum;
  held_.cells += held.cells;
  held_.checksum += held.checksum;
}

void PublishedMap::forget(const Held& held) {
  size_ -= held.cells;
  checksum_ -= held.checksum;
  held_.cells -= held.cells;
  held_.checksum -= held.checksum;
}

std::vector<PublishedCell> PublishedMap::sortedCells() const {
  // Slabs sorted by key (x / 8, y / 8, z) give CellKey order without sorting the cells: for each slab
  // column x / 8, each x in it, each row y / 8 and each y in it, the cells (x, y, z) of that row's slabs
  // in z order.
  std::vector<std::pair<CellKey, const PublishedBlock*>> slabs;
  slabs.reserve(blocks_.size());
  blocks_.forEach([&](const CellKey& key, const PublishedBlock& block) { slabs.emplace_back(key, &block); });
  std::sort(slabs.begin(), slabs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });

  std::vector<PublishedCell> out;
  out.reserve(size_);
  std::vector<std::size_t> rows;  // where each y / 8 row of the current column starts in `slabs`
  for (std::size_t column = 0; column < slabs.size();) {
    std::size_t end = column;
    rows.clear();
    while (end < slabs.size() && slabs[end].first.x == slabs[column].first.x) {
      if (end == column || slabs[end].first.y != slabs[end - 1].first.y) rows.push_back(end);
      ++end;
    }
    rows.push_back(end);
    for (unsigned lx = 0; lx < PublishedBlock::kSide; ++lx)
      for (std::size_t r = 0; r + 1 < rows.size(); ++r)
        for (unsigned ly = 0; ly < PublishedBlock::kSide; ++ly) {
          const unsigned local = lx + PublishedBlock::kSide * ly;
          for (std::size_t s = rows[r]; s < rows[r + 1]; ++s) {
            const PublishedBlock& block = *slabs[s].second;
            if (block.has(local)) out.push_back(cellOf(PublishedBlock::cellKey(slabs[s].first, local), block.at(local)));
          }
        }
    column = end;
  }
  return out;
}

std::size_t PublishedMap::memoryBytes() const {
  return sizeof(*this) + blocks_.capacity() * SlabTable::bytesPerSlot() +
         stored_ * PublishedBlock::kCellBytes;
}

}  // namespace ogf::delta
