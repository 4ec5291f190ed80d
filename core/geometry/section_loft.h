#pragma once
// The blade rebuilt from its processed sections (repair paper §1.4): a surface
// lofted through measured section curves, and the deviation of the measured
// points from it (the paper reports a mean of 3.51 um).
//
// Loft. Each section — a closed curve, ordered, oriented, smoothed and
// start-aligned (core/repair/section_points.h, section_curve.h) — is sampled at the same
// M fractions of its arc length from its start, so sample j of every section
// is the same place on the profile (the §1.3 alignment is what makes that
// true). The N x M samples are interpolated as interpolate_grid does an open
// grid (blade paper eq. 5, the same two passes) except around the section:
// each section's samples by the closed C2 cubic (interpolate_closed_cubic) at
// one knot vector for all, uniform because the samples are at equal arc
// length; then each column of the closed curves' control points along the
// span by interpolate_cubic at the sections' averaged chord-length
// parameters (eq. 4), end tangents estimated as for any grid. The surface is
// therefore closed and C2 around the section, with no seam: its first three
// control-point columns are its last three. It interpolates every sample,
// and spans from the first section (u = 0) to the last (u = 1): nothing is
// extrapolated past them (the tip extension of §1.4.2 is a later step).
//
// Orientation, as SPEC §2: u runs from the first section to the last, v once
// around, in the direction that makes pu x pv point out of the material —
// against the sections' own direction when they run counter-clockwise about
// the direction from the first section to the last.
#include <vector>

#include "core/common/types.h"
#include "core/geometry/closed_curve.h"
#include "core/geometry/point_grid.h"
#include "core/geometry/surface.h"

namespace bliskrun {

struct SectionLoftOptions {
  // Samples per section (M), at equal arc length. Enough to resolve the
  // edges: 512 on a 70 mm profile are 0.14 mm apart, ~14 on the half circle
  // of a 0.6 mm edge radius, where the cubic's error h^4 / (384 R^3) is
  // below 0.01 um (it falls as the fourth power of the spacing). At least 16.
  int samples = 512;
};

struct SectionLoft {
  BSplineSurface surface;          // (u, v) in [0, 1]^2, periodic in v
  std::vector<double> section_u;   // u of each section (surface row through it)
  PointGrid grid;                  // the N x M samples it interpolates, row k = section k, column j at v = j / M
};

// Throws ParameterError ("sections") for fewer than 2 sections or two
// sections whose samples coincide, ("samples") for fewer than 16.
SectionLoft loft_sections(const std::vector<ClosedCurve>& sections, const SectionLoftOptions& options = {});

// Distances of measured points from the lofted surface by point inversion
// (core/geometry/projection.h), Newton from the nearest sample of the grid.
// Across the seam v = 0 = 1 the projection runs on the surface re-started
// half a period on, so a point there is not held at a domain edge the
// surface does not have. Points beyond the first or last section project to
// that edge (the surface ends there).
struct LoftDeviation {
  int points = 0;
  double mean_mm = 0;  // the paper's figure
  double rms_mm = 0;
  double max_mm = 0;
  int worst = -1;      // index of the point at max_mm
};

// Where one point projects and how far it is, signed: positive outside the
// material (along pu x pv).
struct PointDeviation {
  double u = 0, v = 0;
  double signed_mm = 0;
};

// Throws ParameterError ("points") for no point or a non-finite one, Error if
// a point does not project (the projection's reason given). With `each`, the
// points' deviations one by one (for a deviation map). The points are
// projected on `threads` threads; the result does not depend on it.
LoftDeviation loft_deviation(const SectionLoft& loft, const std::vector<Vec3>& points,
                             std::vector<PointDeviation>* each = nullptr, int threads = 1);

}  // namespace bliskrun
