// An allocator for big arrays (graphs, tapes, evaluator scratch): every block is aligned to 64
// bytes (SIMD loads), and blocks of 2 MiB and more are aligned to 2 MiB and marked for
// transparent huge pages. Random access into them then misses the
// TLB far less, and first touching them costs one page fault per 2 MiB instead of per 4 KiB
// (on big converted meshes, 4 KiB faults took a quarter of a render's time).
// Freed blocks of 2 MiB and more are cached (up to 1 GiB in all) and reused for later requests
// of at least half their size, so that memory freed and allocated again is not cleared again.
#pragma once

#include <cstddef>
#include <new>
#include <utility>
#include <vector>

namespace frep {

void* allocate_large(std::size_t bytes);
void deallocate_large(void* p, std::size_t bytes) noexcept;
// Frees the cached blocks (a long-running program may call it between jobs).
void release_cached_large_blocks() noexcept;

template <class T>
struct LargeAllocator {
  using value_type = T;
  LargeAllocator() = default;
  template <class U>
  LargeAllocator(const LargeAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_large(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { deallocate_large(p, n * sizeof(T)); }
  // Elements added without a value (resize) are default-initialized: numbers are left as they
  // are, so that scratch arrays are not written twice and pages never used are never touched.
  template <class U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <class U>
  bool operator==(const LargeAllocator<U>&) const { return true; }
};

template <class T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

}  // namespace frep
