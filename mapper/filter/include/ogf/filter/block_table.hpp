// The map's blocks by key: a CellKeyTable (open addressing, at most half full, backward-shift erase) of
// owning pointers, so a block stays where it is while the table grows or pages regions in and out.
#pragma once

#include <cstddef>
#include <memory>
#include <ogf/core/cell_key_table.hpp>

namespace ogf::filter {

template <class Value>
class BlockTable {
 public:
  std::size_t size() const { return table_.size(); }
  // Slots allocated (for the memory accounting).
  std::size_t capacity() const { return table_.capacity(); }
  static constexpr std::size_t bytesPerSlot() { return Table::bytesPerSlot(); }

  Value* find(const CellKey& key) const {
    const std::unique_ptr<Value>* owner = table_.find(key);
    return owner != nullptr ? owner->get() : nullptr;
  }

  // A hint that `key` is looked up soon: its home slot is asked of the CPU (the value itself is not).
  void prefetch(const CellKey& key) const { table_.prefetch(key); }

  // The value of `key`, made by `make()` (a std::unique_ptr<Value>) when missing; `inserted` says which.
  template <class Make>
  Value& findOrInsert(const CellKey& key, Make&& make, bool& inserted) {
    if (Value* value = find(key)) {
      inserted = false;
      return *value;
    }
    // Made before the slot is taken, so a failing make() leaves the table as it was.
    std::unique_ptr<Value> made = make();
    std::unique_ptr<Value>& owner = table_.obtain(key, inserted);
    owner = std::move(made);
    return *owner;
  }

  // Removes the value of `key`; false when there is none.
  bool erase(const CellKey& key) { return table_.erase(key); }

  // Every key and value, in the table's order (not deterministic).
  template <class Visit>
  void forEach(Visit&& visit) const {
    table_.forEach([&](const CellKey& key, const std::unique_ptr<Value>& owner) { visit(key, *owner); });
  }

 private:
  using Table = CellKeyTable<std::unique_ptr<Value>, 1, 2>;
  Table table_;
};

}  // namespace ogf::filter
