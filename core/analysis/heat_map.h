#pragma once
// A value over a surface's (u, v) parameter square as an SVG heat map:
// v (chord) across, u (span, hub at the bottom) up, with a colour bar and
// labels. Serves the Gaussian-curvature picture (the blisk paper's Fig. 11)
// and the undercut map (Fig. 15).
//
// The colour scale is diverging and centred on 0 (blue < 0, white 0, red > 0)
// over [-m, m], m = max |value| over the finite values (or `scale_max` when
// set: a run's maps share one scale so two of them compare), so the sign
// reads at a glance; the colour bar's labels have 3 significant digits, no
// exponent. Two kinds of "no value", each with its legend entry:
// +-infinity is "never reached" (a sample no tool came near: plain grey),
// NaN is "not part of this map" (outside a region measured, the gaps of a
// mosaic: white, hatched with grey diagonals). Values are quantised to `levels`
// colours and equal neighbours along a row merged into one rectangle, which
// keeps a 100 x 500 curvature map at a few hundred kB (a 200 x 1000
// undercut map, noisier along the chord, at 2-3 MB). Output bytes depend only on
// the input (fixed number formatting), so pictures can be compared in tests.
#include <string>
#include <vector>

#include "core/common/raster.h"

namespace bliskrun {

struct HeatMap {
  int rows = 0, cols = 0;      // rows along u, cols along v
  std::vector<double> values;  // row-major, rows x cols
  double at(int i, int j) const { return values[static_cast<size_t>(i) * cols + j]; }
};

// Text over the plot, e.g. a mosaic tile's surface: its top-left corner at
// fraction v of the plot's width from the left and u of its height from the
// bottom; drawn on a white box.
struct HeatMapLabel {
  double v = 0, u = 1;
  std::string text;
};

struct HeatMapOptions {
  std::string title;
  std::string value_label;  // over the colour bar, e.g. "K (mm^-2)"
  std::string footer;       // one line under the plot
  // The axes: v across, u up (a flank's chord and span; an edge region's
  // span and the way round the edge).
  std::string v_label = "v (chord)";
  std::string u_label = "u (span, hub to tip)";
  // Ticks 0 .. 1 along both axes; off where the axes are not one
  // parameter (a mosaic of several surfaces).
  bool fraction_ticks = true;
  std::vector<HeatMapLabel> labels;
  double scale_max = 0;     // > 0: fixed scale [-scale_max, scale_max]; values beyond are clamped
  int plot_width_px = 800;
  int plot_height_px = 320;
  int levels = 64;          // colours in the scale, >= 2
};

// Throws ParameterError for an empty or mis-sized map or an option out of range.
std::string heat_map_svg(const HeatMap& map, const HeatMapOptions& opts);
// Writes heat_map_svg(...) with write_file_atomic.
void write_heat_map_svg(const HeatMap& map, const std::string& path, const HeatMapOptions& opts);

// The same picture as a raster (one pixel per plot pixel, each showing the
// nearest cell), so a 200 x 1000 map costs what its picture size costs, not
// what its cell count costs. Same colours, layout and labels as the SVG, drawn
// with raster.h's built-in bitmap font.
//
// Where things are in the PNG, so tests and readers can find the plot: the
// plot occupies [plot_x, plot_x + plot_width_px) x [plot_y, plot_y + plot_height_px),
// u = 0 (hub) at the bottom row, v = 0 at the left column.
struct HeatMapRasterLayout {
  int plot_x = 0, plot_y = 0;
  int bar_x = 0, bar_width = 0;  // colour bar, same rows as the plot, -m at the bottom
  int legend_y = 0;              // top of the legend line (never reached, not part of this map)
  int width = 0, height = 0;     // whole picture
};
HeatMapRasterLayout heat_map_raster_layout(const HeatMapOptions& opts);
// The scale's colour for `value` on [-m, m] quantised to `levels` colours;
// grey (187, 187, 187) for +-infinity (never reached), white for NaN (not
// part of the map: the background of its hatching, heat_map_hatch). The
// SVG uses the same colours.
Rgb heat_map_colour(double value, double m, int levels);
// "Not part of this map" at picture pixel (x, y): white with a grey
// (150, 150, 150) diagonal every 6 pixels.
Rgb heat_map_hatch(int x, int y);
// The scale's half range m the picture uses: opts.scale_max if set, else the
// largest |finite value| (1 if all are zero).
double heat_map_scale(const HeatMap& map, const HeatMapOptions& opts);
RgbImage heat_map_raster(const HeatMap& map, const HeatMapOptions& opts);
// Writes encode_png(heat_map_raster(...)) with write_file_atomic.
void write_heat_map_png(const HeatMap& map, const std::string& path, const HeatMapOptions& opts);

}  // namespace bliskrun
