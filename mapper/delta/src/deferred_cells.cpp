#include "ogf/delta/deferred_cells.hpp"

namespace ogf::delta {

void DeferredCells::enqueue(const CellKey& key, Slot& slot) {
  // Cells that left or changed kind leave elements behind in the queues; past twice the waiting cells
  // the queues are rebuilt without them, so their memory follows the cells waiting, not the churn.
  if (class_queue_.size() + other_queue_.size() > 2 * cells_.size() + 4096) compact();
  slot.stamp = next_stamp_++;
  queueOf(slot.entry.worth).push_back({key, slot.stamp});
  class_changes_ += slot.entry.worth == Worth::kClass ? 1 : 0;
}

bool DeferredCells::waits(const CellKey& key) const {
  const CellKey slab = PublishedBlock::blockKeyOf(key);
  if (!asked_valid_ || !(slab == asked_slab_)) {
    asked_bits_ = waitingIn(slab);
    asked_slab_ = slab;
    asked_valid_ = true;
  }
  return (asked_bits_ >> PublishedBlock::localIndexOf(key) & 1U) != 0;
}

void DeferredCells::erase(const CellKey& key) {
  cells_.erase(key);
  const CellKey slab = PublishedBlock::blockKeyOf(key);
  std::uint64_t& bits = slabs_.obtain(slab);
  bits &= ~(std::uint64_t{1} << PublishedBlock::localIndexOf(key));
  if (bits == 0) slabs_.erase(slab);
  asked_valid_ = false;
}

bool DeferredCells::add(const Entry& entry) {
  if (full()) return false;
  slabs_.obtain(PublishedBlock::blockKeyOf(entry.cell.key)) |= std::uint64_t{1} << PublishedBlock::localIndexOf(entry.cell.key);
  asked_valid_ = false;
  Slot& slot = cells_.obtain(entry.cell.key);
  slot.entry = entry;
  enqueue(entry.cell.key, slot);
  return true;
}

bool DeferredCells::refresh(const PublishedCell& cell, Worth worth) {
  if (!waits(cell.key)) return false;
  Slot* found = cells_.find(cell.key);
  if (found == nullptr) return false;
  Slot& slot = *found;
  if (worth == Worth::kNothing) {
    // Back within the step of what clients hold: nothing to send. Its queue element is skipped later.
    forget(slot.entry.worth);
    erase(cell.key);
    return true;
  }
  slot.entry.cell = cell;
  if (worth != slot.entry.worth) {
    // Changed kind: it moves to the other queue, at its back.
    forget(slot.entry.worth);
    slot.entry.worth = worth;
    enqueue(cell.key, slot);
  }
  return true;
}

void DeferredCells::compact() {
  for (auto* queue : {&class_queue_, &other_queue_}) {
    std::deque<Queued> kept;
    for (const Queued& q : *queue) {
      const Slot* slot = cells_.find(q.key);
      if (slot != nullptr && slot->stamp == q.stamp) kept.push_back(q);
    }
    queue->swap(kept);
  }
}

void DeferredCells::clear() {
  cells_.clear();
  slabs_.clear();
  asked_valid_ = false;
  class_queue_.clear();
  other_queue_.clear();
  class_changes_ = 0;
}

}  // namespace ogf::delta
