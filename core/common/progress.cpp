#include "core/common/progress.h"

#include "core/common/error.h"

namespace bliskrun {

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
}

Progress& Progress::none() {
  static thread_local Progress instance;
  return instance;
}

}  // namespace bliskrun
