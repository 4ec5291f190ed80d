#include "core/common/memory_budget.h"

#include <gtest/gtest.h>

#include <memory>
#include <new>
#include <vector>

namespace bliskrun {
namespace {

// Allocates and touches n bytes (a use the compiler cannot elide).
__attribute__((noinline)) char allocate(size_t n) {
  std::vector<char> block(n);
  block[n / 2] = 1;
  volatile char* p = block.data();
  return p[n / 2];
}

// Restores "no budget" whatever a test does.
struct BudgetGuard {
  ~BudgetGuard() { set_memory_budget(0); }
};

// operator new counts what it hands out and delete gives it back: a 40 MB
// vector shows in memory_in_use while it lives, and not after.
TEST(MemoryBudget, CountsTheCxxHeap) {
  const size_t before = memory_in_use();
  {
    std::vector<char> block(40u << 20);
    block.back() = 1;
    EXPECT_GE(memory_in_use(), before + (40u << 20));
  }
  EXPECT_LT(memory_in_use(), before + (1u << 20));
}

// A C++ allocation beyond the budget fails with std::bad_alloc and marks the
// budget exceeded; one within it succeeds; the count is unchanged by the
// refusal.
TEST(MemoryBudget, RefusesAllocationsBeyondTheBudget) {
  BudgetGuard guard;
  set_memory_budget(static_cast<double>(memory_in_use()) + (16u << 20));
  EXPECT_FALSE(memory_budget_exceeded());
  auto small = std::make_unique<std::vector<char>>(4u << 20);
  (*small)[0] = 1;
  const size_t in_use = memory_in_use();
  EXPECT_THROW(allocate(64u << 20), std::bad_alloc);
  EXPECT_TRUE(memory_budget_exceeded());
  EXPECT_EQ(memory_in_use(), in_use);
  set_memory_budget(0);  // clears the mark
  EXPECT_FALSE(memory_budget_exceeded());
  EXPECT_NO_THROW(allocate(64u << 20));
}

// The Lua heap's allocator reserves from the same total.
TEST(MemoryBudget, ReservationsShareTheTotal) {
  BudgetGuard guard;
  set_memory_budget(static_cast<double>(memory_in_use()) + (8u << 20));
  EXPECT_TRUE(reserve_memory(6u << 20));
  EXPECT_THROW(allocate(4u << 20), std::bad_alloc);  // 6 + 4 > 8
  release_memory(6u << 20);
  EXPECT_NO_THROW(allocate(4u << 20));
  EXPECT_FALSE(reserve_memory(16u << 20));
  EXPECT_TRUE(memory_budget_exceeded());
}

}  // namespace
}  // namespace bliskrun
