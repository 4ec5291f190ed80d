#pragma once
// The Lua-side tool: the immutable core value plus its FCL body, built on
// first use by a collision query and shared after. Shared by wrap_tools.cpp
// (constructors, methods) and wrap_collision.cpp (queries).
#include <memory>
#include <string>

#include "core/collision/collision_world.h"
#include "core/tools/pose.h"
#include "core/tools/tool.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

struct LuaTool {
  Tool tool;
  double collision_tol_mm = 1e-3;  // tessellation tolerance of the FCL body
  std::shared_ptr<const ToolBody> body_cache;

  const ToolBody& body() {
    if (!body_cache) body_cache = std::make_shared<const ToolBody>(tool, collision_tol_mm);
    return *body_cache;
  }
};

// A plan and what its request points to (the tool, the world if one was
// given), kept alive together: the userdata of a planner that keeps nothing
// else (bliskrun.hub_finish, bliskrun.point_mill).
template <class Request, class Result>
struct LuaToolPlan {
  std::shared_ptr<const Tool> tool;
  std::shared_ptr<const CollisionWorld> world;
  Request request;
  std::shared_ptr<const Result> result;
};

// The Tool of a planner's option 'tool' (validated options `o`), copied for
// the plan to keep; otherwise a Lua error "<what>: option 'tool': expected a
// bliskrun.Tool (<kind>)", kind the tool the planner takes ("a flat-end mill").
inline std::shared_ptr<const Tool> tool_option(lua_State* L, const luax::Options& o, const std::string& what,
                                               const std::string& kind) {
  o.push_raw("tool");
  const LuaTool* t = luax::test<LuaTool>(L, -1);
  if (!t) luax::error(L, what + ": option 'tool': expected a bliskrun.Tool (" + kind + ")");
  auto tool = std::make_shared<const Tool>(t->tool);
  lua_pop(L, 1);
  return tool;
}

// The options of a planner that leans a ball end away from the surface and
// turns it sideways until it is clear (bliskrun.hub_finish,
// bliskrun.point_mill), into its request: lean, lean_step, lean_max,
// side_tilt, side_step (degrees; the planner's own defaults `lean_deg`,
// `lean_max_deg`, `side_step_deg`, else 1 and 20), clearance,
// holder_clearance, retract, min_retract and guard_spacing (the request's
// defaults).
template <class Request>
void read_clearing_options(const luax::Options& o, Request& rq, double lean_deg, double lean_max_deg,
                           double side_step_deg) {
  rq.lean_rad = deg_to_rad(o.number("lean", lean_deg));
  rq.lean_step_rad = deg_to_rad(o.number("lean_step", 1));
  rq.lean_max_rad = deg_to_rad(o.number("lean_max", lean_max_deg));
  rq.side_tilt_rad = deg_to_rad(o.number("side_tilt", 20));
  rq.side_step_rad = deg_to_rad(o.number("side_step", side_step_deg));
  rq.clearances.shank_mm = o.number("clearance", rq.clearances.shank_mm);
  rq.clearances.holder_mm = o.number("holder_clearance", rq.clearances.holder_mm);
  rq.links.retract_mm = o.number("retract", rq.links.retract_mm);
  rq.links.min_retract_mm = o.number("min_retract", rq.links.min_retract_mm);
  rq.guard_spacing_mm = o.number("guard_spacing", rq.guard_spacing_mm);
}

// A pose as the Lua tables every planner returns and the posts read:
// {tip = {x, y, z}, axis = {x, y, z}} (mm, unit axis tip -> spindle).
inline void push_pose(lua_State* L, const ToolPose& p) {
  lua_createtable(L, 0, 2);
  luax::set_vec3(L, "tip", p.tip);
  luax::set_vec3(L, "axis", p.axis);
}

// The pose of a table that holds {tip = {x, y, z}, axis = {x, y, z}} among
// other fields (a job move, a plan's pose); the axis is normalised.
inline ToolPose pose_from_table(lua_State* L, int idx, const char* name) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) luax::error(L, std::string(name) + ": expected {tip = {x, y, z}, axis = {x, y, z}}");
  ToolPose p;
  lua_getfield(L, idx, "tip");
  p.tip = luax::check_vec3(L, -1, (std::string(name) + ".tip").c_str());
  lua_getfield(L, idx, "axis");
  p.axis = luax::check_vec3(L, -1, (std::string(name) + ".axis").c_str());
  lua_pop(L, 2);
  const double n = p.axis.norm();
  if (!(n > 1e-12)) luax::error(L, std::string(name) + ".axis: expected a non-zero vector");
  p.axis /= n;
  return p;
}

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaTool> {
  static constexpr const char* name = "bliskrun.Tool";
};
}  // namespace bliskrun::luax
