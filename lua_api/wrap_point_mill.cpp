// bliskrun.point_mill{...}: five-axis point milling of a face with a ball or
// tapered ball end (core/planning/point_milling.h): the plan's report, its
// moves, the simulation of the face (core/sim). Lengths in mm, angles in
// degrees. See docs/lua_api/point_milling.md.
#include <memory>
#include <string>
#include <vector>

#include "core/planning/point_milling.h"
#include "core/sim/undercut.h"
#include "lua_api/finish_moves.h"
#include "lua_api/lua_tool.h"
#include "lua_api/modules.h"
#include "lua_api/refusal_reasons.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_collision.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {
using LuaPointMillPlan = LuaToolPlan<PointMillRequest, PointMillResult>;
}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaPointMillPlan> {
  static constexpr const char* name = "bliskrun.PointMillPlan";
};
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;
using luax::number_field;

LuaPointMillPlan& check_point_plan(lua_State* L) { return luax::check<LuaPointMillPlan>(L, 1); }

// A Surface, or {surface = Surface, flip = bool, name = string}.
PointMillSurface point_surface_at(lua_State* L, int idx, const std::string& where, const std::string& fallback_name) {
  PointMillSurface s;
  s.name = fallback_name;
  if (const SurfaceHandle* h = luax::test<SurfaceHandle>(L, idx)) {
    s.surface = h->surface;
    return s;
  }
  if (!lua_istable(L, idx)) luax::error(L, where + ": expected a bliskrun.Surface or {surface =, flip =, name =}");
  lua_getfield(L, idx, "surface");
  const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
  if (!h) luax::error(L, where + ": field 'surface': expected a bliskrun.Surface");
  s.surface = h->surface;
  lua_pop(L, 1);
  lua_getfield(L, idx, "flip");
  if (!lua_isnil(L, -1)) {
    if (!lua_isboolean(L, -1)) luax::error(L, where + ": field 'flip': expected a boolean");
    s.flip_normal = lua_toboolean(L, -1);
  }
  lua_pop(L, 1);
  lua_getfield(L, idx, "name");
  if (lua_isstring(L, -1)) s.name = lua_tostring(L, -1);
  lua_pop(L, 1);
  return s;
}

// plan:report() -> {rows =, poses =, scallop = {target =, measured =, closed_form =}, ...}
int w_point_plan_report(lua_State* L) {
  const LuaPointMillPlan& p = check_point_plan(L);
  const PointMillResult& r = *p.result;
  const PointMillRequest& rq = p.request;
  lua_createtable(L, 0, 24);
  luax::set_string(L, "tool", rq.tool->description());
  luax::set_number(L, "ball_radius", r.ball_radius_mm);
  luax::set_number(L, "taper", r.taper_rad * 180 / kPi);
  luax::set_number(L, "rows", static_cast<double>(r.rows.size()));
  luax::set_number(L, "passes", static_cast<double>(r.passes.size()));
  luax::set_number(L, "poses", r.poses);
  luax::set_number(L, "tilted", r.tilted);
  luax::set_number(L, "smoothed_rows", r.smoothed_rows);
  luax::set_number(L, "gouge_splits", r.gouge_splits);
  luax::set_number(L, "steps", r.steps);
  luax::set_number(L, "links", r.links);
  luax::set_number(L, "refused_links", r.refused_connections);
  luax::set_number(L, "first_row_u", r.first_row_u);
  luax::set_bool(L, "follows_fillet", r.follows_fillet);
  if (r.follows_fillet) {
    luax::set_number(L, "fillet_u_min", r.fillet_u_min);
    luax::set_number(L, "fillet_u_max", r.fillet_u_max);
  }
  luax::set_number(L, "scallop", rq.scallop_mm);
  luax::set_number(L, "scallop_measured", r.scallop_max_mm);
  luax::set_number(L, "scallop_closed_form", r.scallop_closed_form_mm);
  luax::set_number(L, "chord_tol", rq.steps.chord_tol_mm);
  luax::set_number(L, "max_deviation", r.max_deviation_mm);
  luax::set_number(L, "max_turn", r.max_turn_rad_per_mm * 180 / kPi);
  luax::set_number(L, "max_turn_allowed", rq.max_turn_rad_per_mm * 180 / kPi);
  luax::set_bool(L, "complete", r.complete());
  luax::set_number(L, "seconds", r.seconds);
  double smin = 1e300, smax = 0;
  for (size_t i = 1; i < r.rows.size(); ++i) smin = std::min(smin, r.rows[i].step_mm), smax = std::max(smax, r.rows[i].step_mm);
  luax::set_number(L, "step_min", r.rows.size() > 1 ? smin : 0);
  luax::set_number(L, "step_max", smax);
  lua_createtable(L, static_cast<int>(r.refusals.size()), 0);
  for (size_t i = 0; i < r.refusals.size(); ++i) {
    lua_createtable(L, 0, 3);
    luax::set_number(L, "row", r.refusals[i].row + 1);
    luax::set_vec3(L, "point", r.refusals[i].contact);
    luax::set_string(L, "reason", r.refusals[i].reason);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "refusals");
  set_refused_connections(L, "refused", r.connections);
  return 1;
}

