// bliskrun.channel_rough{...}: notching and widening of one impeller channel
// (impeller paper §4.1–4.2, core/planning/channel_roughing.h) — the channel
// between two blade faces opened in its middle in depth levels, then widened
// towards both faces along the hub, every pose, motion and link proved.
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/planning/channel_roughing.h"
#include "core/toolpath/move.h"
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

// The option fields of one channel (bliskrun.channel_rough, and each entry of
// bliskrun.channel_rough_all's channels).
std::vector<Field> channel_fields() {
  return {Field{"left", Kind::Any, true, std::nullopt, std::nullopt,
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
          number_field("stock", "stock left on the faces (and the hub, unless hub_stock), mm; default 0.3", 0, 100),
          number_field("hub_stock",
                       "stock left on the hub, mm, at most the stock; default the stock. 0: the passes on the hub "
                       "finish it (the world must then hold the hub for the shank and holder only, and for the "
                       "cutter a surface inside it)",
                       0, 100),
          number_field("hub_chord_tol",
                       "how far the ball centre may leave the hub's offset between stations on the hub, mm; "
                       "default 0.005 + hub_stock / 2 (poses are inserted)",
                       1e-6, 100),
          number_field("scallop", "scallop height on the hub between widening paths, mm; default 0.01", 1e-6),
          number_field("depth_step", "deepest step between notch levels, mm; default 5", 1e-3, 1000),
          Field{"widen", Kind::Boolean, false, std::nullopt, std::nullopt, "widen after notching; default true", {}},
          number_field("clearance", "clearance of the shank and holder, mm; default 0.5", 0, 100),
          number_field("cutter_clearance",
                       "clearance of the cutter from every surface, mm; default half the stock (the ball keeps the "
                       "whole stock by construction; the rest absorbs the world's tessellation)",
                       0, 100),
          number_field("link_retract", "how far links and leads go up the tool axis, mm; default 5", 0.01, 1000)};
}

// One channel's request and what it points to, kept alive while it is
// planned (the faces, hub and world are shared read-only between channels).
struct ChannelCall {
  ChannelRequest rq;
  std::shared_ptr<const Surface> left, right, hub;
  std::shared_ptr<const CollisionWorld> world;
  std::unique_ptr<FlankCutter> cutter;
};

// Reads the option table at idx into a request (Lua errors name `what`);
// call inside luax::guarded (the cutter's checks throw).
std::unique_ptr<ChannelCall> read_channel(lua_State* L, int idx, const std::string& what) {
  const luax::Options o(L, idx, what, channel_fields());
  auto call = std::make_unique<ChannelCall>();
  ChannelRequest& rq = call->rq;
  call->left = surface_option(L, o, "left");
  call->right = surface_option(L, o, "right");
  rq.left.face = call->left.get();
  rq.right.face = call->right.get();
  chord_range(L, o, "left_v", rq.left);
  chord_range(L, o, "right_v", rq.right);
  call->hub = surface_option(L, o, "hub");
  rq.hub = dynamic_cast<const SurfaceOfRevolution*>(call->hub.get());
  if (!rq.hub) luax::error(L, what + ": option 'hub': expected a surface of revolution (impeller:hub())");
  o.push_raw("tool");
  LuaTool& tool = luax::check<LuaTool>(L, -1);
  lua_pop(L, 1);
  o.push_raw("world");
  call->world = luax::check<LuaWorld>(L, -1).world;
  lua_pop(L, 1);
  if (!o.has("ball_radius")) luax::error(L, what + ": missing required option 'ball_radius'");
  call->cutter = std::make_unique<FlankCutter>(tool.tool, o.number("ball_radius", 0));
  rq.cutter = call->cutter.get();
  rq.world = call->world.get();
  rq.body = &tool.body();  // built here, on the Lua thread, before any worker reads it
  rq.stations = static_cast<int>(o.integer("stations", 41));
  rq.stock_mm = o.number("stock", 0.3);
  rq.hub_stock_mm = o.number("hub_stock", rq.stock_mm);
  if (rq.hub_stock_mm > rq.stock_mm) luax::error(L, what + ": option 'hub_stock': expected at most the stock");
  // A roughing pass's ball may dip into half the stock it leaves on the hub
  // (the cutter's clearance in the world still holds); a finishing pass
  // keeps to 5 um.
  rq.hub_chord_tol_mm = o.number("hub_chord_tol", 0.005 + 0.5 * rq.hub_stock_mm);
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
  return call;
}

// Pushes a plan as the table bliskrun.channel_rough returns.
void push_channel_plan(lua_State* L, const ChannelPlan& plan) {
  lua_createtable(L, 0, 20);
  luax::set_number(L, "notch_levels", plan.notch_levels);
  luax::set_number(L, "widen_left", plan.widen_left);
  luax::set_number(L, "widen_right", plan.widen_right);
  luax::set_number(L, "paths_added", plan.paths_added);
  luax::set_number(L, "inserted", plan.inserted);
  luax::set_number(L, "hub_stock", plan.hub_stock_mm);
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
  const Toolpath moves = channel_moves(plan);
  lua_createtable(L, static_cast<int>(moves.size()), 0);
  for (size_t i = 0; i < moves.size(); ++i) {
    push_pose(L, moves[i].pose);
    luax::set_string(L, "kind", to_string(moves[i].kind));
    luax::set_string(L, "motion", moves[i].motion);
    luax::set_number(L, "row", moves[i].row + 1);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "moves");
}

// bliskrun.channel_rough{left=, right=, hub=, tool=, ball_radius=, world=, ...} -> plan table
int w_channel_rough(lua_State* L) {
  return luax::guarded(L, [&] {
    const std::unique_ptr<ChannelCall> call = read_channel(L, 1, "bliskrun.channel_rough");
    push_channel_plan(L, plan_channel(call->rq));
    return 1;
  });
}

// bliskrun.channel_rough_all{channels = {{...}, ...}, threads=} -> {plan, ...}:
// the channels planned on --threads workers, plans in the order given (the
// same for any thread count).
int w_channel_rough_all(lua_State* L) {
  return luax::guarded(L, [&] {
    const std::string what = "bliskrun.channel_rough_all";
    const luax::Options o(
        L, 1, what,
        {Field{"channels", Kind::Table, true, std::nullopt, std::nullopt,
               "list of option tables as bliskrun.channel_rough takes", {}},
         Field{"threads", Kind::Integer, false, 1, 256,
               "worker threads (default: the run's --threads); plans do not depend on it", {}}});
    o.push_raw("channels");
    const int list = lua_gettop(L);
    const lua_Integer n = luaL_len(L, list);
    if (n < 1) luax::error(L, what + ": option 'channels': expected at least one channel");
    std::vector<std::unique_ptr<ChannelCall>> calls;
    std::vector<ChannelRequest> requests;
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, list, i);
      calls.push_back(read_channel(L, lua_gettop(L), what + " channels[" + std::to_string(i) + "]"));
      requests.push_back(calls.back()->rq);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    const int threads = static_cast<int>(o.integer("threads", context(L).options.threads));
    const std::vector<ChannelPlan> plans = plan_channels(requests, threads, context(L).progress);
    lua_createtable(L, static_cast<int>(plans.size()), 0);
    for (size_t k = 0; k < plans.size(); ++k) {
      push_channel_plan(L, plans[k]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    return 1;
  });
}

}  // namespace

void open_channel(lua_State* L) {
  static const luaL_Reg functions[] = {
      {"channel_rough", w_channel_rough}, {"channel_rough_all", w_channel_rough_all}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
