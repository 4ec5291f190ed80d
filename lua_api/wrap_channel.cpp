// bliskrun.channel_rough{...}: notching and widening of one impeller channel
// (impeller paper §4.1–4.2, core/planning/channel_roughing.h) — the channel
// between two blade faces opened in its middle in depth levels, then widened
// towards both faces along the hub, every pose, motion and link proved.
#include <algorithm>
#include <memory>
#include <string>

#include "core/common/error.h"
#include "core/planning/channel_roughing.h"
#include "lua_api/lua_tool.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_collision.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;
using luax::number_field;

// A face's part of the chord, {inlet v, outlet v}; {0, 1} when absent.
void chord_range(lua_State* L, const luax::Options& o, const char* key, ChannelFace& face) {
  if (!o.has(key)) return;
  o.push_raw(key);
  const std::string what = std::string("bliskrun.channel_rough: option '") + key + "'";
  if (luaL_len(L, -1) != 2) luax::error(L, what + ": expected {v at the inlet, v at the outlet}");
  double v[2];
  for (int i = 0; i < 2; ++i) {
    lua_rawgeti(L, -1, i + 1);
    int ok = 0;
    v[i] = lua_tonumberx(L, -1, &ok);
    lua_pop(L, 1);
    if (!ok || !(v[i] >= 0 && v[i] <= 1)) luax::error(L, what + ": expected two face parameters in [0, 1]");
  }
  lua_pop(L, 1);
  if (v[0] == v[1]) luax::error(L, what + ": the inlet and outlet parameters are equal");
  face.v_inlet = v[0];
  face.v_outlet = v[1];
}

std::shared_ptr<const Surface> surface_option(lua_State* L, const luax::Options& o, const char* key) {
  o.push_raw(key);
  std::shared_ptr<const Surface> s = luax::check<SurfaceHandle>(L, -1).surface;
  lua_pop(L, 1);
  return s;
}

