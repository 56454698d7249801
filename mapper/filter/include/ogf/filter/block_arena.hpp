// Fixed-size slots for the blocks' values, carved from chunks of memory, with the slots of erased blocks
// reused first. The first 8 MB come in chunks of 256 KB, their pages made present in one call
// (MADV_POPULATE_WRITE); after that a chunk is one 2 MB transparent huge page where the kernel gives one.
//
// A map's memory is mostly its blocks, and a block's first write costs a page fault per 4 KB (huge_pages.hpp;
// 8 µs a page populated in one call on the README's VM, against 14 µs faulted one by one). A first 0.1 m
// street scan allocates about 19 k blocks (68 MB). Huge pages also spare the updates TLB misses: a scan's
// blocks are spread over tens of MB. No allocator header per block either.
//
// Under AddressSanitizer the slots not handed out (released, or not yet carved) are poisoned, so a block
// that writes past its slot or after its release is caught as with malloc.
#pragma once

#include <cstddef>
#include <vector>

namespace ogf::filter {

class BlockArena {
 public:
  // Slots of `slotBytes`, rounded up to a cache line.
  explicit BlockArena(std::size_t slotBytes);
  ~BlockArena();
  BlockArena(const BlockArena&) = delete;
  BlockArena& operator=(const BlockArena&) = delete;

  // A slot, uninitialised and aligned to a cache line; throws std::bad_alloc when memory is exhausted.
  void* allocate();
  // Returns a slot from allocate() for reuse (it holds the link of the free list until then).
  void release(void* slot) noexcept;

  std::size_t slotBytes() const { return slot_bytes_; }
  // Bytes mapped for slots, in use or not.
  std::size_t mappedBytes() const { return mapped_bytes_; }

 private:
  struct Chunk {
    void* base = nullptr;
    std::size_t bytes = 0;
  };
  void addChunk();

  std::size_t slot_bytes_;
  std::size_t mapped_bytes_ = 0;
  std::vector<Chunk> chunks_;
  char* next_ = nullptr;  // the unused rest of the last chunk
  char* end_ = nullptr;
  void* free_ = nullptr;  // the last released slot; each holds the one released before it
};

}  // namespace ogf::filter
