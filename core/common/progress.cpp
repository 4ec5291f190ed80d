#include "core/common/progress.h"

#include <algorithm>
#include <cstdio>

#include <mutex>

#include "core/common/cancel_after.h"
#include "core/common/error.h"

namespace bliskrun {

namespace {
// cancel_all alone decides the fast path (one relaxed load per point); the
// countdown of request_cancel_all_after() is read only once it is set, and
// is 0 for a request that takes effect at once.
std::atomic<bool> cancel_all{false};
std::atomic<long> points_left{0};
std::mutex cancel_all_mutex;
std::string cancel_all_reason;

void request(long points, const std::string& reason) {
  {
    std::lock_guard<std::mutex> lock(cancel_all_mutex);
    cancel_all_reason = reason;
  }
  points_left.store(points);
  cancel_all.store(true);
}
}  // namespace

void request_cancel_all(const std::string& reason) { request(0, reason); }

void request_cancel_all_after(long points, const std::string& reason) { request(std::max(points, 1L), reason); }

void clear_cancel_all() {
  cancel_all.store(false);
  points_left.store(0);
}

bool cancel_all_requested() {
  return cancel_all.load(std::memory_order_relaxed) && points_left.load(std::memory_order_relaxed) <= 0;
}

void cancellation_point() {
  if (!cancel_all.load(std::memory_order_relaxed)) return;
  // A countdown: points before the last one pass. Once it has run out the
  // count goes on below zero and every point throws.
  std::atomic_thread_fence(std::memory_order_acquire);  // see the countdown stored before the flag
  if (points_left.fetch_sub(1, std::memory_order_relaxed) > 1) return;
  std::string reason;
  {
    std::lock_guard<std::mutex> lock(cancel_all_mutex);
    reason = cancel_all_reason;
  }
  throw Cancelled("cancelled: " + reason);
}

std::string progress_bar_line(const std::string& task, long done, long total, double elapsed_s, int bar_width) {
  const double f = total > 0 ? std::clamp(static_cast<double>(done) / total, 0.0, 1.0) : 0.0;
  const int filled = static_cast<int>(f * bar_width);
  char tail[96];
  if (done > 0 && done < total)
    std::snprintf(tail, sizeof tail, "] %3d%%  elapsed %.1f s  remaining ~%.1f s", static_cast<int>(f * 100),
                  elapsed_s, elapsed_s * (total - done) / done);
  else
    std::snprintf(tail, sizeof tail, "] %3d%%  elapsed %.1f s", static_cast<int>(f * 100), elapsed_s);
  return "[" + task + "] [" + std::string(filled, '#') + std::string(bar_width - filled, '.') + tail;
}

void Progress::begin(const std::string& task, long total) {
  task_ = task;
  total_ = total;
  last_reported_ = -1;
  check();
  if (reporter_) reporter_(task_, 0, total_);
}

void Progress::step(long done) {
  check();
  if (!reporter_ || total_ <= 0) return;
  // Report at whole percents only, so a tight loop does not flood stderr.
  const long percent = done * 100 / total_;
  if (percent != last_reported_) {
    last_reported_ = percent;
    reporter_(task_, done, total_);
  }
}

void Progress::end() {
  if (reporter_ && last_reported_ != 100) reporter_(task_, total_, total_);
  task_.clear();
}

void Progress::check() const {
  if (cancelled_.load()) throw Cancelled("cancelled: " + reason_);
  if (parent_) parent_->check();
  cancellation_point();
}

Progress& Progress::none() {
  static thread_local Progress instance;
  return instance;
}

}  // namespace bliskrun
