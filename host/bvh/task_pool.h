// A fixed pool of threads for the BVH builder: parallel_for over task indices, the calling
// thread taking part. Tasks are handed out one at a time from a shared counter, so which thread
// runs which task varies from run to run; callers keep results independent of that.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hrpp {

class TaskPool {
 public:
  // `threads` threads in all: the caller and threads - 1 workers (at least one thread).
  explicit TaskPool(int threads);
  ~TaskPool();
  TaskPool(const TaskPool&) = delete;
  TaskPool& operator=(const TaskPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }

  // Runs fn(task, thread) for every task in [0, tasks), thread in [0, size()) naming the thread
  // that runs it (0: the caller); returns when all are done, rethrowing the first exception.
  using Task = std::function<void(std::size_t task, int thread)>;
  void parallel_for(std::size_t tasks, const Task& fn);

 private:
  void worker_loop(int thread);
  void drain(int thread);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const Task* fn_ = nullptr;
  std::size_t tasks_ = 0;
  std::atomic<std::size_t> next_{0};
  std::uint64_t generation_ = 0;
  int running_ = 0;  // workers still in the current parallel_for
  bool stop_ = false;
  std::exception_ptr error_;
};

}  // namespace hrpp
