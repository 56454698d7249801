#include "ogf/view/occupied_slots.hpp"

#include <algorithm>

namespace ogf::view {

void OccupiedSlots::mark(std::uint32_t i) {
  if (changed_flag_[i] != 0) return;
  changed_flag_[i] = 1;
  changed_.push_back(i);
}

void OccupiedSlots::set(const delta::PublishedCell& cell) {
  const bool occupied = cell.cell_class == ogf::map_delta_t::CLASS_OCCUPIED;
  auto it = index_.find(cell.key);
  if (!occupied) {
    if (it == index_.end()) return;
    const std::uint32_t i = it->second;
    slots_[i] = SlotCell{cell.key, kEmptySlot, 0.0f};
    free_.push_back(i);
    index_.erase(it);
    mark(i);
    return;
  }
  std::uint32_t i = 0;
  if (it != index_.end()) {
    i = it->second;
  } else if (!free_.empty()) {
    i = free_.back();
    free_.pop_back();
    index_.emplace(cell.key, i);
  } else {
    i = static_cast<std::uint32_t>(slots_.size());
    slots_.push_back({});
    changed_flag_.push_back(0);
    index_.emplace(cell.key, i);
  }
  slots_[i] = SlotCell{cell.key, static_cast<std::uint16_t>(std::max<std::int16_t>(cell.probability, 0)), cell.variance};
  mark(i);
}

void OccupiedSlots::reset(std::span<const delta::PublishedCell> cells) {
  slots_.clear();
  index_.clear();
  free_.clear();
  changed_flag_.clear();
  changed_.clear();
  for (const auto& c : cells) set(c);
  // A full frame carries every slot; nothing is pending on top of it.
  std::fill(changed_flag_.begin(), changed_flag_.end(), 0);
  changed_.clear();
  full_pending_ = true;
}

std::vector<std::uint32_t> OccupiedSlots::takeChanged() {
  std::vector<std::uint32_t> out;
  out.swap(changed_);
  for (std::uint32_t i : out) changed_flag_[i] = 0;
  std::sort(out.begin(), out.end());
  return out;
}

bool OccupiedSlots::takeFullPending() {
  const bool pending = full_pending_;
  full_pending_ = false;
  return pending;
}

std::vector<std::uint32_t> OccupiedSlots::filledSlots() const {
  std::vector<std::uint32_t> out;
  out.reserve(index_.size());
  for (std::uint32_t i = 0; i < slots_.size(); ++i)
    if (slots_[i].probability != kEmptySlot) out.push_back(i);
  return out;
}

}  // namespace ogf::view
