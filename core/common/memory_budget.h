#pragma once
// The run's memory budget as seen by core: the bliskrun runner sets it from
// --memory-limit, and code about to make one large allocation whose size it
// can estimate (a mesh, a grid) asks first, so an absurd request is refused
// with the estimate in the message instead of exhausting the machine.
//
// This is a check of single estimated requests against the whole budget, not
// an accounting of every allocation (the Lua heap is accounted exactly by the
// runner's allocator).
#include <cstddef>
#include <string>

namespace bliskrun {

// Bytes a run may use; 0 = no budget. Process-wide (one run at a time).
void set_memory_budget(double bytes);
double memory_budget();

// Throws Error "<what> needs an estimated N MB, more than the memory
// limit of M MB (--memory-limit)" when estimated_bytes exceeds the budget.
void check_allocation_estimate(double estimated_bytes, const std::string& what);

}  // namespace bliskrun
