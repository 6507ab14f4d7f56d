// An allocator for big arrays (graphs, tapes, evaluator scratch): every block is aligned to 64
// bytes (SIMD loads), and blocks of 2 MiB and more are aligned to 2 MiB and marked for
// transparent huge pages. Random access into them then misses the
// TLB far less, and first touching them costs one page fault per 2 MiB instead of per 4 KiB
// (on big converted meshes, 4 KiB faults took a quarter of a render's time).
#pragma once

#include <cstddef>
#include <vector>

namespace frep {

void* allocate_large(std::size_t bytes);
void deallocate_large(void* p, std::size_t bytes) noexcept;

template <class T>
struct LargeAllocator {
  using value_type = T;
  LargeAllocator() = default;
  template <class U>
  LargeAllocator(const LargeAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_large(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { deallocate_large(p, n * sizeof(T)); }
  template <class U>
  bool operator==(const LargeAllocator<U>&) const { return true; }
};

template <class T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

}  // namespace frep
