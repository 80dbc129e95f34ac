#include "common/task_pool.h"

#include <algorithm>

namespace hrpp {

int resolve_threads(int threads) {
  if (threads > 0) return threads;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

TaskPool::TaskPool(int threads) {
  for (int t = 1; t < std::max(1, threads); ++t) workers_.emplace_back([this, t] { worker_loop(t); });
}

TaskPool::~TaskPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& w : workers_) w.join();
}

void TaskPool::parallel_for(std::size_t tasks, const Task& fn) {
  if (workers_.empty() || tasks <= 1) {
    for (std::size_t i = 0; i < tasks; ++i) fn(i, 0);
    return;
  }
  Job job{&fn, tasks, {0}, {0}, {false}, 0, nullptr};
  {
    std::lock_guard lock(mutex_);
    job_ = &job;
    ++generation_;
  }
  wake_.notify_all();
  run(job, 0);
  {
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return job.done.load() == tasks && job.users == 0; });
    job_ = nullptr;
  }
  if (job.error) std::rethrow_exception(job.error);
}

void TaskPool::run(Job& job, int thread) {
  for (std::size_t i = job.next.fetch_add(1); i < job.tasks; i = job.next.fetch_add(1)) {
    try {
      if (!job.failed.load()) (*job.fn)(i, thread);
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!job.error) job.error = std::current_exception();
      job.failed.store(true);
    }
    job.done.fetch_add(1);
  }
}

void TaskPool::worker_loop(int thread) {
  std::uint64_t seen = 0;
  for (;;) {
    Job* job = nullptr;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || (job_ && generation_ != seen); });
      if (stop_) return;
      seen = generation_;
      job = job_;
      ++job->users;
    }
    run(*job, thread);
    {
      std::lock_guard lock(mutex_);
      --job->users;
    }
    done_.notify_all();
  }
}

}  // namespace hrpp
