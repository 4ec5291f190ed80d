// bliskrun.channel_rough{...}: notching and widening of one impeller channel
// (impeller paper §4.1–4.2, core/planning/channel_roughing.h) — the channel
// between two blade faces opened in its middle in depth levels, then widened
// towards both faces along the hub, every pose, motion and link proved.
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/planning/channel_levels.h"
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

// The fields every channel plan's table has (both strategies): what was
// proved, the passes, refusals and moves, into the table on top.
void set_channel_path(lua_State* L, const ChannelPath& plan) {
  luax::set_number(L, "poses", static_cast<double>(plan.poses));
  luax::set_number(L, "links", static_cast<double>(plan.links.size()));
  long steps = 0;
  for (const PlannedLink& link : plan.links) steps += link.via.empty() ? 1 : 0;
  luax::set_number(L, "steps", static_cast<double>(steps));
  luax::set_number(L, "turned", static_cast<double>(plan.turned));
  luax::set_number(L, "inserted", static_cast<double>(plan.inserted));
  luax::set_bool(L, "complete", plan.complete);
  luax::set_string(L, "stopped", plan.stopped);
  lua_createtable(L, static_cast<int>(plan.passes.size()), 0);
  for (size_t i = 0; i < plan.passes.size(); ++i) {
    const ChannelPass& p = plan.passes[i];
    lua_createtable(L, 0, 6);
    luax::set_string(L, "kind", to_string(p.kind));
    luax::set_number(L, "index", p.index);
    if (p.level > 0) luax::set_number(L, "level", p.level);
    luax::set_number(L, "poses", static_cast<double>(p.poses.size()));
    luax::set_number(L, "t_first", p.t.front());
    luax::set_number(L, "t_last", p.t.back());
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "passes");
  lua_createtable(L, static_cast<int>(plan.refusals.size()), 0);
  for (size_t i = 0; i < plan.refusals.size(); ++i) {
    const ChannelRefusal& r = plan.refusals[i];
    lua_createtable(L, 0, 5);
    luax::set_string(L, "kind", to_string(r.kind));
    luax::set_number(L, "index", r.index);
    if (r.level > 0) luax::set_number(L, "level", r.level);
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

// Pushes a plan as the table bliskrun.channel_rough returns.
void push_channel_plan(lua_State* L, const ChannelPlan& plan) {
  lua_createtable(L, 0, 20);
  luax::set_number(L, "notch_levels", plan.notch_levels);
  luax::set_number(L, "widen_left", plan.widen_left);
  luax::set_number(L, "widen_right", plan.widen_right);
  luax::set_number(L, "paths_added", plan.paths_added);
  luax::set_number(L, "hub_stock", plan.hub_stock_mm);
  luax::set_number(L, "step_over", plan.step_over_mm);
  luax::set_number(L, "outlet_width_left", plan.outlet_width_left_mm);
  luax::set_number(L, "outlet_width_right", plan.outlet_width_right_mm);
  luax::set_number(L, "scallop_max", plan.scallop_max_mm);
  luax::set_number(L, "scallop_outlet", plan.scallop_outlet_mm);
  luax::set_number(L, "deepest_step", plan.deepest_step_mm);
  set_channel_path(L, plan);
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

// bliskrun.channel_levels{...}: a blisk channel roughed in levels
// (core/planning/channel_levels.h).
std::vector<Field> levels_fields() {
  return {Field{"left", Kind::Any, true, std::nullopt, std::nullopt,
                "blade face bounding the channel on one side (normal out of the material, into the channel)", {}},
          Field{"right", Kind::Any, true, std::nullopt, std::nullopt, "blade face on the other side", {}},
          Field{"left_v", Kind::Table, false, std::nullopt, std::nullopt,
                "{v at the inlet, v at the outlet} of the left face's part of the channel; default {0, 1}", {}},
          Field{"right_v", Kind::Table, false, std::nullopt, std::nullopt, "the same for the right face", {}},
          Field{"left_blade", Kind::Table, false, std::nullopt, std::nullopt,
                "the rest of the left face's blade (its edge rounds, its other flank): surfaces the contacts keep "
                "the stock off where the ball passes the face's ends",
                {}},
          Field{"right_blade", Kind::Table, false, std::nullopt, std::nullopt, "the same for the right face", {}},
          Field{"hub", Kind::Any, true, std::nullopt, std::nullopt, "hub surface of revolution (blisk:hub())", {}},
          Field{"top", Kind::Any, true, std::nullopt, std::nullopt,
                "the blank's top over the channel, a surface of revolution (blisk:casing())", {}},
          Field{"tool", Kind::Any, true, std::nullopt, std::nullopt, "ball-end or tapered ball-end mill", {}},
          number_field("ball_radius", "radius of the tool's tip ball, mm (required)", 1e-6),
          Field{"world", Kind::Any, true, std::nullopt, std::nullopt,
                "CollisionWorld: both faces, the blades beyond them and the hub (blisk_world.around_channel)", {}},
          Field{"stations", Kind::Integer, false, 2, 100000,
                "stations per level, inlet to outlet, of the paths that leave the stock; default 41", {}},
          Field{"interior_stations", Kind::Integer, false, 2, 100000,
                "how many of them the paths between run through; default 11", {}},
          number_field("stock", "stock left on both faces (and the hub, unless hub_stock), mm; default 0.5", 0, 100),
          number_field("hub_stock", "stock left on the hub, mm, at most the stock; default the stock", 0, 100),
          number_field("step_down", "largest depth between levels (axial engagement), mm; default 1", 1e-3, 1000),
          number_field("step_over",
                       "largest distance between neighbouring paths (radial engagement), mm, at most the ball's "
                       "diameter; default 2",
                       1e-3, 1000),
          number_field("scallop", "cusp over the stock on the faces between levels and on the hub, mm; default 0.03",
                       1e-6),
          number_field("chord_tol", "contact paths and the hub level between stations, mm; default 0.005", 1e-6, 10),
          number_field("tilt", "contact axes' lean off the face beyond the cone's half angle, degrees; default 3", 0, 44),
          number_field("clearance", "clearance of the shank and holder over the stock, mm; default 0.5", 0, 100),
          number_field("allowance",
                       "how far inside the stock the cutter is let come by the world's check (its tessellation, "
                       "the motion tolerance), mm; default 0.035: the cutter's clearance is the hub stock less it",
                       0, 100),
          number_field("link_retract", "how far links and leads go up the tool axis, mm; default 5", 0.01, 1000),
          Field{"threads", Kind::Integer, false, 1, 256,
                "worker threads (default: the run's --threads); the plan does not depend on it", {}}};
}

void set_pair(lua_State* L, const char* key, const double (&v)[2]) { luax::set_numbers(L, key, {v[0], v[1]}); }

void set_list(lua_State* L, const char* key, const std::vector<int>& v) {
  lua_createtable(L, static_cast<int>(v.size()), 0);
  for (size_t i = 0; i < v.size(); ++i) {
    lua_pushinteger(L, v[i]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, key);
}

// bliskrun.channel_levels{left=, right=, hub=, top=, tool=, ball_radius=, world=, ...} -> plan table
int w_channel_levels(lua_State* L) {
  return luax::guarded(L, [&] {
    const std::string what = "bliskrun.channel_levels";
    const luax::Options o(L, 1, what, levels_fields());
    ChannelLevelsRequest rq;
    const std::shared_ptr<const Surface> left = surface_option(L, o, "left"), right = surface_option(L, o, "right");
    rq.left.face = left.get();
    rq.right.face = right.get();
    chord_range(L, o, "left_v", rq.left);
    chord_range(L, o, "right_v", rq.right);
    std::vector<std::shared_ptr<const Surface>> blades;  // kept alive while planning
    for (const char* key : {"left_blade", "right_blade"}) {
      if (!o.has(key)) continue;
      ChannelFace& face = key[0] == 'l' ? rq.left : rq.right;
      o.push_raw(key);
      const lua_Integer n = luaL_len(L, -1);
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
        if (!h) luax::error(L, what + ": option '" + key + "': expected a list of surfaces");
        blades.push_back(h->surface);
        face.blade.push_back(h->surface.get());
        lua_pop(L, 1);
      }
      lua_pop(L, 1);
    }
    const std::shared_ptr<const Surface> hub = surface_option(L, o, "hub"), top = surface_option(L, o, "top");
    rq.hub = dynamic_cast<const SurfaceOfRevolution*>(hub.get());
    if (!rq.hub) luax::error(L, what + ": option 'hub': expected a surface of revolution (blisk:hub())");
    rq.top = dynamic_cast<const SurfaceOfRevolution*>(top.get());
    if (!rq.top) luax::error(L, what + ": option 'top': expected a surface of revolution (blisk:casing())");
    o.push_raw("tool");
    LuaTool& tool = luax::check<LuaTool>(L, -1);
    lua_pop(L, 1);
    o.push_raw("world");
    const std::shared_ptr<const CollisionWorld> world = luax::check<LuaWorld>(L, -1).world;
    lua_pop(L, 1);
    if (!o.has("ball_radius")) luax::error(L, what + ": missing required option 'ball_radius'");
    const FlankCutter cutter(tool.tool, o.number("ball_radius", 0));
    rq.cutter = &cutter;
    rq.world = world.get();
    rq.body = &tool.body();
    rq.stations = static_cast<int>(o.integer("stations", 41));
    rq.interior_stations = static_cast<int>(o.integer("interior_stations", 11));
    rq.stock_mm = o.number("stock", 0.5);
    rq.hub_stock_mm = o.number("hub_stock", rq.stock_mm);
    if (rq.hub_stock_mm > rq.stock_mm) luax::error(L, what + ": option 'hub_stock': expected at most the stock");
    rq.step_down_mm = o.number("step_down", 1.0);
    rq.step_over_mm = o.number("step_over", 2.0);
    rq.scallop_mm = o.number("scallop", 0.03);
    rq.chord_tol_mm = o.number("chord_tol", 0.005);
    rq.tilt_deg = o.number("tilt", 3.0);
    const double allowance = o.number("allowance", 0.035);
    if (allowance > rq.hub_stock_mm)
      throw ParameterError("allowance", "expected at most the hub stock (" + std::to_string(rq.hub_stock_mm) + " mm)");
    rq.clearances.cutter_mm = rq.hub_stock_mm - allowance;
    rq.clearances.shank_mm = rq.clearances.holder_mm = rq.hub_stock_mm + o.number("clearance", 0.5);
    rq.link.retract_mm = o.number("link_retract", 5);
    rq.link.min_retract_mm = std::min(rq.link.min_retract_mm, rq.link.retract_mm);
    rq.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
    const ChannelLevelsPlan plan = plan_channel_levels(rq, context(L).progress);
    lua_createtable(L, 0, 32);
    luax::set_number(L, "levels", plan.levels);
    luax::set_number(L, "levels_added", plan.levels_added);
    luax::set_number(L, "paths_added", plan.paths_added);
    set_list(L, "paths_left", plan.paths_left);
    set_list(L, "paths_right", plan.paths_right);
    luax::set_number(L, "level_step_max", plan.level_step_max_mm);
    luax::set_number(L, "step_over_max", plan.step_over_max_mm);
    luax::set_number(L, "axial_engagement_max", plan.axial_engagement_max_mm);
    luax::set_number(L, "slot_width", plan.slot_width_mm);
    set_pair(L, "face_cusp_max", plan.face_cusp_max_mm);
    luax::set_number(L, "hub_cusp_max", plan.hub_cusp_max_mm);
    luax::set_number(L, "top_height_min", plan.top_height_min_mm);
    luax::set_number(L, "top_height_max", plan.top_height_max_mm);
    luax::set_number(L, "hub_stock", plan.hub_stock_mm);
    luax::set_number(L, "station_step_max", plan.station_step_max_mm);
    set_pair(L, "corner", plan.corner_mm);
    set_pair(L, "contact_top", plan.contact_top_mm);
    luax::set_number(L, "hub_u_in", plan.hub_u_in);
    luax::set_number(L, "hub_u_out", plan.hub_u_out);
    luax::set_number(L, "cutter_clearance", rq.clearances.cutter_mm);
    set_channel_path(L, plan);
    return 1;
  });
}

}  // namespace

void open_channel(lua_State* L) {
  static const luaL_Reg functions[] = {
      {"channel_rough", w_channel_rough},
      {"channel_rough_all", w_channel_rough_all},
      {"channel_levels", w_channel_levels},
      {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
