// Block slots in chunks: small populated ones first, then huge pages.
#include "ogf/filter/block_arena.hpp"

#include <ogf/core/huge_pages.hpp>

#include <sys/mman.h>

#include <algorithm>
#include <new>

#if defined(__SANITIZE_ADDRESS__)
#define OGF_ARENA_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define OGF_ARENA_ASAN 1
#endif
#endif
#ifdef OGF_ARENA_ASAN
#include <sanitizer/asan_interface.h>
#endif

namespace ogf::filter {

namespace {
// Marks memory unusable (poison) or usable again for AddressSanitizer; nothing in other builds.
#ifdef OGF_ARENA_ASAN
void poison(void* p, std::size_t bytes) { __asan_poison_memory_region(p, bytes); }
void unpoison(void* p, std::size_t bytes) { __asan_unpoison_memory_region(p, bytes); }
#else
void poison(void*, std::size_t) {}
void unpoison(void*, std::size_t) {}
#endif

constexpr std::size_t kCacheLine = 64;
// Chunks of at most 256 KB up to 8 MB; after that a huge page's unused slots are under a fifth of the map.
constexpr std::size_t kSmallChunk = std::size_t{256} << 10;
constexpr std::size_t kSmallChunksUpTo = std::size_t{8} << 20;
}  // namespace

BlockArena::BlockArena(std::size_t slotBytes)
    : slot_bytes_((std::max<std::size_t>(slotBytes, 1) + kCacheLine - 1) / kCacheLine * kCacheLine) {}

BlockArena::~BlockArena() {
  for (const Chunk& c : chunks_) {
    unpoison(c.base, c.bytes);  // the addresses may be mapped again by anyone
    munmap(c.base, c.bytes);
  }
}

void* BlockArena::allocate() {
  if (free_ != nullptr) {
    void* slot = free_;
    unpoison(slot, slot_bytes_);
    free_ = *static_cast<void**>(slot);
    return slot;
  }
  if (static_cast<std::size_t>(end_ - next_) < slot_bytes_) addChunk();
  void* slot = next_;
  next_ += slot_bytes_;
  unpoison(slot, slot_bytes_);
  return slot;
}

void BlockArena::release(void* slot) noexcept {
  *static_cast<void**>(slot) = free_;
  free_ = slot;
  poison(slot, slot_bytes_);
}

void BlockArena::addChunk() {
  void* base = nullptr;
  std::size_t bytes = 0;
  if (mapped_bytes_ >= kSmallChunksUpTo && slot_bytes_ <= kHugePageBytes) {
    // A 2 MB page where the kernel has one to give (transparent huge pages, "madvise" or "always"): one
    // fault and one TLB entry instead of 512 of each.
    bytes = kHugePageBytes;
    base = mapHugePages(bytes);
  } else {
    // A quarter of what is mapped, in whole pages: a small map keeps few unused slots.
    constexpr std::size_t kPage = 4096;
    bytes = std::clamp(mapped_bytes_ / 4, slot_bytes_, std::max(kSmallChunk, slot_bytes_));
    bytes = (bytes + kPage - 1) / kPage * kPage;
    base = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (base == MAP_FAILED) throw std::bad_alloc();
#ifdef MADV_POPULATE_WRITE
    // Best effort: a kernel without it (before Linux 5.14) faults the pages in as they are written.
    madvise(base, bytes, MADV_POPULATE_WRITE);
#endif
  }
  try {
    chunks_.push_back({base, bytes});
  } catch (...) {
    munmap(base, bytes);
    throw;
  }
  mapped_bytes_ += bytes;
  poison(base, bytes);
  next_ = static_cast<char*>(base);
  end_ = next_ + bytes;
}

}  // namespace ogf::filter
