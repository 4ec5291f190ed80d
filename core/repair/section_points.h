#pragma once
// Measured blade sections, the first step of a repair (repair paper §1.1):
// the scattered points a probe or scanner took on one section are put in
// order around the profile, strays are rejected, and the sections of a blade
// are given one orientation and comparable start points.
//
// Ordering. The paper walks greedily to the nearest unused point and refuses
// a step that turns by more than α_r from the previous step (its set W),
// trying the next nearest instead. That is kept — the cone of half-angle
// max_turn around the direction of travel is what stops the walk jumping
// across a thin leading or trailing edge to the other flank — with these
// changes, because a measured repair section has what the paper's simulated
// data had not:
//  - the direction of travel is the chord back to the last point at least two
//    spacings behind, not the last step alone: with noise a fraction of the
//    spacing a single step points anywhere, and the cone would refuse good
//    points;
//  - a step is at most max_step long. Where nothing lies in the cone within
//    it (a gap the probe could not reach, the missing edge of a damaged
//    blade, an edge sampled too coarsely for the cone) the walk stops instead
//    of jumping, and walks again from its seed the other way. Walks from
//    further seeds give more chains; the chains are joined end to end in the
//    order and directions that make the joining links shortest, so a gap is
//    bridged once, between its two ends;
//  - every point is tested against its neighbours' local curve — a quadratic
//    in chord length through neighbours within its stretch (not across a
//    gap), the least distance over four windows (two each side, the four
//    nearest along the loop, four before, four after; a line for a one-sided
//    window), measured at the point's foot on the curve and scaled by the
//    fit's own uncertainty there. A profile point fits one of them (the side
//    of a sharp edge next to a coarsely probed flank, the flank at a gap's
//    end); a stray fits none. Points farther than the outlier distance are
//    rejected, the worst of a neighbourhood first (a stray also bends its
//    neighbours' fits), until none is left; so are points alone between two
//    gaps, which nothing can vouch for;
//  - then the points the walks passed by (noise put two points side by
//    side) and chains of fewer than 3 points (the tip of a coarsely sampled
//    edge, a stray) are put back where they lengthen the loop least, if a
//    loop point is within max_step (farther ones are rejected), and tested
//    the same way.
// Limits no local test removes: the one point on the tip of an edge of
// radius below the spacing is, to every such test, a stray; and four or more
// stray points on a smooth curve of their own (a fixture edge probed along)
// are a stretch of profile to them — joined in where it costs least, with a
// gap reported either side.
// Cost: O(n) grid look-ups (core/geometry/point_index.h) for the walk and the
// tests, each rejection pass O(n) (passes: the largest cluster of strays),
// n log n for sorting. Measured: ~9 ms for a 2000-point section, ~15 ms of
// CPU each for 30 such sections with 10 strays each, on a loaded build
// machine (1000 to 16000 points: 4 to 90 ms).
//
// Orientation (§1.1, Fig. 4). The paper compares the cross products of three
// convex-hull points on neighbouring sections. The vector area of the whole
// loop, ½ Σ p_i × p_{i+1}, is used instead: it is the same test (a blade's
// concave pressure side is inside the hull, the area's sign does not see it)
// but sums every point, so no three noisy points can flip it, and it works on
// loops that are not planar (sections on a cone or cylinder) and on loops
// with a gap.
#include <vector>

#include "core/common/types.h"
#include "core/geometry/curve_profile.h"  // vector_area

