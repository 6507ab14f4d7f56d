// The one way frep runs work in parallel: a small persistent thread pool with a parallel-for
// over items or ranges. Threads are started once and reused, so a loop costs a wake-up rather
// than thread creation (renderers and meshers run many loops, some of them milliseconds long).
// Thread counts are `int` everywhere in frep; 0 means all hardware threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace frep {

// The number of threads `threads` asks for: itself if positive, else the hardware's (at least 1).
int resolve_thread_count(int threads);

class ThreadPool {
 public:
  // `threads` workers in all, the calling thread included; 0 = all hardware threads. If the
  // system cannot start that many threads, the pool works with the ones it could start.
  explicit ThreadPool(int threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(threads_.size()) + 1; }

  // Calls body(worker, item) for every item in [0, items), items handed out one at a time to
  // whichever worker is free; `worker` in [0, size()) identifies per-worker scratch. The caller
  // works too and returns when all items are done. The first exception thrown by `body` stops
  // handing out items and is rethrown here once every worker has left the loop. Not reentrant:
  // `body` must not start another loop on the same pool.
  void parallel_for(int items, const std::function<void(int worker, int item)>& body);

  // Calls body(worker, begin, end) for consecutive ranges of at most `grain` items that together
  // cover [0, n) exactly once. Which worker gets which range varies; the ranges do not.
  template <class F>
  void parallel_for_ranges(std::size_t n, std::size_t grain, F&& body) {
    grain = std::max<std::size_t>(grain, 1);
    const std::size_t chunks = (n + grain - 1) / grain;
    if (chunks == 0) return;
    if (chunks == 1) return body(0, std::size_t(0), n);
    parallel_for(static_cast<int>(chunks), [&](int worker, int c) {
      const std::size_t b = static_cast<std::size_t>(c) * grain;
      body(worker, b, std::min(n, b + grain));
    });
  }

 private:
  void run_items(int worker);
  void worker_main(int worker);

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  // Written under mutex_; read without it too by the short spins before a worker or the caller
  // blocks (a loop of one job usually follows the last within microseconds, and a futex
  // wake-up costs tens of them).
  std::atomic<std::uint64_t> generation_{0};  // bumped for every loop
  std::atomic<int> busy_{0};                  // workers still in the current loop
  std::atomic<bool> stop_{false};
  // The current loop.
  const std::function<void(int, int)>* body_ = nullptr;
  int items_ = 0;
  int next_ = 0;
  std::exception_ptr error_;
};

// One-shot: the same over a pool of `threads` made for this call (none when one range or one
// thread suffices). Prefer a reusable ThreadPool where loops repeat.
template <class F>
void parallel_for_ranges(int threads, std::size_t n, std::size_t grain, F&& body) {
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t chunks = (n + grain - 1) / grain;
  const int t = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(resolve_thread_count(threads)), chunks));
  if (t <= 1) {
    for (std::size_t b = 0; b < n; b += grain) body(0, b, std::min(n, b + grain));
    return;
  }
  ThreadPool pool(t);
  pool.parallel_for_ranges(n, grain, body);
}

}  // namespace frep
