#pragma once
// The Lua UndercutMap (sim.map of a simulation): shared by the wrappers that
// make one (planning, flank milling, bliskrun.simulate) and the VTK writer
// that paints it on a surface; and the fields of the simulation's result
// those wrappers report alike.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/analysis/heat_map.h"
#include "core/sim/undercut.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

// The undercut over the simulated window, rows along u, columns along v;
// values in mm (+inf never reached, NaN not part of the map). A mosaic
// (bliskrun.map_mosaic) carries its tiles' labels and its own axis names.
struct LuaUndercutMap {
  HeatMap map;
  std::string footer;
  std::vector<HeatMapLabel> labels;
  std::string u_label, v_label;  // empty: HeatMapOptions' defaults (span up, chord across)
  bool fraction_ticks = true;
};

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaUndercutMap> {
  static constexpr const char* name = "bliskrun.UndercutMap";
};
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {

// Pushes a new UndercutMap of rows x cols values (row-major).
inline void push_undercut_map(lua_State* L, int rows, int cols, std::vector<double> values, std::string footer) {
  LuaUndercutMap m;
  m.map.rows = rows;
  m.map.cols = cols;
  m.map.values = std::move(values);
  m.footer = std::move(footer);
  luax::push_new(L, std::move(m));
}

// t.undercut_max, undercut_mean, undercut_median, undercut_std and overcut
// (mm) of a simulation's result.
inline void set_undercut_stats(lua_State* L, const UndercutResult& u) {
  luax::set_number(L, "undercut_max", u.undercut_max_mm);
  luax::set_number(L, "undercut_mean", u.undercut_mean_mm);
  luax::set_number(L, "undercut_median", u.undercut_median_mm);
  luax::set_number(L, "undercut_std", u.undercut_std_mm);
  luax::set_number(L, "overcut", u.overcut_mm);
}

// t.untouched (samples no tool reached), samples and tool_positions of a
// simulation's result.
inline void set_undercut_counts(lua_State* L, const UndercutResult& u) {
  luax::set_integer(L, "untouched", u.untouched);
  luax::set_integer(L, "samples", static_cast<lua_Integer>(u.samples_u) * u.samples_v);
  luax::set_integer(L, "tool_positions", u.tool_positions);
}

// The map's sample nearest to grid point (i, j) of a rows x cols grid over
// the same (u, v) square (a surface drawn at another resolution than its map).
inline double undercut_map_nearest(const HeatMap& m, int i, int rows, int j, int cols) {
  const int mi = rows > 1 ? static_cast<int>(std::lround(double(i) * (m.rows - 1) / (rows - 1))) : 0;
  const int mj = cols > 1 ? static_cast<int>(std::lround(double(j) * (m.cols - 1) / (cols - 1))) : 0;
  return m.at(mi, mj);
}

}  // namespace bliskrun::lua_api
