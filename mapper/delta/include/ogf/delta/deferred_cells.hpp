// The cells worth sending (publishing_rule.hpp) that a delta update's byte allowance left out: they wait
// here, one entry per cell holding its latest state (a newer change of a waiting cell replaces its state
// and keeps its place), and go out in later updates, class changes first, each kind oldest first. The set
// holds at most its capacity: past it a change is not kept (DeltaStream marks its slab stale instead,
// stale_slabs.hpp), so the memory and the time of a scan's look-ups stay bounded however far the map's
// changes outrun the budget.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>

#include "ogf/core/cell_key.hpp"
#include "ogf/core/cell_key_table.hpp"
#include "ogf/delta/published_block.hpp"
#include "ogf/delta/publishing_rule.hpp"

namespace ogf::delta {

class DeferredCells {
 public:
  struct Entry {
    PublishedCell cell;
    Worth worth = Worth::kProbability;
    // Whether the published map held the cell when it was deferred; a held cell that is no longer in
    // memory has left with its region (PublishedMap::evict) and is not sent (DeltaStream::update).
    bool was_published = false;
  };

  bool empty() const { return cells_.size() == 0; }
  std::size_t size() const { return cells_.size(); }
  // The most cells waiting at once (unbounded unless set); lowering it keeps the cells already waiting.
  void setCapacity(std::size_t cells) { capacity_ = cells; }
  std::size_t capacity() const { return capacity_; }
  bool full() const { return cells_.size() >= capacity_; }
  // How many more cells may wait.
  std::size_t room() const { return full() ? 0 : capacity_ - cells_.size(); }
  // Waiting cells whose class differs from the published one.
  std::size_t classChanges() const { return class_changes_; }

  // Whether the cell waits (refresh() asks this before it looks the cell up).
  bool waits(const CellKey& key) const;
  // Which cells of a slab (PublishedBlock::blockKeyOf) wait, a bit per PublishedBlock::localIndexOf.
  std::uint64_t waitingIn(const CellKey& slab) const {
    const std::uint64_t* bits = slabs_.find(slab);
    return bits == nullptr ? 0 : *bits;
  }
  // Queues a cell not waiting yet (entry.worth is kClass or kProbability); false, and nothing kept, when
  // the set is full.
  bool add(const Entry& entry);
  // A newer state of `cell`, judged `worth` against the published cell: when the cell waits, its state
  // and worth are replaced (kNothing: it leaves) and true is returned; false when it does not wait.
  bool refresh(const PublishedCell& cell, Worth worth);
  // Removes up to `max` waiting cells of that worth, oldest first, into `out` (appended).
  template <class Out>
  std::size_t take(Worth worth, std::size_t max, Out& out);
  void clear();

 private:
  struct Slot {
    Entry entry;
    std::uint64_t stamp = 0;  // which queue element stands for the entry; older elements are skipped
  };
  struct Queued {
    CellKey key;
    std::uint64_t stamp = 0;
  };
  std::deque<Queued>& queueOf(Worth worth) { return worth == Worth::kClass ? class_queue_ : other_queue_; }
  void enqueue(const CellKey& key, Slot& slot);
  void compact();
  void forget(Worth worth) { class_changes_ -= worth == Worth::kClass ? 1 : 0; }
  void erase(const CellKey& key);

  // Which cells of each slab (PublishedBlock's 8 × 8 × 1) wait, a bit each: most of a scan's candidates do
  // not wait, and a scan's candidates come slab by slab, so one look-up in this small table (a few slabs'
  // entries per thousand waiting cells) answers for a run of them where the cells' table would take a
  // cache miss per candidate.
  CellKeyTable<std::uint64_t, 1, 2> slabs_;
  // The slab asked last and its bits (valid until a bit changes).
  mutable CellKey asked_slab_{};
  mutable std::uint64_t asked_bits_ = 0;
  mutable bool asked_valid_ = false;

  // Open addressing (one slot a look-up, no node per cell): a street drive at 0.1 m over a small budget
  // keeps millions of cells waiting, and every candidate of a scan is looked up.
  CellKeyTable<Slot, 1, 2> cells_;
  std::deque<Queued> class_queue_;
  std::deque<Queued> other_queue_;
  std::uint64_t next_stamp_ = 1;  // 0: a slot not queued yet
  std::size_t class_changes_ = 0;
  std::size_t capacity_ = std::numeric_limits<std::size_t>::max();
};

template <class Out>
std::size_t DeferredCells::take(Worth worth, std::size_t max, Out& out) {
  std::deque<Queued>& queue = queueOf(worth);
  std::size_t taken = 0;
  while (taken < max && !queue.empty()) {
    const Queued q = queue.front();
    queue.pop_front();
    const Slot* slot = cells_.find(q.key);
    if (slot == nullptr || slot->stamp != q.stamp) continue;  // left, or queued again since
    out.push_back(slot->entry);
    forget(slot->entry.worth);
    erase(q.key);
    ++taken;
  }
  return taken;
}

}  // namespace ogf::delta
