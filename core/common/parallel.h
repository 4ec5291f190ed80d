#pragma once
// Independent jobs on a few worker threads (several flanks, several
// channels): each job writes its own result slot, so results do not depend
// on the thread count. One step of `progress` per finished job; the first
// failure stops handing out work and is rethrown to the caller once every
// worker has stopped; cancelling `progress` stops each worker at its job's
// next safe point.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/common/error.h"
#include "core/common/progress.h"

namespace bliskrun {

// Calls job(k, worker_progress) for k in [0, n) on up to `threads` threads.
template <class Job>
void run_parallel(size_t n, int threads, Progress& progress, const std::string& task, Job&& job) {
  if (threads < 1) throw ParameterError("threads", "must be >= 1");
  const int workers = std::max(1, std::min<int>(threads, static_cast<int>(n)));
  std::atomic<size_t> next{0};
  long done = 0;
  std::mutex mutex;  // the reporter is not thread-safe
  std::exception_ptr failure;
  progress.begin(task, static_cast<long>(n));
  auto work = [&] {
    Progress own(&progress);  // cancelled with the caller's
    for (;;) {
      const size_t k = next.fetch_add(1);
      if (k >= n) return;
      try {
        job(k, own);
        std::lock_guard<std::mutex> lock(mutex);
        progress.step(++done);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        next.store(n);  // stop handing out work
        return;
      }
    }
  };
  if (workers == 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    for (int w = 0; w < workers; ++w) pool.emplace_back(work);
    for (auto& t : pool) t.join();
  }
  if (failure) std::rethrow_exception(failure);
  progress.end();
}

// Calls f(i) for i in [0, n) on up to `threads` threads, each taking a
// contiguous run of indices (at least 8 of them, so small loops stay on
// the caller's thread). f writes only what belongs to index i. Where f
// throws, the exception of the lowest such index is rethrown once every
// thread has stopped — the one a plain loop would have thrown. No
// progress: for loops inside a job that reports its own.
template <class F>
void parallel_for_index(size_t n, int threads, F&& f) {
  const int workers = std::max(1, std::min<int>(threads, static_cast<int>(n / 8)));
  if (workers == 1) {
    for (size_t i = 0; i < n; ++i) f(i);
    return;
  }
  std::vector<std::exception_ptr> failure(workers);
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) {
    pool.emplace_back([&, w] {
      const size_t lo = n * w / workers, hi = n * (w + 1) / workers;
      try {
        for (size_t i = lo; i < hi; ++i) f(i);
      } catch (...) {
        failure[w] = std::current_exception();
      }
    });
  }
  for (auto& t : pool) t.join();
  for (const std::exception_ptr& e : failure)
    if (e) std::rethrow_exception(e);
}

}  // namespace bliskrun
