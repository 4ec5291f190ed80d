#pragma once
// Wall-clock seconds for the timings planners report (trim_seconds,
// plan_seconds, ...): steady_clock, which never jumps with the system clock.
#include <chrono>

namespace bliskrun {

using SteadyClock = std::chrono::steady_clock;

inline double seconds_since(SteadyClock::time_point t0) {
  return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

}  // namespace bliskrun
