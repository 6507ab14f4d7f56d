// LargeAllocator: alignment, values kept by explicit construction, and the cache of freed huge
// blocks (a block freed is reused for a request of at least half its size, not for less).
#include <gtest/gtest.h>

#include <cstdint>

#include "frep/util/large_allocator.hpp"

namespace frep {
namespace {

TEST(LargeAllocator, AlignsAndConstructsGivenValues) {
  LargeVector<std::uint32_t> small(100, 7u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % 64, 0u);
  for (std::uint32_t v : small) EXPECT_EQ(v, 7u);
  LargeVector<std::uint64_t> big(std::size_t{3} << 20, 9u);  // 24 MiB: huge pages
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.data()) % (std::size_t{2} << 20), 0u);
  EXPECT_EQ(big.front(), 9u);
  EXPECT_EQ(big.back(), 9u);
}

TEST(LargeAllocator, ReusesFreedHugeBlocksOfTheRightSize) {
  // Sizes no other test uses, so that the cache holds no other candidate. Untouched: only the
  // addresses are compared (resize leaves numbers uninitialized, so no page is written).
  constexpr std::size_t kMiB = std::size_t{1} << 20;
  release_cached_large_blocks();  // room in the cache, whatever earlier tests left there
  void* first = nullptr;
  {
    LargeVector<char> a;
    a.resize(300 * kMiB);
    first = a.data();
  }
  {
    LargeVector<char> b;
    b.resize(200 * kMiB);  // at least half of 300 MiB: the cached block
    EXPECT_EQ(static_cast<void*>(b.data()), first);
  }
  {
    LargeVector<char> c;
    c.resize(100 * kMiB);  // less than half: a block of its own
    EXPECT_NE(static_cast<void*>(c.data()), first);
  }
}

}  // namespace
}  // namespace frep
