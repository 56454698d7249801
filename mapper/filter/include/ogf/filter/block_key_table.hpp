// A map from block keys to small integers for the length of one batch: open addressing with linear
// probing over a power-of-two table kept at most half full, cleared and reused from batch to batch, so
// grouping a scan's measurements by block costs a multiply and a probe or two per measurement instead of
// an unordered_map node per block.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <cstdint>
#include <limits>
#include <vector>

namespace ogf::filter {

class BlockKeyTable {
 public:
  static constexpr std::uint32_t kAbsent = std::numeric_limits<std::uint32_t>::max();

  // Forgets every key, keeps the memory.
  void clear() {
    for (std::uint32_t s : used_) {
      slots_[s].value = kAbsent;
    }
    used_.clear();
  }
  std::size_t size() const { return used_.size(); }

  // The value of `key`, or kAbsent.
  std::uint32_t find(const CellKey& key) const {
    if (slots_.empty()) {
      return kAbsent;
    }
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t s = CellKeyHash{}(key) & mask;; s = (s + 1) & mask) {
      const Slot& slot = slots_[s];
      if (slot.value == kAbsent || slot.key == key) {
        return slot.value;
      }
    }
  }

  // The value of `key`, inserting `value` when the key is new (then `inserted` is set). Inlined: it runs
  // once per measurement of a batch in random order.
  [[gnu::always_inline]] std::uint32_t findOrInsert(const CellKey& key, std::uint32_t value, bool& inserted) {
    if ((used_.size() + 1) * 2 > slots_.size()) [[unlikely]] {
      grow();
    }
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t s = CellKeyHash{}(key) & mask;; s = (s + 1) & mask) {
      Slot& slot = slots_[s];
      if (slot.value == kAbsent) [[unlikely]] {
        insertAt(s, key, value);
        inserted = true;
        return value;
      }
      if (slot.key == key) {
        inserted = false;
        return slot.value;
      }
    }
  }

 private:
  struct Slot {
    CellKey key;
    std::uint32_t value = kAbsent;
  };

  [[gnu::noinline]] void insertAt(std::size_t s, const CellKey& key, std::uint32_t value) {
    slots_[s] = {key, value};
    used_.push_back(static_cast<std::uint32_t>(s));
  }

  [[gnu::noinline]] void grow() {
    std::vector<Slot> old;
    old.reserve(used_.size());
    for (std::uint32_t s : used_) {
      old.push_back(slots_[s]);
    }
    slots_.assign(slots_.empty() ? 1024 : slots_.size() * 2, Slot{});
    used_.clear();
    bool inserted = false;
    for (const Slot& slot : old) {
      findOrInsert(slot.key, slot.value, inserted);
    }
  }

  std::vector<Slot> slots_;
  std::vector<std::uint32_t> used_;  // occupied slots, so clear() touches only those
};

}  // namespace ogf::filter
