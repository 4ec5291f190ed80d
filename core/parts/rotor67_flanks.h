#pragma once
// NASA Rotor 67's flanks as grids for the planners: the stream surfaces the
// reader gives (core/io/rotor67_reader.h) lofted by the blade model, the one
// loft of every part given as sections (core/parts/blade_model.h).
#include "core/geometry/point_grid.h"
#include "core/io/rotor67_reader.h"

namespace bliskrun {

// Flank grids of blade 0, one row per stream surface (hub -> casing), cols
// along the chord: loft_blade (core/parts/blade_model.h) of blade_sections()
// without span extension - edge circles found from the geometry, each side
// resampled at `cols` common chord fractions (projection on the LE-TE
// chord) in [edge_margin, 1 - edge_margin] so that columns correspond across
// sections and the edge circles are left out (the edge strategy machines
// them).
// Orientation as the built-in blisk: u hub -> tip; v LE -> TE on the
// pressure side, TE -> LE on the suction side, so that pu x pv points out of
// the material on both.
struct RotorFlanks {
  PointGrid pressure, suction;
};
RotorFlanks rotor_flank_grids(const StreamSurfaceRotor& rotor, int cols = 200, double edge_margin = 0.03);

}  // namespace bliskrun