// plan:moves() -> {{kind =, motion =, tip =, axis =, row =}, ...} up to the
// first refused connection.
int w_point_plan_moves(lua_State* L) {
  const LuaPointMillPlan& p = check_point_plan(L);
  return luax::guarded(L, [&] {
    push_finish_moves(L, point_mill_moves(*p.result));
    return 1;
  });
}

// plan:simulate{samples = {u, v}, sweep_step =, threads =} -> {left_max =, left_mean =, overcut =, untouched =,
// samples =, seconds =}: the material the plan's moves leave on the face
// (the lofted design surface itself) over the window it mills, from the
// first row up.
int w_point_plan_simulate(lua_State* L) {
  const LuaPointMillPlan& p = check_point_plan(L);
  const luax::Options o(L, 2, "plan:simulate",
                        {Field{"samples", Kind::Table, false, std::nullopt, std::nullopt,
                               "{span, chord} samples of the face (default {120, 400})", {}},
                         number_field("sweep_step", "largest cutter-point motion between evaluated positions, mm "
                                                    "(default 0.05)", 1e-3, 10),
                         Field{"threads", Kind::Integer, false, 1, 256, "worker threads (default: the run's --threads)", {}}});
  UndercutOptions uo;
  uo.samples_u = 120, uo.samples_v = 400;
  o.integer_pair("samples", "{span, chord}", 2, 20000, uo.samples_u, uo.samples_v);
  uo.sweep_step_mm = o.number("sweep_step", 0.05);
  uo.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
  return luax::guarded(L, [&] {
    const PointMillRequest& rq = p.request;
    const PointMillResult& r = *p.result;
    uo.flip_normal = rq.face.flip_normal;
    // The rows' window: from the hub stop up, or following the fillet the
    // face trimmed at the fillet line (below it: the root corner,
    // plan:root_strip's corner).
    uo.u0 = r.milled_u0, uo.u1 = r.milled_u1, uo.v0 = rq.v0, uo.v1 = rq.v1;
    // The ball rounds off past the rows' ends along v: measured inside them.
    uo.search_above_mm = 0.2;
    const ToolpathPasses tp = toolpath_passes(point_mill_moves(r));
    const UndercutResult u = simulate_undercut(*r.milled_surface, *rq.tool, tp.passes, uo, context(L).progress);
    lua_createtable(L, 0, 8);
    luax::set_number(L, "samples", static_cast<double>(u.samples_u) * u.samples_v);
    luax::set_number(L, "untouched", u.untouched);
    luax::set_number(L, "left_max", u.undercut_max_mm);
    luax::set_number(L, "left_mean", u.undercut_mean_mm);
    luax::set_number(L, "overcut", u.overcut_mm);
    luax::set_number(L, "u0", r.first_row_u);
    return 1;
  });
}

// plan:root_strip{samples = {u, v}} -> {height =, height_min =, u0 =, u1 =, left_max =, left_mean =, samples =,
// max_u =, max_v =, from_fillet =, corner_left_max =, corner_u =, corner_v =}: the band from the hub (the
// fillet line when the plan has the hub, else the window's edge) up to the hub stop: the distance from its
// design points to the nearest ball of the plan's moves (measure_root_strip), mm; the corner below the
// fillet line apart.
int w_point_plan_root_strip(lua_State* L) {
  const LuaPointMillPlan& p = check_point_plan(L);
  const luax::Options o(L, 2, "plan:root_strip",
                        {Field{"samples", Kind::Table, false, std::nullopt, std::nullopt,
                               "{span, chord} samples of the strip (default {12, 200})", {}}});
  int su = 12, sv = 200;
  o.integer_pair("samples", "{span, chord}", 2, 20000, su, sv);
  return luax::guarded(L, [&] {
    const PointMillStrip st = measure_root_strip(p.request, *p.result, su, sv);
    lua_createtable(L, 0, 8);
    luax::set_number(L, "height", st.height_mm);
    luax::set_number(L, "height_min", st.height_min_mm);
    luax::set_number(L, "u0", st.u0);
    luax::set_number(L, "u1", st.u1);
    luax::set_number(L, "left_max", st.material_max_mm);
    luax::set_number(L, "left_mean", st.material_mean_mm);
    luax::set_number(L, "samples", st.samples);
    luax::set_number(L, "max_u", st.max_u);
    luax::set_number(L, "max_v", st.max_v);
    luax::set_bool(L, "from_fillet", st.from_fillet);
    if (st.from_fillet) {
      luax::set_number(L, "corner_left_max", st.corner_max_mm);
      luax::set_number(L, "corner_u", st.corner_u);
      luax::set_number(L, "corner_v", st.corner_v);
    }
    return 1;
  });
}

