// PublishedMap's slabs by key: open addressing with linear probing, the slab stored in its slot (key and
// slab, 32 bytes). A look-up reads one slot, mostly one cache line, where a node-based hash map reads a
// bucket and then a node; and since the slot's place follows from the key alone, a caller that knows which
// slabs come next can prefetch them (prefetch()). The table is kept at most 3/4 full; erasing shifts the
// following slots of the run back, so paging slabs in and out leaves no tombstones.
//
// Slots move when the table grows or a slab is erased: a pointer from find() or obtain() holds until the
// next obtain() or erase().
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "ogf/delta/published_block.hpp"

namespace ogf::delta {

class SlabTable {
 public:
  std::size_t size() const { return size_; }
  // Slots allocated, for the memory accounting.
  std::size_t capacity() const { return slots_.size(); }
  static constexpr std::size_t bytesPerSlot() { return sizeof(Slot); }

  const PublishedBlock* find(const CellKey& key) const {
    if (slots_.empty()) return nullptr;
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t s = home(key);; s = (s + 1) & mask) {
      const Slot& slot = slots_[s];
      if (slot.key == key) return &slot.block;
      if (slot.key.x == kEmpty) return nullptr;
    }
  }
  PublishedBlock* find(const CellKey& key) {
    return const_cast<PublishedBlock*>(std::as_const(*this).find(key));
  }

  // The slab of `key`, an empty one added when there is none. `key` is a slab key (see kEmpty).
  PublishedBlock& obtain(const CellKey& key) {
    assert(key.x != kEmpty);
    if ((size_ + 1) * 4 > slots_.size() * 3) grow();
    Slot& slot = slots_[probe(key)];
    if (slot.key.x == kEmpty) {
      slot.key = key;
      ++size_;
    }
    return slot.block;
  }

  // Removes the slab of `key`; false when there is none.
  bool erase(const CellKey& key) {
    if (slots_.empty()) return false;
    const std::size_t mask = slots_.size() - 1;
    std::size_t hole = probe(key);
    if (slots_[hole].key.x == kEmpty) return false;
    --size_;
    // Backward shift: a later slot of the run moves into the hole unless its home lies cyclically in
    // (hole, s], where it would no longer be found.
    for (std::size_t s = (hole + 1) & mask; slots_[s].key.x != kEmpty; s = (s + 1) & mask) {
      const std::size_t h = home(slots_[s].key);
      const bool stays = hole <= s ? (hole < h && h <= s) : (hole < h || h <= s);
      if (!stays) {
        slots_[hole] = std::move(slots_[s]);
        hole = s;
      }
    }
    slots_[hole] = Slot{};
    return true;
  }

  // Empties the table and gives its slots back to the allocator.
  void clear() {
    std::vector<Slot>().swap(slots_);
    size_ = 0;
  }

  // Asks for the slot where `key`'s slab would be found first (a hint; nothing is read).
  void prefetch(const CellKey& key) const {
    if (!slots_.empty()) __builtin_prefetch(&slots_[home(key)]);
  }

  // Every key and slab, in the table's order (not deterministic).
  template <class Visit>
  void forEach(Visit&& visit) const {
    for (const Slot& slot : slots_) {
      if (slot.key.x != kEmpty) visit(slot.key, slot.block);
    }
  }

 private:
  // No slab has this x: slab keys are cell keys floor-divided by 8 in x and y, so |x| < 2^28.
  static constexpr std::int32_t kEmpty = std::numeric_limits<std::int32_t>::min();
  struct Slot {
    CellKey key{kEmpty, 0, 0};
    PublishedBlock block;
  };

  // The first slot `key` may be in (its run goes on from there).
  std::size_t home(const CellKey& key) const { return CellKeyHash{}(key) & (slots_.size() - 1); }

  // The slot holding `key`, or the empty slot where it would go.
  std::size_t probe(const CellKey& key) const {
    const std::size_t mask = slots_.size() - 1;
    std::size_t s = home(key);
    while (slots_[s].key.x != kEmpty && !(slots_[s].key == key)) s = (s + 1) & mask;
    return s;
  }

  void grow() {
    std::vector<Slot> old =
        std::exchange(slots_, std::vector<Slot>(slots_.empty() ? 1024 : slots_.size() * 2));
    for (Slot& slot : old) {
      if (slot.key.x != kEmpty) slots_[probe(slot.key)] = std::move(slot);
    }
  }

  std::vector<Slot> slots_;
  std::size_t size_ = 0;
};

}  // namespace ogf::delta
