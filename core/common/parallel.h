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

}  // namespace bliskrun
