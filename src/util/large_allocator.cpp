// Big arrays on transparent huge pages (frep/util/large_allocator.hpp).
#include "frep/util/large_allocator.hpp"

#include <sys/mman.h>

#include <cstdlib>
#include <new>

namespace frep {
namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
}  // namespace

void* allocate_large(std::size_t bytes) {
  if (bytes < kHugePage) {
    // Cache-line aligned, so that SIMD code may use aligned loads on any of these arrays.
    void* p = std::aligned_alloc(64, (bytes + 63) / 64 * 64 + (bytes == 0) * 64);
    if (!p) throw std::bad_alloc();
    return p;
  }
  const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  void* p = std::aligned_alloc(kHugePage, rounded);
  if (!p) throw std::bad_alloc();
  ::madvise(p, rounded, MADV_HUGEPAGE);  // a hint: failure only costs speed
  return p;
}

void deallocate_large(void* p, std::size_t) noexcept { std::free(p); }

}  // namespace frep
