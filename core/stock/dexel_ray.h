#pragma once
// One dexel: the material a ray of the stock passes through, as sorted,
// disjoint spans [start, end] of the coordinate along the ray (mm).
//
// The stock holds hundreds of thousands to millions of rays, most of them
// with one span (a solid blank) or none (outside it), so a ray is 16 bytes:
// one span stored inline, more on the heap. Span ends are floats: at the
// 130 mm of a blisk blank a float is exact to 8 µm / 10^3 = 15 nm, far
// below any resolution the stock is built at, and half the memory of doubles.
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace bliskrun {

class DexelRay {
 public:
  struct Span {
    float start, end;
  };
  // A span shorter than this (mm) is dropped when a cut leaves it: float
  // rounding of two cuts at the same place would otherwise leave slivers.
  static constexpr double kMinSpanMm = 1e-4;

  DexelRay() : inline_{0, 0} {}
  DexelRay(const DexelRay& other);
  DexelRay(DexelRay&& other) noexcept;
  DexelRay& operator=(DexelRay other) noexcept;
  ~DexelRay();

  int size() const { return static_cast<int>(size_); }
  bool empty() const { return size_ == 0; }
  const Span* begin() const { return data(); }
  const Span* end() const { return data() + size_; }
  const Span& operator[](int i) const { return data()[i]; }

  // Appends a span after the last one (start > the last end; spans shorter
  // than kMinSpanMm are skipped). For building a blank.
  void push_back(double start, double end);

  // Removes [a, b] (a <= b) from the material. `removed(s, e)` is called
  // for every removed piece, s < e; returns the removed length (mm).
  template <class OnRemoved>
  double subtract(double a, double b, OnRemoved&& removed);

  // Whether any material lies strictly between a and b.
  bool overlaps(double a, double b) const {
    for (const Span& s : *this) {
      if (s.start >= b) return false;
      if (s.end > a) return true;
    }
    return false;
  }
  // Material along the ray, mm.
  double length() const;
  // Heap bytes beyond the ray itself.
  std::size_t heap_bytes() const { return capacity_ > 1 ? capacity_ * sizeof(Span) : 0; }

 private:
  Span* data() { return capacity_ > 1 ? heap_ : &inline_; }
  const Span* data() const { return capacity_ > 1 ? heap_ : &inline_; }
  void reserve(std::uint32_t n);
  // Replaces spans [first, last) by `count` spans from `with`.
  void replace(int first, int last, const Span* with, int count);

  union {
    Span inline_;
    Span* heap_;
  };
  std::uint32_t size_ = 0, capacity_ = 1;
};

// Float bounds that contain [a, b]: a cut takes its own float ends, so
// cutting the same solid twice takes nothing the second time.
inline float float_at_or_below(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -HUGE_VALF) : f;
}
inline float float_at_or_above(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, HUGE_VALF) : f;
}

template <class OnRemoved>
double DexelRay::subtract(double a, double b, OnRemoved&& removed) {
  if (size_ == 0 || !(b > a)) return 0;
  const Span* s = data();
  if (b <= s[0].start || a >= s[size_ - 1].end) return 0;
  const float fa = float_at_or_below(a), fb = float_at_or_above(b);
  int first = 0;
  while (first < static_cast<int>(size_) && s[first].end <= fa) ++first;
  int last = first;
  while (last < static_cast<int>(size_) && s[last].start < fb) ++last;
  if (first == last) return 0;  // [a, b] lies in a gap
  // At most two spans survive: the piece before a and the piece after b.
  // Lengths are taken from the stored floats, so the removed total is what
  // the spans lose.
  Span kept[2];
  int n = 0;
  double total = 0;
  for (int i = first; i < last; ++i) {
    const float lo = s[i].start, hi = s[i].end;
    float removed_lo = lo > fa ? lo : fa, removed_hi = hi < fb ? hi : fb;
    if (lo < fa) {
      if (static_cast<double>(fa) - lo >= kMinSpanMm) {
        kept[n++] = {lo, fa};
      } else {
        removed_lo = lo;
      }
    }
    if (hi > fb) {
      if (static_cast<double>(hi) - fb >= kMinSpanMm) {
        kept[n++] = {fb, hi};
      } else {
        removed_hi = hi;
      }
    }
    if (removed_hi > removed_lo) {
      removed(static_cast<double>(removed_lo), static_cast<double>(removed_hi));
      total += static_cast<double>(removed_hi) - removed_lo;
    }
  }
  replace(first, last, kept, n);
  return total;
}

}  // namespace bliskrun
