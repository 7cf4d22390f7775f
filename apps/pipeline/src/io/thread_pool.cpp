#include "thread_pool.h"

#include <algorithm>
#include <memory>

namespace imuconv::pipeline {

ThreadPool::ThreadPool(unsigned threads) {
  if (threads == 0) threads = std::thread::hardware_concurrency();
  size_ = threads == 0 ? 1 : std::min(threads, kMaxThreads);
  threads_.reserve(size_ - 1);
  for (unsigned i = 1; i < size_; ++i) threads_.emplace_back([this] { worker(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(m_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& t : threads_) t.join();
}

void ThreadPool::worker() {
  std::size_t seen = 0;
  while (true) {
    const std::function<void()>* job = nullptr;
    {
      std::unique_lock<std::mutex> lock(m_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      job = job_;
    }
    (*job)();  // jobs catch their own exceptions
    std::lock_guard<std::mutex> lock(m_);
    if (--busy_ == 0) done_.notify_one();
  }
}

void ThreadPool::start_workers(const std::function<void()>& job) {
  {
    std::lock_guard<std::mutex> lock(m_);
    job_ = &job;
    busy_ = threads_.size();
    ++generation_;
  }
  wake_.notify_all();
}

void ThreadPool::wait_workers() {
  std::unique_lock<std::mutex> lock(m_);
  done_.wait(lock, [&] { return busy_ == 0; });
  job_ = nullptr;
}

void ThreadPool::ordered_for(std::size_t n, std::size_t window,
                             const std::function<void(std::size_t)>& produce,
                             const std::function<void(std::size_t)>& consume) {
  if (threads_.empty() || n <= 1) {
    for (std::size_t i = 0; i < n; ++i) {
      produce(i);
      consume(i);
    }
    return;
  }
  window = std::max<std::size_t>(window, 1);
  // Item states, in slot i % window (memory bounded by the window, not by n: item i starts
  // only after item i - window was consumed and its slot reset): 0 pending, 1 produced,
  // 2 failed (its exception in errors[i % window]).
  const std::size_t slots = std::min(window, n);
  std::unique_ptr<std::atomic<int>[]> slot_state(new std::atomic<int>[slots]);
  for (std::size_t i = 0; i < slots; ++i) slot_state[i].store(0, std::memory_order_relaxed);
  const auto state = [&](std::size_t i) -> std::atomic<int>& { return slot_state[i % window]; };
  std::vector<std::exception_ptr> errors(window);
  std::atomic<std::size_t> next{0};      // next item to claim
  std::atomic<std::size_t> consumed{0};  // items consumed
  std::atomic<bool> abort{false};
  std::mutex m;
  std::condition_variable produced_cv, consumed_cv;

  const auto run = [&](std::size_t i) {
    int s = 1;
    try {
      produce(i);
    } catch (...) {
      errors[i % window] = std::current_exception();
      s = 2;
    }
    {
      std::lock_guard<std::mutex> lock(m);
      state(i).store(s, std::memory_order_release);
    }
    produced_cv.notify_all();
  };
  const std::function<void()> worker_loop = [&] {
    while (!abort.load(std::memory_order_relaxed)) {
      const std::size_t i = next.fetch_add(1, std::memory_order_relaxed);
      if (i >= n) return;
      if (i >= consumed.load(std::memory_order_acquire) + window) {
        std::unique_lock<std::mutex> lock(m);
        consumed_cv.wait(lock, [&] { return abort.load() || i < consumed.load() + window; });
        if (abort.load()) return;
      }
      run(i);
    }
  };
  start_workers(worker_loop);
  std::exception_ptr failure;
  for (std::size_t j = 0; j < n && !failure; ++j) {
    // Help while item j is not there: claim an item only if it fits in the window (the
    // consumer must never wait for the window itself).
    while (state(j).load(std::memory_order_acquire) == 0) {
      std::size_t i = next.load(std::memory_order_relaxed);
      if (i < n && i < j + window &&
          next.compare_exchange_weak(i, i + 1, std::memory_order_relaxed)) {
        run(i);
        continue;
      }
      std::unique_lock<std::mutex> lock(m);
      produced_cv.wait(lock, [&] {
        if (state(j).load(std::memory_order_acquire) != 0) return true;
        const std::size_t k = next.load(std::memory_order_relaxed);
        return k < n && k < j + window;  // something to help with
      });
    }
    if (state(j).load(std::memory_order_acquire) == 2) {
      failure = errors[j % window];
      break;
    }
    try {
      consume(j);
    } catch (...) {
      failure = std::current_exception();
      break;
    }
    {
      std::lock_guard<std::mutex> lock(m);
      state(j).store(0, std::memory_order_relaxed);  // free for item j + window
      consumed.store(j + 1, std::memory_order_release);
    }
    consumed_cv.notify_all();
  }
  if (failure) {
    {
      std::lock_guard<std::mutex> lock(m);
      abort.store(true);
    }
    consumed_cv.notify_all();
  }
  wait_workers();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace imuconv::pipeline
