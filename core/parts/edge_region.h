#pragma once
// The leading- or trailing-edge region of a blade as a surface of its own
// (edge paper §3.2, SPEC §6.2): the round between the two flanks, from hub
// to tip, extended onto both flanks by an overlap margin so that the edge
// operation and the flank operation leave no ridge between them.
//
// Parameters (the convention, not the flanks'): v along the span
// (v = 0 at the flanks' u = span_u0, v = 1 at span_u1), u around the edge,
// so that rows at constant v run around the edge as the paper's rows at
// constant v do (§3.2: "單向走刀沿著等 v 參數(shù)線"). u runs so that pu x pv
// points out of the material: it starts on the flank whose edge end is at
// its v = 0 (the pressure flank at the LE, the suction flank at the TE for
// the built-in blisk and for loft_blade's grids), goes round the edge and
// ends on the other flank.
//
// Construction, where the flanks end at the round (the built-in blisk): the built-in blisk's exact flanks, lofted
// blades and grids (anything given as two flank surfaces that end where the
// edge round starts): at each span, the edge round is the circle tangent to
// both flanks at their ends (centre and radius by least squares from the
// two end points and normals; the misfit is reported), the arc swept from
// the first flank's end normal round to the second's (the small out-of-plane
// part of a twisted blade's end normals blended linearly along the arc), and
// the flanks' last `overlap_mm` (arc length) on either side. The points are
// sampled on a grid (uniform in arc length around, uniform in span) and
// interpolated by a bicubic B-spline (core/geometry interpolate_grid); the
// spline's deviation from the construction between the samples is measured
// and reported.
//
// Where the two flanks meet at the edge point instead (ends within 0.01 mm:
// blades lofted from section data with edge_margin 0 and cosine columns,
// core/parts/blade_model.h) they carry the data's own round, and no circle is
// constructed: the region is each flank's last stretch, walked by arc length
// from the edge point — the round (until the section's curvature falls below
// half the edge point's) and `overlap_mm` past it. A circle tangent to two
// flank ends at a chord-fraction margin does not fit such data: on Rotor 67
// the two ends' centres were 0.25-0.9 mm apart whatever the margin, and the
// arc between them stepped onto the flanks.
#include <memory>
#include <string>

#include "core/geometry/surface.h"

namespace bliskrun {

struct EdgeRegionRequest {
  std::shared_ptr<const Surface> first;   // flank whose edge end is at v = 0
  std::shared_ptr<const Surface> second;  // flank whose edge end is at v = 1
  double overlap_mm = 0.3;                // onto each flank, arc length
  double span_u0 = 0, span_u1 = 1;        // flank u range covered (v = 0..1)
  int samples_around = 161;               // grid columns of the construction
  int samples_span = 81;
};

struct EdgeRegion {
  std::shared_ptr<const Surface> surface;  // u around, v span
  // Where the round starts and ends on u at each end of the span (the
  // overlap on the flanks is u < round_u0 and u > round_u1), as the
  // smallest/largest over the sampled spans.
  double round_u0 = 0, round_u1 = 1;
  double overlap_mm = 0;          // measured arc length on each flank, smallest over the spans
  double radius_min_mm = 0, radius_max_mm = 0;  // edge-circle radius over the span
  double circle_misfit_mm = 0;    // largest distance between the two flanks' circle centres
                                  // (flanks that meet: between their ends)
  bool flanks_meet = false;       // the flanks carry the round (no circle constructed)
  double crease_deg = 0;          // flanks that meet: largest angle between their normals there
  double fit_deviation_mm = 0;    // largest spline deviation from the construction between samples
};

// Throws ParameterError for missing flanks, overlap_mm < 0, span range out of
// [0, 1] or empty, fewer than 8 samples around or 4 along the span, and
// Error when the two flank ends do not bound a round (parallel normals).
EdgeRegion build_edge_region(const EdgeRegionRequest& request);

}  // namespace bliskrun
