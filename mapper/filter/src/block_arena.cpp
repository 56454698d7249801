// Slabs for block values: 2 MiB aligned mappings, collapsed into a huge page once full.
#include "ogf/filter/block_arena.hpp"

#include <sys/mman.h>

#include <cstdint>
#include <memory>
#include <new>
#include <utility>

namespace ogf::filter {

namespace {

constexpr std::size_t kAlignment = 64;  // a cache line

// An anonymous mapping of kSlabBytes at an address that is a multiple of kSlabBytes: twice the size mapped,
// the misaligned head and the tail unmapped.
void* mapSlab() {
  constexpr std::size_t size = BlockArena::kSlabBytes;
  void* p = mmap(nullptr, 2 * size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) {
    throw std::bad_alloc();
  }
  const auto start = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t aligned = (start + size - 1) & ~std::uintptr_t{size - 1};
  if (aligned > start) {
    munmap(p, aligned - start);
  }
  const std::uintptr_t end = start + 2 * size;
  if (end > aligned + size) {
    munmap(reinterpret_cast<void*>(aligned + size), end - (aligned + size));
  }
  return reinterpret_cast<void*>(aligned);
}

// Asks the kernel to back a full slab with one huge page now. Best effort: without transparent huge pages
// or before Linux 6.1 the call fails and the slab stays on small pages.
void collapse(void* slab) {
#if defined(__linux__)
#ifdef MADV_COLLAPSE
  constexpr int kCollapse = MADV_COLLAPSE;
#else
  constexpr int kCollapse = 25;  // Linux 6.1 uapi value; glibc 2.36 headers predate it
#endif
  static_cast<void>(madvise(slab, BlockArena::kSlabBytes, kCollapse));
#else
  static_cast<void>(slab);
#endif
}

}  // namespace

BlockArena::BlockArena(std::size_t floatsPerBlock)
    : blockBytes_((floatsPerBlock * sizeof(float) + kAlignment - 1) / kAlignment * kAlignment),
      blocksPerSlab_(kSlabBytes / blockBytes_) {}

BlockArena::~BlockArena() { release(); }

BlockArena::BlockArena(BlockArena&& other) noexcept
    : blockBytes_(other.blockBytes_),
      blocksPerSlab_(other.blocksPerSlab_),
      slabs_(std::move(other.slabs_)),
      large_(std::move(other.large_)) {
  other.slabs_.clear();
}

BlockArena& BlockArena::operator=(BlockArena&& other) noexcept {
  if (this != &other) {
    release();
    blockBytes_ = other.blockBytes_;
    blocksPerSlab_ = other.blocksPerSlab_;
    slabs_ = std::move(other.slabs_);
    large_ = std::move(other.large_);
    other.slabs_.clear();
  }
  return *this;
}

void BlockArena::release() noexcept {
  for (const Slab& slab : slabs_) {
    munmap(slab.base, kSlabBytes);
  }
  slabs_.clear();
}

float* BlockArena::allocate() {
  if (blocksPerSlab_ == 0) {
    large_.push_back(std::make_unique_for_overwrite<float[]>(blockBytes_ / sizeof(float)));
    return large_.back().get();
  }
  if (slabs_.empty() || slabs_.back().blocks == blocksPerSlab_) {
    if (slabs_.size() == slabs_.capacity()) {
      slabs_.reserve(2 * slabs_.size() + 1);  // so that the push below cannot throw with the mapping made
    }
    if (!slabs_.empty()) {
      collapse(slabs_.back().base);  // full, and every block in it written by now
    }
    slabs_.push_back({mapSlab(), 0});
  }
  Slab& slab = slabs_.back();
  return reinterpret_cast<float*>(static_cast<char*>(slab.base) + blockBytes_ * slab.blocks++);
}

std::size_t BlockArena::bytesInUse() const {
  std::size_t bytes = large_.size() * blockBytes_;
  for (const Slab& slab : slabs_) {
    bytes += slab.blocks == blocksPerSlab_ ? kSlabBytes : slab.blocks * blockBytes_;
  }
  return bytes;
}

}  // namespace ogf::filter
