#include "core/analysis/curvature_map.h"

#include <cstdio>
#include <utility>

#include "core/analysis/heat_map.h"
#include "core/common/atomic_file.h"
#include "core/common/error.h"

namespace bliskrun {

namespace {

// The K picture's map and labels, shared by the SVG and the PNG.
std::pair<HeatMap, HeatMapOptions> curvature_heat_map(const CurvatureStats& st, const CurvatureMapOptions& o) {
  if (st.map.empty() ||
      st.map.size() != static_cast<size_t>(st.samples_u) * static_cast<size_t>(st.samples_v))
    throw ParameterError("stats", "expected curvature statistics with a map (keep_map = true)");
  HeatMap map;
  map.rows = st.samples_u;
  map.cols = st.samples_v;
  map.values.reserve(st.map.size());
  for (const CurvatureSample& s : st.map) map.values.push_back(s.K);
  HeatMapOptions h;
  h.title = o.title;
  h.value_label = "K (mm^-2)";
  char footer[200];
  std::snprintf(footer, sizeof footer, "K < 0 on %.1f%% of %d x %d samples; K in [%.3e, %.3e]",
                100 * st.negative_K_fraction, st.samples_u, st.samples_v, st.K_min, st.K_max);
  h.footer = footer;
  h.plot_width_px = o.plot_width_px;
  h.plot_height_px = o.plot_height_px;
  h.levels = o.levels;
  return {std::move(map), std::move(h)};
}

}  // namespace

std::string curvature_map_svg(const CurvatureStats& st, const CurvatureMapOptions& o) {
  const auto [map, h] = curvature_heat_map(st, o);
  return heat_map_svg(map, h);
}

void write_curvature_map_png(const CurvatureStats& st, const std::string& path, const CurvatureMapOptions& o) {
  const auto [map, h] = curvature_heat_map(st, o);
  write_heat_map_png(map, path, h);
}

void write_curvature_map_svg(const CurvatureStats& stats, const std::string& path,
                             const CurvatureMapOptions& opts) {
  write_file_atomic(path, curvature_map_svg(stats, opts));
}

}  // namespace bliskrun
