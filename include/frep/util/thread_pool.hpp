// A small persistent thread pool for data-parallel loops: the threads are started once and
// reused, so a loop costs a wake-up rather than thread creation (renderers run several loops
// per frame, frames take milliseconds).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace frep {

class ThreadPool {
 public:
  // `threads` workers in all, the calling thread included; 0 = all hardware threads.
  explicit ThreadPool(int threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(threads_.size()) + 1; }

  // Calls body(worker, item) for every item in [0, items), items handed out one at a time to
  // whichever worker is free; `worker` in [0, size()) identifies per-worker scratch. The caller
  // works too and returns when all items are done. The first exception thrown by `body` stops
  // handing out items and is rethrown here. Not reentrant.
  void parallel_for(int items, const std::function<void(int worker, int item)>& body);

 private:
  void run_items(int worker);
  void worker_main(int worker);

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::uint64_t generation_ = 0;  // bumped for every loop
  int busy_ = 0;                  // workers still in the current loop
  bool stop_ = false;
  // The current loop.
  const std::function<void(int, int)>* body_ = nullptr;
  int items_ = 0;
  int next_ = 0;
  std::exception_ptr error_;
};

}  // namespace frep
