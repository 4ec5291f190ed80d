#pragma once
// A Gaussian-curvature picture like the blisk paper's Fig. 11: K over the
// flank's (u, v) parameter square as an SVG heat map, v (chord) across,
// u (span, hub at the bottom) up, with a colour bar and labels.
//
// The colour scale is diverging and centred on K = 0 (blue K < 0, white 0,
// red K > 0) over [-m, m], m = max |K|, so the saddle region the wheel
// design looks at (§2.2) reads at a glance. Values are quantised to `levels`
// colours and equal neighbours along a row merged into one rectangle, which
// keeps a 100 x 500 map around a few hundred kB. Output bytes depend only on
// the input (fixed number formatting), so pictures can be compared in tests.
#include <string>

#include "core/analysis/curvature_stats.h"

namespace bliskrun {

struct CurvatureMapOptions {
  std::string title = "Gaussian curvature K";
  int plot_width_px = 800;
  int plot_height_px = 320;
  int levels = 64;  // colours in the scale, >= 2
};

// Throws ParameterError if the stats carry no map (keep_map was false) or an
// option is out of range.
std::string curvature_map_svg(const CurvatureStats& stats, const CurvatureMapOptions& opts = {});

// Writes curvature_map_svg(...) with write_file_atomic.
void write_curvature_map_svg(const CurvatureStats& stats, const std::string& path,
                             const CurvatureMapOptions& opts = {});

}  // namespace bliskrun
