// A small fixed thread pool for independent work items (internal to imuconv_pipeline).
//
// parallel_for(n, f) calls f(i) once for every i in [0, n); the calling thread takes part.
// Results must go to slots owned by i (f(i) writes nothing shared), so that the outcome does
// not depend on which thread ran which item. When items throw, the exception of the lowest
// failing index is rethrown (items after it may be skipped): the same error a serial loop
// would have stopped at. With one thread, items run in order on the caller and the first
// exception propagates at once.
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
  void parallel_for(std::size_t n, const std::function<void(std::size_t)>& f) { parallel_for(n, f, nullptr); }
  /// The same, with `meanwhile` run first on the calling thread while the other threads
  /// start on the items (e.g. writing out the previous batch's results). An exception from
  /// it is rethrown once the items are done (it wins over theirs).
  void parallel_for(std::size_t n, const std::function<void(std::size_t)>& f, const std::function<void()>& meanwhile);

 private:
  void worker();
  void work_on_current_job();

  unsigned size_ = 1;
  std::vector<std::thread> threads_;
  std::mutex m_;
  std::condition_variable wake_, done_;
  bool stop_ = false;
  std::size_t generation_ = 0;  // bumped per job
  std::size_t busy_ = 0;        // workers still on the current job

  // The current job.
  const std::function<void(std::size_t)>* f_ = nullptr;
  std::size_t n_ = 0;
  std::atomic<std::size_t> next_{0};
  std::atomic<std::size_t> first_failure_{0};
  std::exception_ptr error_;  // of first_failure_ (guarded by m_)
};

}  // namespace imuconv::pipeline