// bliskrun.channel_rough{left=, right=, hub=, tool=, ball_radius=, world=, ...} -> plan table
int w_channel_rough(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.channel_rough",
      {Field{"left", Kind::Any, true, std::nullopt, std::nullopt,
             "blade face bounding the channel on one side (normal out of the material, into the channel)", {}},
       Field{"right", Kind::Any, true, std::nullopt, std::nullopt, "blade face on the other side", {}},
       Field{"left_v", Kind::Table, false, std::nullopt, std::nullopt,
             "{v at the inlet, v at the outlet} of the left face's part of the channel; default {0, 1}", {}},
       Field{"right_v", Kind::Table, false, std::nullopt, std::nullopt, "the same for the right face", {}},
       Field{"hub", Kind::Any, true, std::nullopt, std::nullopt, "hub surface of revolution (impeller:hub())", {}},
       Field{"tool", Kind::Any, true, std::nullopt, std::nullopt, "ball-end or tapered ball-end mill", {}},
       number_field("ball_radius", "radius of the tool's tip ball, mm (required)", 1e-6),
       Field{"world", Kind::Any, true, std::nullopt, std::nullopt,
             "CollisionWorld: both faces, the hub and every other surface the tool may reach", {}},
       Field{"stations", Kind::Integer, false, 2, 100000, "stations along the channel, inlet to outlet; default 41", {}},
       number_field("stock", "stock left on the hub and the faces, mm; default 0.3", 0, 100),
       number_field("scallop", "scallop height on the hub between widening paths, mm; default 0.01", 1e-6),
       number_field("depth_step", "deepest step between notch levels, mm; default 5", 1e-3, 1000),
       Field{"widen", Kind::Boolean, false, std::nullopt, std::nullopt, "widen after notching; default true", {}},
       number_field("clearance", "clearance of the shank and holder, mm; default 0.5", 0, 100),
       number_field("cutter_clearance",
                    "clearance of the cutter from every surface, mm; default half the stock (the ball keeps the "
                    "whole stock by construction; the rest absorbs the world's tessellation)",
                    0, 100),
       number_field("link_retract", "how far links and leads go up the tool axis, mm; default 5", 0.01, 1000)});
  ChannelRequest rq;
  const std::shared_ptr<const Surface> left = surface_option(L, o, "left"), right = surface_option(L, o, "right");
  rq.left.face = left.get();
  rq.right.face = right.get();
  chord_range(L, o, "left_v", rq.left);
  chord_range(L, o, "right_v", rq.right);
  const std::shared_ptr<const Surface> hub_surface = surface_option(L, o, "hub");
  rq.hub = dynamic_cast<const SurfaceOfRevolution*>(hub_surface.get());
  if (!rq.hub) luax::error(L, "bliskrun.channel_rough: option 'hub': expected a surface of revolution (impeller:hub())");
  o.push_raw("tool");
  LuaTool& tool = luax::check<LuaTool>(L, -1);
  lua_pop(L, 1);
  o.push_raw("world");
  const std::shared_ptr<const CollisionWorld> world = luax::check<LuaWorld>(L, -1).world;
  lua_pop(L, 1);
  if (!o.has("ball_radius")) luax::error(L, "bliskrun.channel_rough: missing required option 'ball_radius'");
  return luax::guarded(L, [&] {
    const FlankCutter cutter(tool.tool, o.number("ball_radius", 0));
    rq.cutter = &cutter;
    rq.world = world.get();
    rq.body = &tool.body();
    rq.stations = static_cast<int>(o.integer("stations", 41));
    rq.stock_mm = o.number("stock", 0.3);
    rq.scallop_mm = o.number("scallop", 0.01);
    rq.depth_step_mm = o.number("depth_step", 5);
    rq.widen = o.boolean("widen", true);
    rq.clearances.shank_mm = rq.clearances.holder_mm = o.number("clearance", 0.5);
    rq.clearances.cutter_mm = o.number("cutter_clearance", 0.5 * rq.stock_mm);
    if (rq.clearances.cutter_mm > rq.stock_mm)
      throw ParameterError("cutter_clearance", "expected at most the stock (" + std::to_string(rq.stock_mm) +
                                                   " mm): the ball is the stock away from hub and faces");
    rq.link.retract_mm = o.number("link_retract", 5);
    rq.link.min_retract_mm = std::min(rq.link.min_retract_mm, rq.link.retract_mm);
    const ChannelPlan plan = plan_channel(rq);

    lua_createtable(L, 0, 20);
    luax::set_number(L, "notch_levels", plan.notch_levels);
    luax::set_number(L, "widen_left", plan.widen_left);
    luax::set_number(L, "widen_right", plan.widen_right);
    luax::set_number(L, "paths_added", plan.paths_added);
    luax::set_number(L, "step_over", plan.step_over_mm);
    luax::set_number(L, "outlet_width_left", plan.outlet_width_left_mm);
    luax::set_number(L, "outlet_width_right", plan.outlet_width_right_mm);
    luax::set_number(L, "scallop_max", plan.scallop_max_mm);
    luax::set_number(L, "scallop_outlet", plan.scallop_outlet_mm);
    luax::set_number(L, "deepest_step", plan.deepest_step_mm);
    luax::set_number(L, "poses", static_cast<double>(plan.poses));
    luax::set_number(L, "links", static_cast<double>(plan.links.size()));
    luax::set_number(L, "turned", static_cast<double>(plan.turned));
    luax::set_bool(L, "complete", plan.complete);
    luax::set_string(L, "stopped", plan.stopped);
    lua_createtable(L, static_cast<int>(plan.passes.size()), 0);
    for (size_t i = 0; i < plan.passes.size(); ++i) {
      const ChannelPass& p = plan.passes[i];
      lua_createtable(L, 0, 5);
      luax::set_string(L, "kind", to_string(p.kind));
      luax::set_number(L, "index", p.index);
      luax::set_number(L, "poses", static_cast<double>(p.poses.size()));
      luax::set_number(L, "t_first", p.t.front());
      luax::set_number(L, "t_last", p.t.back());
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "passes");
    lua_createtable(L, static_cast<int>(plan.refusals.size()), 0);
    for (size_t i = 0; i < plan.refusals.size(); ++i) {
      const ChannelRefusal& r = plan.refusals[i];
      lua_createtable(L, 0, 4);
      luax::set_string(L, "kind", to_string(r.kind));
      luax::set_number(L, "index", r.index);
      luax::set_number(L, "t", r.t);
      luax::set_string(L, "reason", r.reason);
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "refusals");
    // The toolpath in the form bliskrun.write_vtk and the posts take; row =
    // the pass (1-based).
    const std::vector<ChannelMove> moves = channel_moves(plan);
    lua_createtable(L, static_cast<int>(moves.size()), 0);
    for (size_t i = 0; i < moves.size(); ++i) {
      push_pose(L, moves[i].pose);
      luax::set_string(L, "kind", moves[i].feed ? "feed" : "rapid");
      luax::set_string(L, "motion", moves[i].motion);
      luax::set_number(L, "row", moves[i].pass + 1);
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "moves");
    return 1;
  });
}

}  // namespace

void open_channel(lua_State* L) {
  static const luaL_Reg functions[] = {{"channel_rough", w_channel_rough}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
