#include "core/common/memory_budget.h"

#include <malloc.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "core/common/error.h"

namespace bliskrun {

namespace {
std::atomic<double> budget_bytes{0};
std::atomic<size_t> in_use{0};
std::atomic<bool> exceeded{false};

std::string megabytes(double bytes) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6g MB", bytes / (1024.0 * 1024.0));
  return text;
}
}  // namespace

void set_memory_budget(double bytes) {
  budget_bytes.store(bytes > 0 ? bytes : 0);
  exceeded.store(false);
}

double memory_budget() { return budget_bytes.load(); }

size_t memory_in_use() { return in_use.load(std::memory_order_relaxed); }

bool reserve_memory(size_t bytes) {
  const size_t before = in_use.fetch_add(bytes, std::memory_order_relaxed);
  const double budget = budget_bytes.load(std::memory_order_relaxed);
  if (budget > 0 && static_cast<double>(before + bytes) > budget) {
    in_use.fetch_sub(bytes, std::memory_order_relaxed);
    exceeded.store(true);
    return false;
  }
  return true;
}

void release_memory(size_t bytes) { in_use.fetch_sub(bytes, std::memory_order_relaxed); }

bool memory_budget_exceeded() { return exceeded.load(); }

void check_allocation_estimate(double estimated_bytes, const std::string& what) {
  const double budget = budget_bytes.load();
  if (budget > 0 && estimated_bytes > budget)
    throw Error(what + " needs an estimated " + megabytes(estimated_bytes) + ", more than the memory limit of " +
                megabytes(budget) + " (--memory-limit)");
}

}  // namespace bliskrun

// ---- counting operator new / delete -------------------------------------
//
// Replacements of the global allocation functions (this object file is
// linked into every program that uses the budget). They count the block's
// usable size, which is what free() gives back, so new and delete agree
// whatever size delete is told.

namespace {

void* counted_alloc(std::size_t size, std::size_t align) {
  if (size == 0) size = 1;
  void* p = align > alignof(std::max_align_t) ? std::aligned_alloc(align, (size + align - 1) / align * align)
                                              : std::malloc(size);
  if (!p) throw std::bad_alloc();
  if (!bliskrun::reserve_memory(malloc_usable_size(p))) {
    std::free(p);
    throw std::bad_alloc();
  }
  return p;
}

void* counted_alloc_nothrow(std::size_t size, std::size_t align) noexcept {
  try {
    return counted_alloc(size, align);
  } catch (...) {
    return nullptr;
  }
}

void counted_free(void* p) noexcept {
  if (!p) return;
  bliskrun::release_memory(malloc_usable_size(p));
  std::free(p);
}

}  // namespace

void* operator new(std::size_t size) { return counted_alloc(size, 0); }
void* operator new[](std::size_t size) { return counted_alloc(size, 0); }
void* operator new(std::size_t size, std::align_val_t a) { return counted_alloc(size, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t size, std::align_val_t a) { return counted_alloc(size, static_cast<std::size_t>(a)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return counted_alloc_nothrow(size, 0); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return counted_alloc_nothrow(size, 0); }
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_alloc_nothrow(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_alloc_nothrow(size, static_cast<std::size_t>(a));
}
void operator delete(void* p) noexcept { counted_free(p); }
void operator delete[](void* p) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { counted_free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { counted_free(p); }
