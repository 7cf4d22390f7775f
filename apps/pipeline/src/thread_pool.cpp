#include "thread_pool.h"

#include <algorithm>

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

void ThreadPool::work_on_current_job() {
  while (true) {
    const std::size_t i = next_.fetch_add(1, std::memory_order_relaxed);
    if (i >= n_) return;
    if (i > first_failure_.load(std::memory_order_relaxed)) continue;  // a serial loop stops earlier
    try {
      (*f_)(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(m_);
      if (i < first_failure_.load(std::memory_order_relaxed)) {
        first_failure_.store(i, std::memory_order_relaxed);
        error_ = std::current_exception();
      }
    }
  }
}

void ThreadPool::worker() {
  std::size_t seen = 0;
  while (true) {
    {
      std::unique_lock<std::mutex> lock(m_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    work_on_current_job();
    std::lock_guard<std::mutex> lock(m_);
    if (--busy_ == 0) done_.notify_one();
  }
}

void ThreadPool::parallel_for(std::size_t n, const std::function<void(std::size_t)>& f,
                              const std::function<void()>& meanwhile) {
  if (threads_.empty() || n <= 1) {
    if (meanwhile) meanwhile();
    for (std::size_t i = 0; i < n; ++i) f(i);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(m_);
    f_ = &f;
    n_ = n;
    next_.store(0);
    first_failure_.store(n);
    error_ = nullptr;
    busy_ = threads_.size();
    ++generation_;
  }
  wake_.notify_all();
  std::exception_ptr own;
  if (meanwhile) {
    try {
      meanwhile();
    } catch (...) {
      own = std::current_exception();
      first_failure_.store(0);  // the items are not needed any more
    }
  }
  work_on_current_job();
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(m_);
    done_.wait(lock, [&] { return busy_ == 0; });
    f_ = nullptr;
    error = error_;
    error_ = nullptr;
  }
  if (own) std::rethrow_exception(own);
  if (error) std::rethrow_exception(error);
}

}  // namespace imuconv::pipeline
