#pragma once
// Lua side of core/collision shared with the planners: the world userdata
// and the tilt-until-clear options (CollisionWorld:tilt and every planner
// that runs the interference loop take the same keys).
#include <memory>
#include <string>
#include <vector>

#include "core/collision/tilt.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

struct LuaWorld {
  std::shared_ptr<const CollisionWorld> world;
};

// clearance, lead, tilt, lead_step, lead_max, allow_tilt, tilt_step,
// tilt_range, motion_tol, axis_limit, machine (see docs/lua_api.md).
std::vector<luax::Field> tilt_option_fields();
// An axis_limit table {name=, rotary_axis=, reference=, min=, max=} at idx.
AxisLimit read_axis_limit(lua_State* L, int idx, const std::string& what);
// Reads those keys from validated options; `what` names the call in errors.
TiltSettings read_tilt_settings(lua_State* L, const luax::Options& o, const std::string& what);
// The world of a planner's option 'world' (validated options `o`); otherwise
// a Lua error "<what>: option 'world': expected a bliskrun.CollisionWorld<hint>".
std::shared_ptr<const CollisionWorld> world_option(lua_State* L, const luax::Options& o, const std::string& what,
                                                   const std::string& hint = "");

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaWorld> {
  static constexpr const char* name = "bliskrun.CollisionWorld";
};
}  // namespace bliskrun::luax
