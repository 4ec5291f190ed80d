#pragma once
// Global cubic B-spline interpolation of curves and of point grids
// (blisk paper §1.1–1.2, eq. 2–8; impeller paper §2, eq. 1–3).
#include <optional>
#include <vector>

#include "core/geometry/curve.h"
#include "core/geometry/point_grid.h"
#include "core/geometry/surface.h"

namespace bliskrun {

// Cumulative chord-length parameters in [0, 1] (eq. 3). Throws ParameterError
// if two consecutive points coincide (zero-length chord).
std::vector<double> chord_length_parameters(const std::vector<Vec3>& points);

// End conditions of a cubic interpolant. Data from CAD has no end tangents;
// the default estimates them from the cubic through the first (last) four
// points, which keeps the edge rows as accurate as the middle.
struct EndTangents {
  std::optional<Vec3> start;  // dC/dt at t = 0 (per unit parameter)
  std::optional<Vec3> end;    // dC/dt at t = 1
};

// Cubic curve through `points` at `params` (chord-length if empty) with the
// tangent end conditions of eq. 8, solved as the banded system of eq. 6–7.
// Needs at least 2 points; 2 or 3 points fall back to lower-order end
// estimates. Reproduces cubic polynomial data exactly when given (or
// estimating) exact end tangents.
BSplineCurve interpolate_cubic(const std::vector<Vec3>& points,
                               const std::vector<double>& params = {},
                               const EndTangents& ends = {});

// Averaged chord-length parameters of a grid (eq. 4): u_i averaged over all
// columns, v_j averaged over all rows.
struct GridParameters {
  std::vector<double> u;  // size rows
  std::vector<double> v;  // size cols
};
GridParameters averaged_grid_parameters(const PointGrid& grid);

// Bicubic surface through every grid point (eq. 5): curves along u for each
// column give intermediate control points, which are interpolated along v.
// Cost is linear in rows * cols. Throws ParameterError on a degenerate grid
// (fewer than 2 rows/cols, repeated points making a zero-length chord).
BSplineSurface interpolate_grid(const PointGrid& grid);
// Same, at given parameters (each vector from 0 to 1, strictly increasing).
BSplineSurface interpolate_grid(const PointGrid& grid, const GridParameters& params);

}  // namespace bliskrun
