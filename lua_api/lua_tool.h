#pragma once
// The Lua-side tool: the immutable core value plus its FCL body, built on
// first use by a collision query and shared after. Shared by wrap_tools.cpp
// (constructors, methods) and wrap_collision.cpp (queries).
#include <memory>

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

// A pose as the Lua tables every planner returns and the posts read:
// {tip = {x, y, z}, axis = {x, y, z}} (mm, unit axis tip -> spindle).
inline void push_pose(lua_State* L, const ToolPose& p) {
  lua_createtable(L, 0, 2);
  luax::set_vec3(L, "tip", p.tip);
  luax::set_vec3(L, "axis", p.axis);
}

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaTool> {
  static constexpr const char* name = "bliskrun.Tool";
};
}  // namespace bliskrun::luax
