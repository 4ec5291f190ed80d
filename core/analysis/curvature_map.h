#pragma once
// A Gaussian-curvature picture like the blisk paper's Fig. 11: K over the
// flank's (u, v) parameter square, drawn by heat_map.h (diverging scale
// centred on K = 0, blue K < 0, so the saddle region the wheel design looks
// at, §2.2, reads at a glance). Output bytes depend only on the input.
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
// The same picture as a PNG (heat_map.h's raster), written atomically.
void write_curvature_map_png(const CurvatureStats& stats, const std::string& path,
                             const CurvatureMapOptions& opts = {});

}  // namespace bliskrun
