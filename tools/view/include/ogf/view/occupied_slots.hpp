// The occupied cells a browser draws, each in a numbered slot (the index of its box in the page's
// instanced mesh). A cell keeps its slot while it stays occupied; a cell that stops being occupied frees
// its slot for the next one. Every browser shares the numbering, so an update is "slot i now holds this
// cell" or "slot i is empty", applied by the page with no lookup. The slots that changed since the last
// takeChanged() are what the next WebSocket frame carries.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "ogf/core/cell_key.hpp"
#include "ogf/delta/published_cell.hpp"

namespace ogf::view {

// A slot's content. probability == kEmptySlot marks a slot that holds no cell.
struct SlotCell {
  CellKey key;
  std::uint16_t probability = 0;  // as published: p * 10000
  float variance = 0.0f;
};
inline constexpr std::uint16_t kEmptySlot = 0xFFFF;

class OccupiedSlots {
 public:
  // Follows one published cell: an occupied cell takes (or keeps) a slot, any other class frees its slot.
  void set(const delta::PublishedCell& cell);
  // Replaces everything with `cells` (a keyframe or a map file), numbering from 0 without holes. The next
  // frame must then be a full one (fullPending()).
  void reset(std::span<const delta::PublishedCell> cells);

  std::size_t occupied() const { return index_.size(); }
  // Slots in use or freed: a page needs this many boxes.
  std::size_t slotCount() const { return slots_.size(); }
  const SlotCell& slot(std::uint32_t i) const { return slots_[i]; }

  // The slots changed since the last call, ascending, each once; clears the record.
  std::vector<std::uint32_t> takeChanged();
  // Whether a reset happened since the last takeFullPending(); clears the flag.
  bool takeFullPending();
  // Every slot holding a cell, ascending.
  std::vector<std::uint32_t> filledSlots() const;

 private:
  void mark(std::uint32_t i);

  std::vector<SlotCell> slots_;
  std::unordered_map<CellKey, std::uint32_t, CellKeyHash> index_;
  std::vector<std::uint32_t> free_;
  std::vector<std::uint8_t> changed_flag_;
  std::vector<std::uint32_t> changed_;
  bool full_pending_ = false;
};

}  // namespace ogf::view
