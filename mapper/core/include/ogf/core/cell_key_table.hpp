// Values by CellKey: open addressing with linear probing over a power-of-two table kept at most
// LoadNumerator / LoadDenominator full, each slot holding the key, whether it is used, and the value itself.
// A look-up is a hash and, mostly, one slot: one cache line, where a node-based hash map reads a bucket and
// then a node; and since a key's first slot follows from the key alone, a caller that knows which keys
// come next can prefetch them. Erasing shifts the following slots of the run back (no tombstones), so a
// table that pages regions in and out does not degrade.
//
// Slots move when the table grows or a key is erased: a pointer from find() or obtain() holds until the
// next obtain() or erase(). The filter's blocks (BlockTable) and the delta stream's slabs (SlabTable) are
// kept in one.
#pragma once

#include <cstddef>
#include <ogf/core/cell_key.hpp>
#include <utility>
#include <vector>

namespace ogf {

template <class Value, std::size_t LoadNumerator, std::size_t LoadDenominator>
class CellKeyTable {
  static_assert(0 < LoadNumerator && LoadNumerator < LoadDenominator, "the table must keep empty slots");

 public:
  CellKeyTable() = default;
  CellKeyTable(const CellKeyTable&) = default;
  CellKeyTable& operator=(const CellKeyTable&) = default;
  // A table moved from is empty (a defaulted move would leave its count beside no slots).
  CellKeyTable(CellKeyTable&& other) noexcept : slots_(std::move(other.slots_)), size_(std::exchange(other.size_, 0)) {
    other.slots_.clear();
  }
  CellKeyTable& operator=(CellKeyTable&& other) noexcept {
    if (this != &other) {
      slots_ = std::move(other.slots_);
      other.slots_.clear();
      size_ = std::exchange(other.size_, 0);
    }
    return *this;
  }

  std::size_t size() const { return size_; }
  // Slots allocated, for the memory accounting.
  std::size_t capacity() const { return slots_.size(); }
  static constexpr std::size_t bytesPerSlot() { return sizeof(Slot); }

  const Value* find(const CellKey& key) const {
    if (slots_.empty()) return nullptr;
    const Slot& slot = slots_[probe(key)];
    return slot.used ? &slot.value : nullptr;
  }
  Value* find(const CellKey& key) { return const_cast<Value*>(std::as_const(*this).find(key)); }

  // The value of `key`, a default-constructed one added when there is none; `inserted` says which.
  Value& obtain(const CellKey& key, bool& inserted) {
    if ((size_ + 1) * LoadDenominator > slots_.size() * LoadNumerator) grow();
    Slot& slot = slots_[probe(key)];
    inserted = !slot.used;
    if (inserted) {
      slot.key = key;
      slot.used = true;
      ++size_;
    }
    return slot.value;
  }
  Value& obtain(const CellKey& key) {
    bool inserted = false;
    return obtain(key, inserted);
  }

  // Removes the value of `key`; false when there is none.
  bool erase(const CellKey& key) {
    if (slots_.empty()) return false;
    const std::size_t mask = slots_.size() - 1;
    std::size_t hole = probe(key);
    if (!slots_[hole].used) return false;
    --size_;
    // Backward shift: a later slot of the run moves into the hole unless its home lies cyclically in
    // (hole, s], where it would no longer be found.
    for (std::size_t s = (hole + 1) & mask; slots_[s].used; s = (s + 1) & mask) {
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

  // Asks for the slot where `key` would be found first (a hint; nothing is read).
  void prefetch(const CellKey& key) const {
    if (!slots_.empty()) __builtin_prefetch(&slots_[home(key)]);
  }

  // Every key and value, in the table's order (not deterministic).
  template <class Visit>
  void forEach(Visit&& visit) const {
    for (const Slot& slot : slots_) {
      if (slot.used) visit(slot.key, slot.value);
    }
  }

 private:
  struct Slot {
    CellKey key;
    bool used = false;
    Value value{};
  };

  // The first slot `key` may be in (its run goes on from there).
  std::size_t home(const CellKey& key) const { return CellKeyHash{}(key) & (slots_.size() - 1); }

  // The slot holding `key`, or the empty slot where it would go.
  std::size_t probe(const CellKey& key) const {
    const std::size_t mask = slots_.size() - 1;
    std::size_t s = home(key);
    while (slots_[s].used && !(slots_[s].key == key)) s = (s + 1) & mask;
    return s;
  }

  void grow() {
    std::vector<Slot> old =
        std::exchange(slots_, std::vector<Slot>(slots_.empty() ? 1024 : slots_.size() * 2));
    for (Slot& slot : old) {
      if (slot.used) slots_[probe(slot.key)] = std::move(slot);
    }
  }

  std::vector<Slot> slots_;
  std::size_t size_ = 0;
};

}  // namespace ogf
