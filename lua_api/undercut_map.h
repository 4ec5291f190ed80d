#pragma once
// The Lua UndercutMap (sim.map of a simulation): shared by the planning
// wrapper that makes it and the VTK writer that paints it on a surface.
#include <string>

#include "core/analysis/heat_map.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

// The undercut over the simulated window, rows along u, columns along v.
struct LuaUndercutMap {
  HeatMap map;
  std::string footer;
};

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaUndercutMap> {
  static constexpr const char* name = "bliskrun.UndercutMap";
};
}  // namespace bliskrun::luax
