#pragma once
// Around a closed curve: samples at equal arc length with the signed
// curvature there, and the vector area of a closed polyline. What the loft
// through closed sections (core/geometry/section_loft.h) and the repair's
// section processing (core/repair/section_curve.h, section_points.h) share.
#include <vector>

#include "core/common/types.h"
#include "core/geometry/closed_curve.h"

namespace bliskrun {

struct CurvatureProfile {
  std::vector<double> t;          // curve parameters of the samples, from t_min
  std::vector<double> curvature;  // 1/mm, signed (positive: convex)
  double length_mm = 0;           // arc length of the whole loop
  double period = 0;              // the curve's parameter period (t of sample n)
};

// `samples` points of equal arc length around the loop from its start (arc
// length by 5-point Gauss–Legendre per knot span). The paper asks for many,
// so the short, sharply curved edges get enough: the default 2048 puts ~13
// samples on the half-circle of a 0.3 mm edge radius of a 150 mm profile; a
// count with small prime factors keeps the FFT of align_start fast. Throws
// ParameterError ("samples") below 16.
CurvatureProfile curvature_profile(const ClosedCurve& curve, int samples = 2048);

// ½ Σ p_i × p_{i+1} over the closed loop: its direction is the loop's normal
// (right-handed with the order), its length the area enclosed.
Vec3 vector_area(const std::vector<Vec3>& loop);

}  // namespace bliskrun
