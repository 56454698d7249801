// The occupied cells a browser draws, each in a numbered slot (the index of its box in the page's
// instanced mesh). A cell keeps its slot while it stays occupied; a cell that stops being occupied frees
// its slot for the next one. Every browser shares the numbering, so an update is "slot i now holds this
// cell" or "slot i is empty", applied by the page with no lookup. The slots that changed since the last
// takeChanged() are what the next WebSocket frame carries.
//
// Level of detail: with lod() = f > 1 a slot holds a box of f × f × f cells (key = the cells' key / f,
// rounded down), drawn while any of its cells is occupied, with the figures of the one that changed last.
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
  // Replaces everything with `cells` (a keyframe or a map file) at level of detail `lod` (a power of 2),
  // numbering from 0 without holes. The next frame must then be a full one (takeFullPending()).
  void reset(std::span<const delta::PublishedCell> cells, std::int32_t lod = 1);
  std::int32_t lod() const { return lod_; }
  // Occupied cells (each counted once, whatever the level of detail).
  std::size_t occupiedCells() const { return fine_.size(); }

  // Boxes drawn (occupied cells at level of detail 1).
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
  CellKey boxOf(const CellKey& k) const;

  std::int32_t lod_ = 1;
  std::unordered_map<CellKey, std::uint8_t, CellKeyHash> fine_;  // occupied cells (value unused)
  std::unordered_map<CellKey, std::uint32_t, CellKeyHash> count_;  // occupied cells per box, lod > 1

  std::vector<SlotCell> slots_;
  std::unordered_map<CellKey, std::uint32_t, CellKeyHash> index_;
  std::vector<std::uint32_t> free_;
  std::vector<std::uint8_t> changed_flag_;
  std::vector<std::uint32_t> changed_;
  bool full_pending_ = false;
};

// The finest level of detail (1, 2, 4, ... 64) at which the occupied `cells` make at most `max_boxes`
// boxes (64 when none does).
std::int32_t chooseLod(std::span<const delta::PublishedCell> cells, std::size_t max_boxes);

}  // namespace ogf::view