namespace bliskrun {

struct SectionOrderOptions {
  // The paper's α_r: the largest turn from the direction of travel to the
  // next point, in (0, π). 60° refuses the near-perpendicular step across a
  // blade's thickness with margin for noise, and lets the walk round an edge
  // whose radius is at least ~1.5 point spacings (the turn per step there is
  // ~1.5 spacing / radius); a coarser edge is bridged by the chain join.
  double max_turn_rad = deg_to_rad(60);
  // Longest step of a walk; a longer distance between consecutive points of
  // the loop is a gap. 0: 2.5 times the 90th percentile of the points'
  // nearest-neighbour distances (a flank probed more coarsely than the rest
  // is still walked; strongly clustered points need it set).
  double max_step_mm = 0;
  // Distance from the local curve beyond which a point is an outlier. 0:
  // outlier_factor times the median such distance of all points (which
  // follows the measurement noise), but at least a tenth of the median
  // spacing: below that a deviation is the profile's own sagitta between
  // samples at an edge, not a stray point.
  double outlier_mm = 0;
  double outlier_factor = 8;
};

// A stretch of the profile with no points, between order[after] and
// order[(after + 1) % size]: a link longer than max_step, or a link where
// the walks stopped, longer than two spacings, across which the profile turns
// back by more than max_turn (the ends of a missing edge can be nearer each
// other than max_step, on the two flanks; an edge too coarsely sampled for
// the cone, with no point on its tip, reads the same).
struct SectionGap {
  int after = 0;
  double length_mm = 0;
};

struct OrderedSection {
  std::vector<int> order;          // indices into the input, around the loop
  std::vector<int> rejected;       // indices of rejected points, ascending
  std::vector<SectionGap> gaps;    // in loop order
  int chains = 0;                  // walks joined (1: the walks both ways from the first seed took every point)
  double spacing_mm = 0;           // median nearest-neighbour distance
  double max_step_mm = 0;          // the ones used
  double outlier_mm = 0;
};

// Orders one section's scattered points (3-D; a section need not be planar)
// into a closed loop. The loop starts at a point in the middle of the
// profile's flattest side (the extreme along the second principal axis),
// so a shuffled input gives the same loop. Throws ParameterError ("points")
// for fewer than 8 points, a non-finite point, all points coincident, and
// ("options") for an option out of range.
OrderedSection order_section(const std::vector<Vec3>& points, const SectionOrderOptions& options = {});

// points[order[0]], points[order[1]], ...
std::vector<Vec3> pick(const std::vector<Vec3>& points, const std::vector<int>& order);

// Thinning a section measured far more densely than the rebuild can use
// (issue 43: ten million points), before it is ordered, to points about
// `spacing_mm` apart. The rule: the points are binned in cubic cells half
// the spacing wide; a cell whose block of 3 x 3 x 3 cells holds fewer points
// than the median occupied cell is dropped (a stray lies alone, a measured
// stretch fills its cells and their neighbours, so a gap's end and a cell
// the profile only clips stay); every other cell gives the one of its points
// nearest the coordinate-wise median of them — a measured point, not an
// average, so the deviations reported stay the measurement's and a stray
// among good points is never the one given; of these, in cell order, each is
// kept unless one kept already lies within the spacing, so the kept points
// are one to about two spacings apart along the profile, as even as a
// probe's jittered steps (one per cell left them as close as two cells'
// corners and as far as three cells, and the ordering found gaps there).
// Returns the kept indices, ascending; all of them when the median cell
// holds fewer than 4 points (not dense against the spacing: nothing to
// thin). Throws ParameterError ("spacing") unless spacing_mm > 0.
std::vector<int> thin_section(const std::vector<Vec3>& points, double spacing_mm);

struct OrientedSection {
  std::vector<Vec3> loop;
  bool reversed = false;  // the input order was clockwise about the axis
  int start = 0;          // index in the input loop of the new first point
};

// Makes every loop counter-clockwise seen from the tip of `axis` (the blade's
// stacking direction: all sections then run the same way, §1.1), keeping a
// reversed loop's first point, and starts every loop after the first at its
// point nearest — across the axis — to the previous loop's start, so start
// points follow one line up the blade before §1.3 refines them. Throws
// ParameterError ("axis") for a zero axis and ("loops") for a loop of fewer
// than 3 points or one seen edge-on from the axis (|area · axis| below a
// tenth of |area|: which way it turns is then a guess).
std::vector<OrientedSection> orient_sections(const std::vector<std::vector<Vec3>>& loops, const Vec3& axis);

}  // namespace bliskrun
