#include "core/common/memory_budget.h"

#include <atomic>
#include <cstdio>

#include "core/common/error.h"

namespace bliskrun {

namespace {
std::atomic<double> budget_bytes{0};

std::string megabytes(double bytes) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6g MB", bytes / (1024.0 * 1024.0));
  return text;
}
}  // namespace

void set_memory_budget(double bytes) { budget_bytes.store(bytes > 0 ? bytes : 0); }

double memory_budget() { return budget_bytes.load(); }

void check_allocation_estimate(double estimated_bytes, const std::string& what) {
  const double budget = budget_bytes.load();
  if (budget > 0 && estimated_bytes > budget)
    throw Error(what + " needs an estimated " + megabytes(estimated_bytes) + ", more than the memory limit of " +
                megabytes(budget) + " (--memory-limit)");
}

}  // namespace bliskrun
