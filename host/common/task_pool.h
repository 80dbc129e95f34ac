// A fixed pool of threads for the CPU's parallel work (the BVH builders, the CPU reference
// traversal over ray batches, the CPU reference renderer): parallel_for over task indices, the
// calling thread taking part. Tasks are handed out one at a time from a shared counter, so which
// thread runs which task varies from run to run; callers keep results independent of that. An
// exception thrown by a task, on any thread, reaches parallel_for's caller.
//
// The caller waits only for tasks, never for a worker to wake up: on a busy machine a worker
// that the scheduler has not run yet finds no task left when it does run, and the caller has
// done them all in the meantime.
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

// The threads parallel work uses for a requested count: `threads` when > 0, else (0: all) the
// hardware's threads, at least 1.
int resolve_threads(int threads);

// Tasks of `chunk` items each (the last one shorter) that cover n items.
constexpr std::size_t chunks(std::size_t n, std::size_t chunk) { return (n + chunk - 1) / chunk; }

class TaskPool {
 public:
  // `threads` threads in all: the caller and threads - 1 workers (at least one thread).
  explicit TaskPool(int threads);
  ~TaskPool();
  TaskPool(const TaskPool&) = delete;
  TaskPool& operator=(const TaskPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }

  // Runs fn(task, thread) for every task in [0, tasks), thread in [0, size()) naming the thread
  // that runs it (0: the caller); returns when all are done, rethrowing the first exception
  // (tasks not yet started when a task throws are skipped).
  using Task = std::function<void(std::size_t task, int thread)>;
  void parallel_for(std::size_t tasks, const Task& fn);

 private:
  struct Job {
    const Task* fn;
    std::size_t tasks;
    std::atomic<std::size_t> next{0}, done{0};
    std::atomic<bool> failed{false};
    int users = 0;  // workers inside run(); guarded by mutex_
    std::exception_ptr error;
  };
  void worker_loop(int thread);
  void run(Job& job, int thread);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  Job* job_ = nullptr;  // the current parallel_for's, while it has tasks to hand out
  std::uint64_t generation_ = 0;
  bool stop_ = false;
};

}  // namespace hrpp
