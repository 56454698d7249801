// The cells worth sending (publishing_rule.hpp) that a delta update's byte allowance left out: they wait
// here, one entry per cell holding its latest state (a newer change of a waiting cell replaces its state
// and keeps its place), and go out in later updates, class changes first, each kind oldest first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>

#include "ogf/core/cell_key.hpp"
#include "ogf/core/cell_key_table.hpp"
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
  // Waiting cells whose class differs from the published one.
  std::size_t classChanges() const { return class_changes_; }

  // A hint that the cell is looked up soon (DeltaStream::update asks a few candidates ahead).
  void prefetch(const CellKey& key) const { cells_.prefetch(key); }
  // Queues a cell not waiting yet (entry.worth is kClass or kProbability).
  void add(const Entry& entry);
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

  // Open addressing (one slot a look-up, no node per cell): a street drive at 0.1 m over a small budget
  // keeps millions of cells waiting, and every candidate of a scan is looked up.
  CellKeyTable<Slot, 1, 2> cells_;
  std::deque<Queued> class_queue_;
  std::deque<Queued> other_queue_;
  std::uint64_t next_stamp_ = 1;  // 0: a slot not queued yet
  std::size_t class_changes_ = 0;
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
    cells_.erase(q.key);
    ++taken;
  }
  return taken;
}

}  // namespace ogf::delta
