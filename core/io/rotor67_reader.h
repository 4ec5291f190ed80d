#pragma once
// NASA Rotor 67 stream-surface export (rotor67geometry.dat; see
// ../shared/data/nasa_rotor67/PROVENANCE.md): 14 stream surfaces from hub to
// casing, each with 110 points of axial distance x, upper-surface R·θ,
// tangential thickness Δ(R·θ) and radius R, in FEET. Points JLE..JTE are on
// the blade; the upper (+θ) side is the suction side.
//
// Converted once, here, to the part frame in millimetres with Z on the rotor
// axis: p = (R cos θ, R sin θ, x), θ = (R·θ)/R.
#include <string>
#include <vector>

#include "core/common/types.h"
#include "core/io/blade_sections.h"

namespace bliskrun {

struct StreamSurfaceRotor {
  std::string source;
  int blade_count = 0;
  int leading_edge = 0, trailing_edge = 0;  // 0-based point indices of the blade's ends
  // Per stream surface (hub -> casing), every point, mm and rad.
  struct Surface {
    std::vector<double> x_mm, r_mm, theta_upper_rad, theta_lower_rad;
  };
  std::vector<Surface> surfaces;
  std::vector<Vec2> hub_meridian, casing_meridian;  // (z, r), mm: surfaces 1 and NS
};

// Throws DataError(file, line, what was expected) on any malformed input.
StreamSurfaceRotor read_rotor67(const std::string& path);
StreamSurfaceRotor parse_rotor67(const std::string& text, const std::string& file_label);

// The blade's sections as closed loops (hub -> casing): each stream surface's
// points JLE..JTE along the upper side, then back along the lower side, the
// edge points once. Rotation not stated (the blade model takes it from the
// camber: the upper side is the convex suction side, the rotor turns towards
// -θ).
BladeSections blade_sections(const StreamSurfaceRotor& rotor);
// (The flank grids lofted from them: rotor_flank_grids, core/parts/rotor67_flanks.h.)

}  // namespace bliskrun
