#pragma once
// Progress reporting and cancellation for long core loops.
//
// Core never prints. A long loop takes a Progress& and calls step() at safe
// points; the caller decides what to show (the CLI prints to stderr unless
// --quiet) and whether to cancel (time limit, memory limit).
#include <atomic>
#include <functional>
#include <string>

namespace bliskrun {

bool cancel_all_requested();

// One line of a terminal progress bar, e.g.
//   "[simulate] [########............]  42%  elapsed 3.1 s  remaining ~4.3 s"
// `bar_width` cells of '#' for the done fraction; the remaining time is
// elapsed * (total - done) / done, shown once something is done. Pure, so
// the CLI's drawing (carriage return on a terminal) is tested through it.
std::string progress_bar_line(const std::string& task, long done, long total, double elapsed_s,
                              int bar_width = 24);

class Progress {
 public:
  // Called with (task, done, total); may be empty.
  using Reporter = std::function<void(const std::string&, long, long)>;

  Progress() = default;
  explicit Progress(Reporter reporter) : reporter_(std::move(reporter)) {}
  // A worker's own Progress inside a parallel job: it reports nothing and is
  // cancelled whenever `parent` is (the watchdog cancels the parent).
  explicit Progress(const Progress* parent) : parent_(parent) {}
  void set_reporter(Reporter reporter) { reporter_ = std::move(reporter); }

  // Starts a named task of `total` units.
  void begin(const std::string& task, long total);
  // Marks `done` units of the current task finished. Throws Cancelled if
  // cancel() was called (from any thread).
  void step(long done);
  void end();

  void cancel(std::string reason) {
    reason_ = std::move(reason);
    cancelled_.store(true);
  }
  bool cancelled() const {
    return cancelled_.load() || (parent_ && parent_->cancelled()) || cancel_all_requested();
  }
  // Throws Cancelled if a cancel was requested.
  void check() const;

  // A shared do-nothing instance for callers that do not care.
  static Progress& none();

 private:
  Reporter reporter_;
  std::string task_;
  long total_ = 0;
  long last_reported_ = -1;
  std::atomic<bool> cancelled_{false};
  const Progress* parent_ = nullptr;
  std::string reason_;
};

// Process-wide cancellation, for the loops that take no Progress (readers,
// analysis, geometry searches, lofting) and for every Progress, none()
// included: once the run's watchdog requests it, cancellation_point() and
// every Progress::check()/step() throw Cancelled. One relaxed atomic load per
// point, so a loop can afford one per row, line or search iteration.
void request_cancel_all(const std::string& reason);
void clear_cancel_all();
bool cancel_all_requested();
void cancellation_point();

}  // namespace bliskrun
