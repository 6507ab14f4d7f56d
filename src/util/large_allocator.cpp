// Big arrays on transparent huge pages (frep/util/large_allocator.hpp).
#include "frep/util/large_allocator.hpp"

#include <sys/mman.h>

#include <cstdlib>
#include <mutex>
#include <new>
#include <unordered_map>
#include <vector>

namespace frep {
namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;

// Freed huge blocks kept for reuse, up to this many bytes in all. Fresh memory costs the kernel
// a page clear per 2 MiB on first touch; the subdivision driver frees and allocates tapes of
// millions of instructions all the time (a 1024 px render of a converted mesh spent a third of
// its time clearing pages before this cache).
constexpr std::size_t kCacheLimit = std::size_t(1) << 30;

// A block is reused for a request of at least half its size, so that a cached block never
// holds more than twice what it serves.
struct Cache {
  std::mutex m;
  std::unordered_map<void*, std::size_t> sizes;      // huge blocks in use: their real size
  std::vector<std::pair<void*, std::size_t>> free;  // cached blocks and their sizes
  std::size_t free_bytes = 0;                       // their total size
};
Cache& cache() {
  static Cache* c = new Cache;  // never destroyed: blocks may be freed during static destruction
  return *c;
}
}  // namespace

void* allocate_large(std::size_t bytes) {
  if (bytes < kHugePage) {
    // Cache-line aligned, so that SIMD code may use aligned loads on any of these arrays.
    void* p = std::aligned_alloc(64, (bytes + 63) / 64 * 64 + (bytes == 0) * 64);
    if (!p) throw std::bad_alloc();
    return p;
  }
  const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  Cache& c = cache();
  {
    std::lock_guard<std::mutex> lock(c.m);
    std::size_t best = c.free.size();
    for (std::size_t i = 0; i < c.free.size(); ++i)
      if (c.free[i].second >= rounded && c.free[i].second <= 2 * rounded &&
          (best == c.free.size() || c.free[i].second < c.free[best].second))
        best = i;
    if (best < c.free.size()) {
      auto [p, size] = c.free[best];
      c.free[best] = c.free.back();
      c.free.pop_back();
      c.free_bytes -= size;
      c.sizes[p] = size;
      return p;
    }
  }
  void* p = std::aligned_alloc(kHugePage, rounded);
  if (!p) throw std::bad_alloc();
  ::madvise(p, rounded, MADV_HUGEPAGE);  // a hint: failure only costs speed
  std::lock_guard<std::mutex> lock(c.m);
  c.sizes[p] = rounded;
  return p;
}

void deallocate_large(void* p, std::size_t bytes) noexcept {
  if (!p) return;
  if (bytes < kHugePage) return std::free(p);
  Cache& c = cache();
  std::size_t size = 0;  // 0: not one of ours (cannot happen), freed at once
  {
    std::lock_guard<std::mutex> lock(c.m);
    const auto it = c.sizes.find(p);
    if (it != c.sizes.end()) {
      size = it->second;
      c.sizes.erase(it);
    }
    if (size > 0 && c.free_bytes + size <= kCacheLimit) {
      try {
        c.free.emplace_back(p, size);
        c.free_bytes += size;
        return;
      } catch (...) {  // no room to list it: free it instead
      }
    }
  }
  std::free(p);
}

void release_cached_large_blocks() noexcept {
  Cache& c = cache();
  std::lock_guard<std::mutex> lock(c.m);
  for (auto& [p, size] : c.free) std::free(p);
  c.free.clear();
  c.free_bytes = 0;
}

}  // namespace frep