int w_point_plan_tostring(lua_State* L) {
  const LuaPointMillPlan& p = check_point_plan(L);
  lua_pushfstring(L, "bliskrun.PointMillPlan(%d rows, %d poses, %d refusals)", static_cast<int>(p.result->rows.size()),
                  p.result->poses, static_cast<int>(p.result->refusals.size()));
  return 1;
}

// bliskrun.point_mill{face =, tool =, neighbours =, ...} -> plan
int w_point_mill(lua_State* L) {
  static const char* what = "bliskrun.point_mill";
  const luax::Options o(
      L, 1, what,
      {Field{"face", Kind::Any, true, std::nullopt, std::nullopt,
             "the face milled: a Surface or {surface =, flip =, name =} (u hub -> shroud, v along the chord)", {}},
       Field{"neighbours", Kind::Table, false, std::nullopt, std::nullopt,
             "surfaces the tool must not cut and must clear (the facing blade or splitter, the hub, ...): a list of "
             "Surface or {surface =, flip =, name =}", {}},
       Field{"tool", Kind::Any, true, std::nullopt, std::nullopt, "a ball or tapered ball-end mill", {}},
       Field{"world", Kind::Any, false, std::nullopt, std::nullopt,
             "CollisionWorld to check against instead of the default (the face for the shank, the neighbours)", {}},
       Field{"rows", Kind::String, false, std::nullopt, std::nullopt,
             "\"along\" the flow (constant u; default) or \"across\" (constant v)", {}},
       Field{"u", Kind::Table, false, std::nullopt, std::nullopt, "{u0, u1} window milled (default {0, 1})", {}},
       Field{"v", Kind::Table, false, std::nullopt, std::nullopt, "{v0, v1} window milled (default {0, 1})", {}},
       number_field("hub_stop", "first row's contact this far above the window's hub edge, mm (default: the ball radius; "
                                "following the fillet: the root band plan:root_strip measures)", 0, 100),
       Field{"hub", Kind::Any, false, std::nullopt, std::nullopt,
             "the hub the face stands on (a surface of revolution: impeller:hub()): the rows are carried down to the "
             "fillet line, the hub guarded", {}},
       Field{"follow_fillet", Kind::Boolean, false, std::nullopt, std::nullopt,
             "with a hub: carry the rows down to the fillet line (default true; false: stop at hub_stop, the band "
             "still measured from the fillet line)", {}},
       number_field("scallop", "scallop height, measured on the face, mm (default 0.005)", 1e-6, 1),
       number_field("chord_tol", "chord tolerance of the ball centre's path, mm (default 0.002)", 1e-6, 1),
       number_field("max_step", "longest step along a row, mm (default 2)", 1e-3, 100),
       number_field("lead", "lead angle: the tool's top towards the feed, degrees (default 0)", -45, 45),
       number_field("lean", "initial lean of the axis from the face, degrees (default 10)", 0.01, 60),
       number_field("lean_step", "step of the lean while clearing, degrees (default 1)", 0.01, 45),
       number_field("lean_max", "largest lean, degrees (default 45)", 0.01, 89),
       number_field("side_tilt", "sideways turns of the axis while clearing, up to +- degrees (default 20; 0: none)", 0, 90),
       number_field("side_step", "step of the sideways turn, degrees (default 5)", 0.01, 90),
       number_field("max_turn", "largest turn of the axis per mm of contact travel, degrees (default 2)", 1e-3, 90),
       number_field("clearance", "shank clearance from the world, mm (default 0.2)", 0, 100),
       number_field("holder_clearance", "holder clearance from the world, mm (default 1)", 0, 100),
       number_field("retract", "links: largest retract up the tool axis, mm (default 5)", 1e-3, 1000),
       number_field("min_retract", "links: smallest retract tried, mm (default 0.1)", 1e-4, 1000),
       number_field("allowed_overcut", "how far any move may cut below the design, mm (default 0.002)", 1e-6, 1),
       number_field("guard_spacing", "design samples of the gouge guards, mm apart (default 0.1)", 0.01, 10),
       Field{"threads", Kind::Integer, false, 1, 256,
             "rows planned on this many threads (default: the run's --threads); the plan does not depend on it", {}}});
  LuaPointMillPlan plan;
  PointMillRequest& rq = plan.request;
  o.push_raw("face");
  rq.face = point_surface_at(L, lua_gettop(L), std::string(what) + ": option 'face'", "the face");
  lua_pop(L, 1);
  if (o.has("neighbours")) {
    o.push_raw("neighbours");
    const int t = lua_gettop(L);
    const lua_Integer n = luaL_len(L, t);
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, t, i);
      rq.neighbours.push_back(point_surface_at(L, lua_gettop(L),
                                               std::string(what) + ": option 'neighbours' [" + std::to_string(i) + "]",
                                               "neighbour " + std::to_string(i)));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  plan.tool = tool_option(L, o, what, "a (tapered) ball-end mill");
  rq.tool = plan.tool.get();
  if (o.has("world")) {
    plan.world = world_option(L, o, what);
    rq.world = plan.world.get();
  }
  const std::string rows = o.string("rows", "along");
  if (rows != "along" && rows != "across")
    luax::error(L, std::string(what) + ": option 'rows': expected \"along\" or \"across\", got '" + rows + "'");
  rq.rows = rows == "along" ? PointMillRows::AlongFlow : PointMillRows::AcrossFlow;
  auto pair = [&](const char* key, double& a, double& b) {
    if (!o.has(key)) return;
    o.push_raw(key);
    const int t = lua_gettop(L);
    if (luaL_len(L, t) != 2) luax::error(L, std::string(what) + ": option '" + key + "': expected {lo, hi}");
    lua_rawgeti(L, t, 1);
    lua_rawgeti(L, t, 2);
    int ia = 0, ib = 0;
    a = lua_tonumberx(L, -2, &ia);
    b = lua_tonumberx(L, -1, &ib);
    if (!ia || !ib || !(0 <= a && a < b && b <= 1))
      luax::error(L, std::string(what) + ": option '" + key + "': expected numbers {lo, hi} with 0 <= lo < hi <= 1");
    lua_pop(L, 3);
  };
  pair("u", rq.u0, rq.u1);
  pair("v", rq.v0, rq.v1);
  rq.hub_stop_mm = o.number("hub_stop", -1);
  if (o.has("hub")) {
    o.push_raw("hub");
    const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
    rq.hub = h ? std::dynamic_pointer_cast<const SurfaceOfRevolution>(h->surface) : nullptr;
    if (!rq.hub)
      luax::error(L, std::string(what) + ": option 'hub': expected a surface of revolution (impeller:hub(), "
                                         "bliskrun.surface_of_revolution)");
    lua_pop(L, 1);
  }
  rq.follow_fillet = o.boolean("follow_fillet", true);
  rq.scallop_mm = o.number("scallop", rq.scallop_mm);
  rq.steps.chord_tol_mm = o.number("chord_tol", rq.steps.chord_tol_mm);
  rq.steps.max_step_mm = o.number("max_step", rq.steps.max_step_mm);
  rq.lead_rad = deg_to_rad(o.number("lead", 0));
  read_clearing_options(o, rq, 10, 45, 5);
  rq.max_turn_rad_per_mm = deg_to_rad(o.number("max_turn", 2));
  rq.allowed_overcut_mm = o.number("allowed_overcut", rq.allowed_overcut_mm);
  rq.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
  return luax::guarded(L, [&] {
    plan.result = std::make_shared<const PointMillResult>(plan_point_milling(rq, context(L).progress));
    luax::push_new<LuaPointMillPlan>(L, std::move(plan));
    return 1;
  });
}

}  // namespace

void open_point_mill(lua_State* L) {
  static const luaL_Reg plan_methods[] = {{"report", w_point_plan_report},
                                          {"moves", w_point_plan_moves},
                                          {"simulate", w_point_plan_simulate},
                                          {"root_strip", w_point_plan_root_strip},
                                          {nullptr, nullptr}};
  luax::register_type(L, luax::TypeName<LuaPointMillPlan>::name, plan_methods, &luax::gc_value<LuaPointMillPlan>,
                      w_point_plan_tostring);
  static const luaL_Reg functions[] = {{"point_mill", w_point_mill}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
