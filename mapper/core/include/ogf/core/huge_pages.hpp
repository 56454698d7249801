// Memory for large working buffers in 2 MB transparent huge pages, where the kernel gives them: a scan's
// buffers (the measurements, the dense box of marks, the map's blocks) are tens of MB written soon after
// they are taken, and each 4 KB page costs a fault on its first write: 14 µs on the README's 2-CPU virtual
// machine, against one fault per 2 MB with huge pages (about 0.3 µs per 4 KB when the kernel has a huge
// page free). With transparent huge pages off ("never") these are ordinary pages.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>

namespace ogf {

inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

// `bytes` (a multiple of 4 KB) of fresh zeroed memory starting at a multiple of 2 MB, advised for huge pages;
// throws std::bad_alloc. Give it back with unmapHugePages(pointer, bytes).
inline void* mapHugePages(std::size_t bytes) {
  void* raw = mmap(nullptr, bytes + kHugePageBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) throw std::bad_alloc();
  const auto start = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t aligned = (start + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
  const std::size_t lead = aligned - start;
  if (lead != 0) munmap(raw, lead);
  munmap(reinterpret_cast<void*>(aligned + bytes), kHugePageBytes - lead);
#ifdef MADV_HUGEPAGE
  madvise(reinterpret_cast<void*>(aligned), bytes, MADV_HUGEPAGE);
#endif
  return reinterpret_cast<void*>(aligned);
}

inline void unmapHugePages(void* memory, std::size_t bytes) { munmap(memory, bytes); }

// A std::vector allocator: arrays of 2 MB or more in huge pages (mapHugePages), smaller ones from
// std::allocator.
template <class T>
struct HugePageAllocator {
  using value_type = T;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>& /*other*/) {}  // NOLINT(google-explicit-constructor): rebinding

  T* allocate(std::size_t n) {
    if (n > SIZE_MAX / sizeof(T) - kHugePageBytes) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePageBytes) return std::allocator<T>().allocate(n);
    return static_cast<T*>(mapHugePages(roundUp(bytes)));
  }
  void deallocate(T* p, std::size_t n) noexcept {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePageBytes) {
      std::allocator<T>().deallocate(p, n);
    } else {
      unmapHugePages(p, roundUp(bytes));
    }
  }
  friend bool operator==(const HugePageAllocator&, const HugePageAllocator&) { return true; }

 private:
  static std::size_t roundUp(std::size_t bytes) { return (bytes + kHugePageBytes - 1) & ~(kHugePageBytes - 1); }
};

}  // namespace ogf
