// Memory for the values of blocks (block_storage.hpp), carved from 2 MiB slabs aligned to 2 MiB.
//
// Why: a measurement's stencil reaches up to 8 blocks, and a large map has thousands, each 28 KiB at the
// default stencil, so with 4 KiB pages nearly every block a measurement touches costs a TLB miss (a page
// walk, dearer still under a hypervisor). Once a slab is full it is collapsed into one transparent huge page
// (Linux' MADV_COLLAPSE), so a large map's blocks sit on few pages: the update on a 400-block map took about
// 0.85 of the time (README, seventh session). A slab that is still filling is left on small pages, of which
// only the touched ones are resident, so a small map costs no more than its blocks. Where the kernel cannot
// collapse (no THP, an older kernel), slabs stay on small pages and nothing else changes.
//
// Blocks are never freed one by one (a map only grows); the arena frees its slabs when it is destroyed.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace ogf::filter {

class BlockArena {
 public:
  static constexpr std::size_t kSlabBytes = std::size_t{2} << 20;

  explicit BlockArena(std::size_t floatsPerBlock);
  ~BlockArena();
  BlockArena(BlockArena&& other) noexcept;
  BlockArena& operator=(BlockArena&& other) noexcept;
  BlockArena(const BlockArena&) = delete;
  BlockArena& operator=(const BlockArena&) = delete;

  // Room for one block, uninitialised, 64-byte aligned; valid until the arena is destroyed.
  float* allocate();

  // Bytes the blocks handed out occupy: every full slab whole (its tail is resident once collapsed), the
  // filling slab up to its last block, and blocks too large for a slab on their own.
  std::size_t bytesInUse() const;

 private:
  struct Slab {
    void* base = nullptr;
    std::size_t blocks = 0;  // handed out from it
  };
  void release() noexcept;

  std::size_t blockBytes_;
  std::size_t blocksPerSlab_;  // 0: blocks are larger than a slab and allocated on their own
  std::vector<Slab> slabs_;
  std::vector<std::unique_ptr<float[]>> large_;
};

}  // namespace ogf::filter
