// bliskrun.hub_finish{...}: a blade's root strip and the channel floor to
// the next blade with a (tapered) ball end (core/planning/hub_finish.h): the
// plan's report, its moves, the simulation of the root strip and the floor
// (core/sim), APT/CL. Lengths in mm, angles in degrees. See docs/lua_api.md.
#include <memory>
#include <string>
#include <vector>

#include "core/common/atomic_file.h"
#include "core/planning/hub_finish.h"
#include "lua_api/finish_moves.h"
#include "lua_api/lua_tool.h"
#include "lua_api/modules.h"
#include "lua_api/refusal_reasons.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_collision.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {
using LuaHubPlan = LuaToolPlan<HubFinishRequest, HubFinishResult>;
}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaHubPlan> {
  static constexpr const char* name = "bliskrun.HubFinishPlan";
};
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;
using luax::number_field;

// {pressure = Surface, suction = Surface[, leading = Surface, trailing =
// Surface]}: a blade's two faces and, optionally, its edge rounds (check
// surfaces only).
BladeFaces faces_option(lua_State* L, const luax::Options& o, const char* what, const char* key) {
  BladeFaces f;
  if (!o.has(key)) return f;
  o.push_raw(key);
  const int t = lua_gettop(L);
  const std::string where = std::string(what) + ": option '" + key + "'";
  if (!lua_istable(L, t)) luax::error(L, where + ": expected {pressure = Surface, suction = Surface}");
  for (const char* side : {"pressure", "suction"}) {
    lua_getfield(L, t, side);
    const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
    if (!h) luax::error(L, where + ": field '" + side + "': expected a bliskrun.Surface (blisk:flank(k, \"" + side + "\"))");
    (std::string(side) == "pressure" ? f.pressure : f.suction) = h->surface;
    lua_pop(L, 1);
  }
  for (const char* edge : {"leading", "trailing"}) {
    lua_getfield(L, t, edge);
    if (!lua_isnil(L, -1)) {
      const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
      if (!h)
        luax::error(L, where + ": field '" + edge + "': expected a bliskrun.Surface, the blade's " + edge +
                           " edge round (blisk_world.edge_round(blisk, k, \"" + edge + "\").surface)");
      (std::string(edge) == "leading" ? f.leading : f.trailing) = h->surface;
    }
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return f;
}

LuaHubPlan& check_hub_plan(lua_State* L) { return luax::check<LuaHubPlan>(L, 1); }

void push_part(lua_State* L, const HubFinishPart& p) {
  lua_createtable(L, 0, 15);
  luax::set_number(L, "rows", p.rows);
  luax::set_number(L, "passes", static_cast<double>(p.passes.size()));
  luax::set_number(L, "poses", p.poses);
  luax::set_number(L, "tilted", p.tilted);
  luax::set_number(L, "refusals", p.refusals);
  luax::set_number(L, "steps", p.steps);
  luax::set_number(L, "links", p.links);
  luax::set_number(L, "refused_links", p.refused_connections);
  luax::set_number(L, "gouge_splits", p.gouge_splits);
  luax::set_number(L, "entered_rows", p.entered_rows);
  luax::set_number(L, "step_min", p.step_min_mm);
  luax::set_number(L, "step_max", p.step_max_mm);
  luax::set_number(L, "max_deviation", p.max_deviation_mm);
  luax::set_number(L, "seconds", p.seconds);
  set_refused_connections(L, "refused", p.connections);
}

// plan:report() -> {root = {...}, channel = {...}, refusals = {...}, fillet = {...}, ...}
int w_hub_plan_report(lua_State* L) {
  const LuaHubPlan& p = check_hub_plan(L);
  const HubFinishResult& r = *p.result;
  const HubFinishRequest& rq = p.request;
  lua_createtable(L, 0, 16);
  luax::set_string(L, "tool", rq.tool->description());
  luax::set_number(L, "scallop", rq.scallop_mm);
  luax::set_number(L, "chord_tol", rq.steps.chord_tol_mm);
  luax::set_number(L, "allowed_overcut", rq.allowed_overcut_mm);
  push_part(L, r.root);
  lua_setfield(L, -2, "root");
  push_part(L, r.channel);
  lua_setfield(L, -2, "channel");
  lua_createtable(L, 0, 6);
  luax::set_number(L, "radius", r.root_fillet_mm);
  luax::set_number(L, "contact_min", r.fillet_min_mm);
  luax::set_number(L, "contact_max", r.fillet_max_mm);
  lua_setfield(L, -2, "fillet");
  luax::set_numbers(L, "heights", {r.first_height_mm, r.top_height_mm});
  luax::set_numbers(L, "z", {r.z_inlet_mm, r.z_outlet_mm});
  luax::set_number(L, "pitch", r.pitch_rad * 180 / kPi);
  luax::set_number(L, "poses", r.root.poses + r.channel.poses);
  lua_createtable(L, 0, 8);
  luax::set_bool(L, "clear", r.join.clear);
  luax::set_number(L, "legs", r.join.clear ? static_cast<double>(r.join.poses.size() + 1) : 0);
  luax::set_string(L, "route", r.join_route);
  luax::set_number(L, "offset", r.join_offset_mm);
  luax::set_number(L, "margin", r.join_margin_mm);
  luax::set_string(L, "margin_at", r.join_margin_at);
  luax::set_number(L, "deepest_cut", r.join_deepest_cut_mm);
  luax::set_string(L, "reason", r.join.reason);
  luax::set_number(L, "seconds", r.join_seconds);
  lua_setfield(L, -2, "join");
  luax::set_number(L, "guard_spacing", r.guard_spacing_mm);
  luax::set_number(L, "setup_seconds", r.setup_seconds);
  luax::set_number(L, "edge_kink", r.edge_kink_deg);
  lua_createtable(L, static_cast<int>(r.refusals.size()), 0);
  for (size_t i = 0; i < r.refusals.size(); ++i) {
    const HubFinishRefusal& f = r.refusals[i];
    lua_createtable(L, 0, 4);
    luax::set_string(L, "operation", hub_finish_op_name(f.op));
    luax::set_number(L, "row", f.row + 1);
    luax::set_vec3(L, "point", f.contact);
    luax::set_string(L, "reason", f.reason);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "refusals");
  return 1;
}

// plan:moves([part]) -> {{kind =, motion =, tip =, axis =, row =}, ...}:
// "root" or "channel" (each with its lead-in and lead-out), or the whole
// program (root, the join, channel); up to the first refused connection
// (nothing unproven is implied).
int w_hub_plan_moves(lua_State* L) {
  const LuaHubPlan& p = check_hub_plan(L);
  const std::string part = lua_isnoneornil(L, 2) ? "both" : luax::check_string(L, 2, "part");
  if (part != "both" && part != "root" && part != "channel")
    luax::error(L, "plan:moves: expected \"root\", \"channel\" or nothing (both), got '" + part + "'");
  return luax::guarded(L, [&] {
    const HubFinishResult& r = *p.result;
    push_finish_moves(L, part == "both" ? hub_finish_moves(r) : hub_finish_moves(part == "root" ? r.root : r.channel));
    return 1;
  });
}

void push_stats(lua_State* L, const HubFinishRegionStats& s) {
  lua_createtable(L, 0, 6);
  luax::set_number(L, "samples", s.samples);
  luax::set_number(L, "unreached", s.unreached);
  luax::set_number(L, "left_max", s.left_max_mm);
  luax::set_number(L, "left_mean", s.left_mean_mm);
  luax::set_number(L, "overcut", s.overcut_mm);
}

HubFinishSimOptions read_sim_options(lua_State* L, const char* what) {
  const luax::Options o(
      L, 2, what,
      {Field{"root_samples", Kind::Table, false, std::nullopt, std::nullopt,
             "{span, around} samples of the root window (default {100, 1200})", {}},
       Field{"floor_samples", Kind::Table, false, std::nullopt, std::nullopt,
             "{meridian, around} samples of the hub around the channel (default {500, 300})", {}},
       number_field("sweep_step", "largest cutter-point motion between evaluated positions, mm (default 0.1)", 1e-3, 10),
       Field{"threads", Kind::Integer, false, 1, 256, "worker threads (default: the run's --threads)", {}}});
  HubFinishSimOptions so;
  o.integer_pair("root_samples", "{n1, n2}", 2, 20000, so.root_samples_u, so.root_samples_v);
  o.integer_pair("floor_samples", "{n1, n2}", 2, 20000, so.floor_samples_u, so.floor_samples_v);
  so.sweep_step_mm = o.number("sweep_step", so.sweep_step_mm);
  so.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
  return so;
}

// plan:regions{root_samples = {u, v}, floor_samples = {u, v}} -> {root = {surface =, u =, v =, samples_u =,
// samples_v =, strip = {bool...}, fillet = {bool...}}, floor = {surface =, u =, v =, samples_u =, samples_v =,
// flip_normal =, floor = {bool...}, middle = {bool...}}}: the surfaces, windows and per-sample regions
// plan:simulate measures (core hub_finish_regions), for a simulation of other moves over them
// (bliskrun.simulate{..., keep = regions.root.strip}). A part the plan does not have is absent.
int w_hub_plan_regions(lua_State* L) {
  const LuaHubPlan& p = check_hub_plan(L);
  const HubFinishSimOptions so = read_sim_options(L, "plan:regions");
  return luax::guarded(L, [&] {
    const HubFinishRegions r = hub_finish_regions(*p.result, p.request, so);
    auto push_mask = [&](const std::vector<char>& mask, const char* name) {
      lua_createtable(L, static_cast<int>(mask.size()), 0);
      for (size_t i = 0; i < mask.size(); ++i) {
        lua_pushboolean(L, mask[i]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
      }
      lua_setfield(L, -2, name);
    };
    auto push_window = [&](const std::shared_ptr<const Surface>& surface, const UndercutOptions& o) {
      lua_createtable(L, 0, 8);
      push_surface(L, surface);
      lua_setfield(L, -2, "surface");
      luax::set_numbers(L, "u", {o.u0, o.u1});
      luax::set_numbers(L, "v", {o.v0, o.v1});
      luax::set_integer(L, "samples_u", o.samples_u);
      luax::set_integer(L, "samples_v", o.samples_v);
      luax::set_bool(L, "flip_normal", o.flip_normal);
    };
    lua_createtable(L, 0, 2);
    if (r.blade) {
      push_window(r.blade, r.root);
      push_mask(r.strip, "strip");
      push_mask(r.fillet, "fillet");
      lua_setfield(L, -2, "root");
    }
    if (r.hub) {
      push_window(r.hub, r.floor);
      push_mask(r.channel_floor, "floor");
      push_mask(r.channel_middle, "middle");
      lua_setfield(L, -2, "floor");
    }
    return 1;
  });
}

// plan:simulate{root_samples = {u, v}, floor_samples = {u, v}, sweep_step =, threads =}
int w_hub_plan_simulate(lua_State* L) {
  const LuaHubPlan& p = check_hub_plan(L);
  const HubFinishSimOptions so = read_sim_options(L, "plan:simulate");
  return luax::guarded(L, [&] {
    const HubFinishSimulation s = simulate_hub_finish(*p.result, p.request, so, context(L).progress);
    lua_createtable(L, 0, 6);
    push_stats(L, s.strip);
    lua_setfield(L, -2, "strip");
    push_stats(L, s.fillet);
    lua_setfield(L, -2, "fillet");
    push_stats(L, s.channel_floor);
    lua_setfield(L, -2, "floor");
    push_stats(L, s.channel_middle);
    lua_setfield(L, -2, "floor_middle");
    luax::set_number(L, "root_overcut", s.root.overcut_mm);
    luax::set_number(L, "floor_overcut", s.floor.overcut_mm);
    luax::set_number(L, "seconds", s.seconds);
    return 1;
  });
}

int w_hub_plan_write_apt(lua_State* L) {
  const LuaHubPlan& p = check_hub_plan(L);
  const std::string path = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  return luax::guarded(L, [&] {
    write_file_atomic(path, hub_finish_apt(*p.result, p.request));
    return 0;
  });
}

int w_hub_plan_tostring(lua_State* L) {
  const LuaHubPlan& p = check_hub_plan(L);
  lua_pushfstring(L, "bliskrun.HubFinishPlan(root %d rows, channel %d rows, %d poses, %d refusals)", p.result->root.rows,
                  p.result->channel.rows, p.result->root.poses + p.result->channel.poses,
                  static_cast<int>(p.result->refusals.size()));
  return 1;
}

// bliskrun.hub_finish{blade =, next =, previous =, hub =, tool =, ...} -> plan
int w_hub_finish(lua_State* L) {
  static const char* what = "bliskrun.hub_finish";
  const luax::Options o(
      L, 1, what,
      {Field{"blade", Kind::Table, true, std::nullopt, std::nullopt,
             "blade k's faces {pressure =, suction =} (blisk:flank), optionally its edge rounds {leading =, "
             "trailing =} (check surfaces for the shank and holder): its root is finished, the channel starts at its "
             "suction side", {}},
       Field{"next", Kind::Table, true, std::nullopt, std::nullopt,
             "blade k+1's faces (and edge rounds): the channel's other side", {}},
       Field{"previous", Kind::Table, false, std::nullopt, std::nullopt,
             "blade k-1's faces and edge rounds (checked against, every tool part)", {}},
       Field{"hub", Kind::Any, true, std::nullopt, std::nullopt, "the hub (blisk:hub())", {}},
       Field{"tool", Kind::Any, true, std::nullopt, std::nullopt,
             "a ball or tapered ball-end mill long enough to reach the hub from outside the casing", {}},
       Field{"world", Kind::Any, false, std::nullopt, std::nullopt,
             "CollisionWorld to check against instead of the default (see docs)", {}},
       Field{"root", Kind::Boolean, false, std::nullopt, std::nullopt, "plan the root strip (default true)", {}},
       Field{"channel", Kind::Boolean, false, std::nullopt, std::nullopt, "plan the channel floor (default true)", {}},
       number_field("top", "height above the hub of the last root row, mm (default 4)", 0.01, 50),
       number_field("scallop", "scallop height on the blade and the hub, mm (default 0.005)", 1e-6, 1),
       number_field("chord_tol", "chord tolerance of the ball centre's path, mm (default 0.001)", 1e-6, 1),
       number_field("max_step", "longest step along a row, mm (default 2)", 1e-3, 100),
       number_field("allowed_overcut", "how far any move may cut below the design, mm (default 0.002)", 1e-6, 1),
       Field{"z", Kind::Table, false, std::nullopt, std::nullopt,
             "{z_inlet, z_outlet} of the channel floor, mm (default: the hub's ends)", {}},
       number_field("lean", "initial axis lean from the blade (root) / the channel's ends, degrees (default 12)", 0.01,
                    59),
       number_field("lean_step", "step of the lean while clearing, degrees (default 1)", 0.01, 45),
       number_field("lean_max", "largest lean, degrees (default 40)", 0.01, 89),
       number_field("side_tilt", "sideways turns of the axis while clearing, up to ± degrees (default 20; 0: none)", 0,
                    90),
       number_field("side_step", "step of the sideways turn, degrees (default 10)", 0.01, 90),
       number_field("clearance", "shank clearance from the world, mm (default 0.2)", 0, 100),
       number_field("holder_clearance", "holder clearance from the world, mm (default 1)", 0, 100),
       number_field("retract", "links: largest retract up the tool axis, mm (default 5)", 1e-3, 1000),
       number_field("min_retract", "links: smallest retract tried, mm (default 0.1)", 1e-4, 1000),
       number_field("guard_spacing", "design samples of the gouge guards, mm apart (default 0.1)", 0.01, 10),
       Field{"threads", Kind::Integer, false, 1, 256,
             "rows planned on this many threads (default: the run's --threads); the plan does not depend on it", {}}});
  LuaHubPlan plan;
  HubFinishRequest& rq = plan.request;
  rq.blade = faces_option(L, o, what, "blade");
  rq.next = faces_option(L, o, what, "next");
  rq.previous = faces_option(L, o, what, "previous");
  rq.hub = revolution_option(L, o, "hub", what);
  plan.tool = tool_option(L, o, what, "a (tapered) ball-end mill");
  rq.tool = plan.tool.get();
  if (o.has("world")) {
    plan.world = world_option(L, o, what);
    rq.world = plan.world.get();
  }
  rq.root = o.boolean("root", true);
  rq.channel = o.boolean("channel", true);
  rq.root_top_mm = o.number("top", rq.root_top_mm);
  rq.scallop_mm = o.number("scallop", rq.scallop_mm);
  rq.steps.chord_tol_mm = o.number("chord_tol", rq.steps.chord_tol_mm);
  rq.steps.max_step_mm = o.number("max_step", rq.steps.max_step_mm);
  rq.allowed_overcut_mm = o.number("allowed_overcut", rq.allowed_overcut_mm);
  rq.links.allowed_overcut_mm = rq.allowed_overcut_mm;
  if (o.has("z")) {
    o.push_raw("z");
    const int t = lua_gettop(L);
    if (luaL_len(L, t) != 2) luax::error(L, std::string(what) + ": option 'z': expected {z_inlet, z_outlet}");
    lua_rawgeti(L, t, 1);
    lua_rawgeti(L, t, 2);
    int a = 0, b = 0;
    rq.z_inlet_mm = lua_tonumberx(L, -2, &a);
    rq.z_outlet_mm = lua_tonumberx(L, -1, &b);
    if (!a || !b || !(rq.z_inlet_mm < rq.z_outlet_mm))
      luax::error(L, std::string(what) + ": option 'z': expected numbers {z_inlet, z_outlet} with z_inlet < z_outlet");
    lua_pop(L, 3);
  }
  read_clearing_options(o, rq, 12, 40, 10);
  rq.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
  return luax::guarded(L, [&] {
    plan.result = std::make_shared<const HubFinishResult>(plan_hub_finish(rq, context(L).progress));
    luax::push_new<LuaHubPlan>(L, std::move(plan));
    return 1;
  });
}

}  // namespace

void open_hub_finish(lua_State* L) {
  static const luaL_Reg plan_methods[] = {{"report", w_hub_plan_report},       {"moves", w_hub_plan_moves},
                                          {"simulate", w_hub_plan_simulate},   {"write_apt", w_hub_plan_write_apt},
                                          {"regions", w_hub_plan_regions},
                                          {nullptr, nullptr}};
  luax::register_type(L, luax::TypeName<LuaHubPlan>::name, plan_methods, &luax::gc_value<LuaHubPlan>,
                      w_hub_plan_tostring);
  static const luaL_Reg functions[] = {{"hub_finish", w_hub_finish}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
