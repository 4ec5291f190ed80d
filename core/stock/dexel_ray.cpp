#include "core/stock/dexel_ray.h"

#include <algorithm>
#include <cstring>
#include <new>
#include <utility>

namespace bliskrun {

namespace {

// Through operator new, so the run's memory budget counts the spans
// (core/common/memory_budget.h).
DexelRay::Span* allocate_spans(std::uint32_t n) {
  return static_cast<DexelRay::Span*>(::operator new(n * sizeof(DexelRay::Span)));
}

}  // namespace

DexelRay::DexelRay(const DexelRay& other) : inline_{0, 0}, size_(other.size_), capacity_(1) {
  if (other.capacity_ == 1) {
    inline_ = other.inline_;
  } else {
    // The copy takes only what it holds.
    if (size_ <= 1) {
      if (size_ == 1) inline_ = other.heap_[0];
    } else {
      heap_ = allocate_spans(size_);
      capacity_ = size_;
      std::copy(other.heap_, other.heap_ + size_, heap_);
    }
  }
}

DexelRay::DexelRay(DexelRay&& other) noexcept : size_(other.size_), capacity_(other.capacity_) {
  std::memcpy(static_cast<void*>(&inline_), &other.inline_, sizeof inline_);  // the span or the heap pointer
  other.capacity_ = 1;
  other.size_ = 0;
}

DexelRay& DexelRay::operator=(DexelRay other) noexcept {
  // The union's bytes, heap pointer or span alike.
  unsigned char bytes[sizeof inline_];
  std::memcpy(bytes, &inline_, sizeof bytes);
  std::memcpy(static_cast<void*>(&inline_), &other.inline_, sizeof bytes);
  std::memcpy(static_cast<void*>(&other.inline_), bytes, sizeof bytes);
  std::swap(size_, other.size_);
  std::swap(capacity_, other.capacity_);
  return *this;
}

DexelRay::~DexelRay() {
  if (capacity_ > 1) ::operator delete(heap_);
}

void DexelRay::reserve(std::uint32_t n) {
  if (n <= capacity_) return;
  const std::uint32_t cap = std::max<std::uint32_t>(n, capacity_ < 2 ? 2 : 2 * capacity_);
  Span* mem = allocate_spans(cap);
  std::copy(data(), data() + size_, mem);
  if (capacity_ > 1) ::operator delete(heap_);
  heap_ = mem;
  capacity_ = cap;
}

void DexelRay::push_back(double start, double end) {
  if (!(end - start >= kMinSpanMm)) return;
  reserve(size_ + 1);
  data()[size_++] = {static_cast<float>(start), static_cast<float>(end)};
}

void DexelRay::replace(int first, int last, const Span* with, int count) {
  const int grow = count - (last - first);
  if (grow > 0) reserve(size_ + static_cast<std::uint32_t>(grow));
  Span* s = data();
  if (grow > 0) std::move_backward(s + last, s + size_, s + size_ + grow);
  if (grow < 0) std::move(s + last, s + size_, s + last + grow);
  std::copy(with, with + count, s + first);
  size_ = static_cast<std::uint32_t>(static_cast<int>(size_) + grow);
}

double DexelRay::length() const {
  double total = 0;
  for (const Span& s : *this) total += static_cast<double>(s.end) - s.start;
  return total;
}

}  // namespace bliskrun
