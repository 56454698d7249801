#include "ogf/view/occupied_slots.hpp"

#include <algorithm>
#include <unordered_set>

namespace ogf::view {
namespace {

// The box of f × f × f cells that holds cell k (keys divided by f, rounded down).
CellKey boxKey(const CellKey& k, std::int32_t f) {
  const auto down = [f](std::int32_t v) { return v >= 0 ? v / f : -((-v + f - 1) / f); };
  return {down(k.x), down(k.y), down(k.z)};
}

}  // namespace

void OccupiedSlots::mark(std::uint32_t i) {
  if (changed_flag_[i] != 0) return;
  changed_flag_[i] = 1;
  changed_.push_back(i);
}

CellKey OccupiedSlots::boxOf(const CellKey& k) const { return lod_ == 1 ? k : boxKey(k, lod_); }

void OccupiedSlots::set(const delta::PublishedCell& cell) {
  const bool occupied = cell.cell_class == ogf::map_delta_t::CLASS_OCCUPIED;
  const bool was = fine_.count(cell.key) != 0;
  if (occupied && !was) fine_.emplace(cell.key, 0);
  if (!occupied && was) fine_.erase(cell.key);
  const CellKey box = boxOf(cell.key);
  if (lod_ > 1 && occupied != was) {
    std::uint32_t& n = count_[box];
    n = occupied ? n + 1 : n - 1;
    if (n == 0) count_.erase(box);
  }
  auto it = index_.find(box);
  const bool drawn = lod_ == 1 ? occupied : count_.count(box) != 0;
  if (!drawn) {
    if (it == index_.end()) return;
    const std::uint32_t i = it->second;
    slots_[i] = SlotCell{box, kEmptySlot, 0.0f};
    free_.push_back(i);
    index_.erase(it);
    mark(i);
    return;
  }
  if (!occupied && it != index_.end()) return;  // the box stays for its other cells
  std::uint32_t i = 0;
  if (it != index_.end()) {
    i = it->second;
  } else if (!free_.empty()) {
    i = free_.back();
    free_.pop_back();
    index_.emplace(box, i);
  } else {
    i = static_cast<std::uint32_t>(slots_.size());
    slots_.push_back({});
    changed_flag_.push_back(0);
    index_.emplace(box, i);
  }
  slots_[i] = SlotCell{box, static_cast<std::uint16_t>(std::max<std::int16_t>(cell.probability, 0)), cell.variance};
  mark(i);
}

void OccupiedSlots::reset(std::span<const delta::PublishedCell> cells, std::int32_t lod) {
  lod_ = std::max(lod, 1);
  slots_.clear();
  index_.clear();
  fine_.clear();
  count_.clear();
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

std::int32_t chooseLod(std::span<const delta::PublishedCell> cells, std::size_t max_boxes) {
  constexpr std::int32_t kMaxLod = 64;
  for (std::int32_t f = 1; f < kMaxLod; f *= 2) {
    std::unordered_set<CellKey, CellKeyHash> boxes;
    for (const auto& c : cells) {
      if (c.cell_class != ogf::map_delta_t::CLASS_OCCUPIED) continue;
      boxes.insert(boxKey(c.key, f));
      if (boxes.size() > max_boxes) break;
    }
    if (boxes.size() <= max_boxes) return f;
  }
  return kMaxLod;
}

}  // namespace ogf::view
