#pragma once
// Narrowest distance between two flank surfaces facing each other across a
// blade passage (the d_min of the blisk paper's eq. 13), for blades given by
// data rather than by the built-in blisk's closed form.
#include "core/geometry/surface.h"

namespace bliskrun {

struct PassageDistance {
  double distance_mm = 0;
  double ua = 0, va = 0, ub = 0, vb = 0;  // feet on a and b
};

// Samples `a` on an nu x nv grid, projects every sample onto `b`, keeps the
// pairs whose foot on b is not on b's boundary (a boundary foot means the
// nearest point lies beyond b), and refines the best few by alternating
// projection (a fixed point is a common normal: a local minimum of the
// distance). Throws Error when no sample has an interior foot.
PassageDistance narrowest_passage(const Surface& a, const Surface& b, int nu = 24, int nv = 64);

}  // namespace bliskrun
