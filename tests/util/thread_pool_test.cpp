#include "frep/util/thread_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace frep {
namespace {

TEST(ThreadPool, EveryItemRunsExactlyOnceAcrossManyLoops) {
  for (int threads : {1, 2, 3, 8}) {
    ThreadPool pool(threads);
    EXPECT_EQ(pool.size(), threads);
    for (int loop = 0; loop < 200; ++loop) {
      const int items = loop % 7 == 0 ? 1 : loop % 50;
      std::vector<std::atomic<int>> hits(static_cast<std::size_t>(items));
      std::atomic<int> bad_worker{0};
      pool.parallel_for(items, [&](int worker, int item) {
        if (worker < 0 || worker >= pool.size()) ++bad_worker;
        ++hits[static_cast<std::size_t>(item)];
      });
      for (auto& h : hits) ASSERT_EQ(h.load(), 1) << "threads " << threads << " loop " << loop;
      ASSERT_EQ(bad_worker.load(), 0);
    }
  }
}

TEST(ThreadPool, FirstExceptionIsRethrownAndThePoolStaysUsable) {
  ThreadPool pool(3);
  EXPECT_THROW(pool.parallel_for(100,
                                 [](int, int item) {
                                   if (item == 17) throw std::runtime_error("boom");
                                 }),
               std::runtime_error);
  std::atomic<int> count{0};
  pool.parallel_for(10, [&](int, int) { ++count; });
  EXPECT_EQ(count.load(), 10);
}

}  // namespace
}  // namespace frep
