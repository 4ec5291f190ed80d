#pragma once
// Blade flanks lofted from closed section loops (issue 6): the one path by
// which Rotor 37, the HECC impeller and Rotor 67 (after blade_sections())
// become pressure and suction flank grids.
//
// Per section loop (hub -> tip):
//   1. the leading and trailing edges: the two loop points farthest apart
//      give the chord; the end with the smaller z is the LE (flow towards
//      +Z). At each end a circle is fitted (least squares, in the plane of
//      the local camber direction and the thickness direction) to the points
//      within ~45 degrees of arc either side of the edge point (the loop
//      point farthest out along the chord from the circle's centre), window
//      and edge point refined until the radius settles;
//   2. the loop is split at the two edge points into two sides, each run
//      LE -> TE, interpolated by a cubic and resampled at `cols` common
//      chord fractions (ChordFraction) in [edge_margin, 1 - edge_margin]
//      (the edge circles are left out: the edge strategy machines them);
//   3. which side is the pressure side (below);
// then each side's resampled sections are the rows of a grid, extended past
// the hub and tip sections along each column's end tangent by
// `span_extension` of the column's length (a CAD face reaches past the hub
// and casing that trim it), and the fit of the given points to the
// interpolated flanks is measured.
//
// Pressure side convention: the side that faces the direction of rotation
// (compressors, fans, impellers: the blade pushes the flow with it). With
// `rotation_sign` given (+1: the rotor turns towards +θ, i.e. right-handed
// about +Z; -1: towards -θ) that decides; with 0 (unknown) the concave side
// is the pressure side, judged in the blade-to-blade plane (conformal
// meridional coordinate ∫dm/r against θ) by which way the camber line bulges
// from the chord; the rotation is then reported as the direction the
// pressure side faces. Both judgements are reported, so a disagreement shows.
//
// Orientation, as the built-in blisk and SPEC §2: u (rows) hub -> tip; v runs
// along the chord in the direction that makes pu x pv point out of the
// material on both flanks. For a rotor turning towards -θ (Rotor 37, 67, the
// built-in blisk) that is LE -> TE on the pressure flank and TE -> LE on the
// suction flank; for one turning towards +θ (HECC) the reverse.
#include <vector>

#include "core/common/types.h"
#include "core/geometry/point_grid.h"
#include "core/io/blade_sections.h"

namespace bliskrun {

// A circle fitted to one rounded edge of a section loop.
struct EdgeCircle {
  Vec3 centre = Vec3::Zero();
  double radius_mm = 0;
  Vec3 normal = Vec3::Zero();  // unit normal of the plane of the fit
  int point = 0;               // loop index of the edge point, where the loop is split
  int fitted_points = 0;       // loop points the circle was fitted to
  double rms_mm = 0;           // their RMS distance from the circle
};

struct SectionEdges {
  EdgeCircle leading, trailing;
};

// LE and TE of one closed loop (first point not repeated; a repeated closing
// point is tolerated). Throws ParameterError("section", ...) for fewer than
// 8 distinct points.
SectionEdges find_section_edges(const std::vector<Vec3>& loop);

// How the columns correspond across sections: a point's chord fraction is
// its projection on the side's chord (the line from the LE to the TE edge
// point, 0 to 1), or its arc length along the side over the side's length.
// Projection follows the blade's axial/meridional progress and lofts better
// between sections (left-out error on the HECC design blades 4 / 2 um
// against 10 / 34 um by arc length); a side that folds back along its chord
// inside the resampled range falls back to arc length for the whole blade.
enum class ChordFraction { projection, arc_length };

// How the grid columns are spread over [edge_margin, 1 - edge_margin]:
// uniformly, or by cosine spacing (f = (1 - cos(pi t)) / 2 over the column
// index t in [0, 1]), dense at both ends. Near a round edge the chord
// fraction grows with the square of the arc length from the edge point, so
// cosine columns fall nearly uniformly in arc length around the edge: with
// edge_margin = 0 the flanks reach the edge point and carry the round
// themselves (200 cosine columns put ~10 on a 0.45 mm round, uniform ones 1).
enum class ColumnSpacing { uniform, cosine };

struct LoftOptions {
  int cols = 200;               // grid columns along the chord, >= 4
  double edge_margin = 0.03;    // chord fraction left out at each edge, [0, 0.5)
  ColumnSpacing spacing = ColumnSpacing::uniform;
  double span_extension = 0.03; // fraction of each column's length added past hub and tip, [0, 0.5]
  ChordFraction chord_fraction = ChordFraction::projection;
  // Also loft the blade once without each interior section and measure that
  // section's points against it: how well the loft represents the blade
  // between its sections (costs one loft per interior section).
  bool cross_check = false;
};

// Distance of the given section points (those inside the resampled chord
// range) from the interpolated flanks, by point inversion.
struct FitStats {
  double max_mm = 0, rms_mm = 0;
  int points = 0;
};

struct BladeLoft {
  PointGrid pressure, suction;
  // Rows of the grids that hold the hub and the tip section (0-based; the
  // rows before and after are the span extension).
  int hub_row = 0, tip_row = 0;
  std::vector<SectionEdges> edges;  // per section
  int rotation_sign = 0;            // the one used: +1 towards +θ, -1 towards -θ
  bool rotation_given = false;      // from the data (BladeSections), else from the camber
  bool camber_agrees = true;        // the concave side is the pressure side
  bool pressure_v_le_to_te = true;  // v direction of the pressure grid (suction: the reverse)
  ChordFraction chord_fraction = ChordFraction::projection;  // the one used
  FitStats fit, fit_pressure, fit_suction;
  std::vector<FitStats> fit_sections;  // per section, both sides
  // With LoftOptions::cross_check: each interior section's points against the
  // loft of the other sections (the hub and tip sections stay zero).
  FitStats cross;
  std::vector<FitStats> cross_sections;
};

// Throws ParameterError naming the option or the section that cannot be used.
BladeLoft loft_blade(const BladeSections& blade, const LoftOptions& options = {});

}  // namespace bliskrun
