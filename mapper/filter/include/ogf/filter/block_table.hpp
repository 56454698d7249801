// The map's blocks by key: open addressing with linear probing over a power-of-two table kept at most
// half full, each slot holding the key and the owning pointer. A look-up is a hash and, mostly, one slot:
// one cache line, where a node-based hash map reads a bucket and then a node. Erasing shifts the following
// slots of the run back (no tombstones), so a table that pages regions in and out does not degrade.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace ogf::filter {

template <class Value>
class BlockTable {
 public:
  std::size_t size() const { return size_; }
  // Slots allocated (for the memory accounting).
  std::size_t capacity() const { return slots_.size(); }
  static constexpr std::size_t bytesPerSlot() { return sizeof(Slot); }

  Value* find(const CellKey& key) const {
    if (slots_.empty()) {
      return nullptr;
    }
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t s = home(key);; s = (s + 1) & mask) {
      const Slot& slot = slots_[s];
      if (slot.value == nullptr || slot.key == key) {
        return slot.value.get();
      }
    }
  }

  // The value of `key`, made by `make()` (a std::unique_ptr<Value>) when missing; `inserted` says which.
  template <class Make>
  Value& findOrInsert(const CellKey& key, Make&& make, bool& inserted) {
    if ((size_ + 1) * 2 > slots_.size()) {
      grow();
    }
    Slot& slot = slots_[probe(key)];
    inserted = slot.value == nullptr;
    if (inserted) {
      slot.key = key;
      slot.value = make();
      ++size_;
    }
    return *slot.value;
  }

  // Removes the value of `key`; false when there is none.
  bool erase(const CellKey& key) {
    if (slots_.empty()) {
      return false;
    }
    const std::size_t mask = slots_.size() - 1;
    std::size_t hole = probe(key);
    if (slots_[hole].value == nullptr) {
      return false;
    }
    slots_[hole].value.reset();
    --size_;
    // Backward shift: a later slot of the run moves into the hole unless its home lies cyclically in
    // (hole, s], where it would no longer be found.
    for (std::size_t s = (hole + 1) & mask; slots_[s].value != nullptr; s = (s + 1) & mask) {
      const std::size_t h = home(slots_[s].key);
      const bool stays = hole <= s ? (hole < h && h <= s) : (hole < h || h <= s);
      if (!stays) {
        slots_[hole] = std::move(slots_[s]);
        hole = s;
      }
    }
    return true;
  }

  // Every key and value, in the table's order (not deterministic).
  template <class Visit>
  void forEach(Visit&& visit) const {
    for (const Slot& slot : slots_) {
      if (slot.value != nullptr) {
        visit(slot.key, *slot.value);
      }
    }
  }

 private:
  struct Slot {
    CellKey key;
    std::unique_ptr<Value> value;  // null: empty
  };

  // The first slot `key` may be in (its run goes on from there).
  std::size_t home(const CellKey& key) const { return CellKeyHash{}(key) & (slots_.size() - 1); }

  // The slot holding `key`, or the empty slot where it would go.
  std::size_t probe(const CellKey& key) const {
    const std::size_t mask = slots_.size() - 1;
    std::size_t s = home(key);
    while (slots_[s].value != nullptr && !(slots_[s].key == key)) {
      s = (s + 1) & mask;
    }
    return s;
  }

  void grow() {
    std::vector<Slot> old =
        std::exchange(slots_, std::vector<Slot>(slots_.empty() ? 1024 : slots_.size() * 2));
    for (Slot& slot : old) {
      if (slot.value != nullptr) {
        Slot& to = slots_[probe(slot.key)];
        to.key = slot.key;
        to.value = std::move(slot.value);
      }
    }
  }

  std::vector<Slot> slots_;
  std::size_t size_ = 0;
};

}  // namespace ogf::filter
