#pragma once
// The run's memory budget, over the Lua heap and the C++ heap together.
//
// The bliskrun runner sets the budget from --memory-limit. Every C++
// allocation through operator new (std containers of meshes, grids, samples,
// FCL models) is counted here by the replacement operators in
// memory_budget.cpp, and the runner's Lua allocator counts the Lua heap into
// the same total: a request that would take the total beyond the budget fails
// — std::bad_alloc in C++, a Lua memory error in Lua — and is reported as the
// limit error at the recipe line. Eigen's dynamic matrices allocate with
// malloc directly and are not counted; core keeps its large data in std
// containers.
//
// Code about to make one large allocation whose size it can estimate (a mesh,
// a grid) also asks first, so an absurd request is refused with the estimate
// in the message before anything is allocated.
#include <cstddef>
#include <string>

namespace bliskrun {

// Bytes a run may use; 0 = no budget. Process-wide (one run at a time).
// Setting it clears the "exceeded" mark.
void set_memory_budget(double bytes);
double memory_budget();

// Bytes counted now (C++ heap through operator new, plus what the Lua
// allocator reserved).
size_t memory_in_use();

// For an allocator outside operator new (the Lua heap): counts `bytes` in if
// the total stays within the budget (true), else marks the budget exceeded
// and counts nothing (false). release_memory gives bytes back.
bool reserve_memory(size_t bytes);
void release_memory(size_t bytes);

// Whether a request was refused for the budget since it was set.
bool memory_budget_exceeded();

// Throws Error "<what> needs an estimated N MB, more than the memory
// limit of M MB (--memory-limit)" when estimated_bytes exceeds the budget.
void check_allocation_estimate(double estimated_bytes, const std::string& what);

}  // namespace bliskrun
