#pragma once
// Cancellation by a count of work instead of a clock, for tests that stop
// long work part-way without depending on the machine's speed (the runner's
// RunOptions::test_cancel_at). Apart from progress.h, which nearly every
// file includes, because only the runner and tests need it.
#include <string>

namespace bliskrun {

// The process-wide request of progress.h (request_cancel_all), taking effect
// at the `points`-th cancellation point from now, counted over all threads
// (Progress::check() and step() pass at least one each), instead of at once.
// Until then cancel_all_requested() is false; clear_cancel_all() withdraws
// it. points >= 1.
void request_cancel_all_after(long points, const std::string& reason);

}  // namespace bliskrun
