#include "frep/util/thread_pool.hpp"

#include <algorithm>
#include <system_error>

namespace frep {

int resolve_thread_count(int threads) {
  return threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

ThreadPool::ThreadPool(int threads) {
  const int n = resolve_thread_count(threads);
  threads_.reserve(static_cast<std::size_t>(n - 1));
  try {
    for (int i = 1; i < n; ++i) threads_.emplace_back([this, i] { worker_main(i); });
  } catch (const std::system_error&) {
    // Out of threads: work with those that started (the caller always works too).
  }
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& t : threads_) t.join();
}

void ThreadPool::run_items(int worker) {
  while (true) {
    int item;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (error_ || next_ >= items_) return;
      item = next_++;
    }
    try {
      (*body_)(worker, item);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      return;
    }
  }
}

void ThreadPool::worker_main(int worker) {
  std::uint64_t seen = 0;
  while (true) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    run_items(worker);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (--busy_ == 0) done_.notify_one();
    }
  }
}

void ThreadPool::parallel_for(int items, const std::function<void(int, int)>& body) {
  if (items <= 0) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    body_ = &body;
    items_ = items;
    next_ = 0;
    error_ = nullptr;
    busy_ = static_cast<int>(threads_.size());
    ++generation_;
  }
  if (!threads_.empty() && items > 1) wake_.notify_all();
  run_items(0);
  {
    std::unique_lock<std::mutex> lock(mutex_);
    // Workers that were not woken (a single item) still count themselves out when they see the
    // new generation, so always wait for all of them: the loop state must outlive their reads.
    if (items <= 1 && !threads_.empty()) wake_.notify_all();
    done_.wait(lock, [&] { return busy_ == 0; });
    body_ = nullptr;
  }
  if (error_) std::rethrow_exception(error_);
}

}  // namespace frep
