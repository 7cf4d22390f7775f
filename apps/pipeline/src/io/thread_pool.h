// A small fixed thread pool for independent work items (internal to imuconv_pipeline).
//
// ordered_for(n, window, produce, consume) calls produce(i) on the pool and consume(i) on the
// calling thread in index order, as soon as item i is produced, with at most `window` items
// produced ahead of consumption (so that their results stay small).
//
// Results must go to slots owned by i (produce writes nothing shared), so that the outcome
// does not depend on which thread ran which item. When items throw, the exception of the
// lowest failing index is rethrown (items after it may be skipped): the same error a serial
// loop would have stopped at. With one thread, items run in order on the caller and the
// first exception propagates at once.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace imuconv::pipeline {

class ThreadPool {
 public:
  /// More are not started (a request for more gets this many).
  static constexpr unsigned kMaxThreads = 256;
  /// `threads` workers in all, the caller included; 0 = std::thread::hardware_concurrency().
  explicit ThreadPool(unsigned threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  unsigned size() const noexcept { return size_; }

  /// produce(i) for every i on the pool (the caller helps while it waits), consume(i) on the
  /// caller in order 0, 1, ..., each once its item is produced; item i is not started before
  /// item i - window is consumed. An exception from produce(i) is rethrown when i's turn to
  /// be consumed comes (so the lowest failing index wins); one from consume(i) at once. No
  /// barrier between items: a thread that is descheduled holds up at most its own item.
  void ordered_for(std::size_t n, std::size_t window,
                   const std::function<void(std::size_t)>& produce,
                   const std::function<void(std::size_t)>& consume);

 private:
  void worker();
  /// Runs job() once on every worker thread; returns at once (join with wait_workers()).
  void start_workers(const std::function<void()>& job);
  void wait_workers();

  unsigned size_ = 1;
  std::vector<std::thread> threads_;
  std::mutex m_;
  std::condition_variable wake_, done_;
  bool stop_ = false;
  std::size_t generation_ = 0;  // bumped per job
  std::size_t busy_ = 0;        // workers still on the current job
  const std::function<void()>* job_ = nullptr;
};

}  // namespace imuconv::pipeline
