#pragma once
// The Lua UndercutMap (sim.map of a simulation): shared by the wrappers that
// make one (planning, flank milling, bliskrun.simulate) and the VTK writer
// that paints it on a surface.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/analysis/heat_map.h"
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

// The map's sample nearest to grid point (i, j) of a rows x cols grid over
// the same (u, v) square (a surface drawn at another resolution than its map).
inline double undercut_map_nearest(const HeatMap& m, int i, int rows, int j, int cols) {
  const int mi = rows > 1 ? static_cast<int>(std::lround(double(i) * (m.rows - 1) / (rows - 1))) : 0;
  const int mj = cols > 1 ? static_cast<int>(std::lround(double(j) * (m.cols - 1) / (cols - 1))) : 0;
  return m.at(mi, mj);
}

}  // namespace bliskrun::lua_api
