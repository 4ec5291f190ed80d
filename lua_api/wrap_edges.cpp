// bliskrun.edge_region{...} and bliskrun.edge_finish{...}: blade leading/
// trailing-edge finishing with the bottom of a flat-end mill
// (core/parts/edge_region.h, core/planning/edge_finish.h), the plan's
// report, the strip-width comparison with side-edge positioning, APT/CL and
// the undercut simulation (core/sim). Lengths in mm, angles in degrees. See
// docs/lua_api.md.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>

#include "core/analysis/heat_map.h"
#include "core/common/atomic_file.h"
#include "core/parts/edge_region.h"
#include "core/planning/edge_finish.h"
#include "core/sim/undercut.h"
#include "lua_api/finish_moves.h"
#include "lua_api/lua_tool.h"
#include "lua_api/modules.h"
#include "lua_api/refusal_reasons.h"
#include "lua_api/runner.h"
#include "lua_api/undercut_map.h"
#include "lua_api/wrap_collision.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

// A plan and everything its request points to, kept alive together.
struct LuaEdgePlan {
  std::string name;
  std::shared_ptr<const Surface> edge, first, second;
  std::shared_ptr<const Tool> tool;
  std::shared_ptr<const CollisionWorld> world;
  EdgeFinishRequest request;
  std::shared_ptr<const EdgeFinishResult> result;
};

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaEdgePlan> {
  static constexpr const char* name = "bliskrun.EdgeFinishPlan";
};
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {
namespace {

using luax::Field;
using luax::Kind;
using luax::set_bool;
using luax::set_integer;
using luax::set_number;
using luax::set_numbers;
using luax::set_string;

std::shared_ptr<const Surface> surface_option(lua_State* L, const luax::Options& o, const std::string& key,
                                              const std::string& what) {
  o.push_raw(key);
  const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
  if (!h) luax::error(L, what + ": option '" + key + "': expected a bliskrun.Surface");
  std::shared_ptr<const Surface> s = h->surface;
  lua_pop(L, 1);
  return s;
}

// {a, b} with 0 <= a < b <= 1.
std::pair<double, double> range_option(lua_State* L, const luax::Options& o, const std::string& key,
                                       const std::string& what, std::pair<double, double> fallback) {
  if (!o.has(key)) return fallback;
  o.push_raw(key);
  const int t = lua_gettop(L);
  lua_rawgeti(L, t, 1);
  lua_rawgeti(L, t, 2);
  const bool ok = lua_isnumber(L, -2) && lua_isnumber(L, -1);
  const double a = lua_tonumber(L, -2), b = lua_tonumber(L, -1);
  lua_pop(L, 3);
  if (!ok || !(a >= 0 && b <= 1 && a < b))
    luax::error(L, what + ": option '" + key + "': expected {from, to} with 0 <= from < to <= 1");
  return {a, b};
}

// ---- bliskrun.edge_region ----------------------------------------------------

int w_edge_region(lua_State* L) {
  return luax::guarded(L, [&] {
    const std::string what = "bliskrun.edge_region";
    const luax::Options o(
        L, 1, what,
        {Field{"first", Kind::Any, true, std::nullopt, std::nullopt,
               "flank whose edge end is at its v = 0 (pressure at the LE, suction at the TE)", {}},
         Field{"second", Kind::Any, true, std::nullopt, std::nullopt, "flank whose edge end is at its v = 1", {}},
         Field{"overlap", Kind::Number, false, 0.0, 50.0, "overlap onto each flank, mm of arc (default 0.3)", {}},
         Field{"span", Kind::Table, false, std::nullopt, std::nullopt, "flank u range {from, to} (default {0, 1})", {}},
         Field{"samples_around", Kind::Integer, false, 8, 10000, "grid samples around the edge (default 161)", {}},
         Field{"samples_span", Kind::Integer, false, 4, 10000, "grid samples along the span (default 81)", {}}});
    EdgeRegionRequest rq;
    rq.first = surface_option(L, o, "first", what);
    rq.second = surface_option(L, o, "second", what);
    rq.overlap_mm = o.number("overlap", 0.3);
    const auto span = range_option(L, o, "span", what, {0.0, 1.0});
    rq.span_u0 = span.first;
    rq.span_u1 = span.second;
    rq.samples_around = static_cast<int>(o.integer("samples_around", 161));
    rq.samples_span = static_cast<int>(o.integer("samples_span", 81));
    const EdgeRegion e = build_edge_region(rq);
    lua_createtable(L, 0, 9);
    push_surface(L, e.surface);
    lua_setfield(L, -2, "surface");
    set_number(L, "round_u0", e.round_u0);
    set_number(L, "round_u1", e.round_u1);
    set_number(L, "overlap", e.overlap_mm);
    set_number(L, "radius_min", e.radius_min_mm);
    set_number(L, "radius_max", e.radius_max_mm);
    set_number(L, "circle_misfit", e.circle_misfit_mm);
    set_bool(L, "flanks_meet", e.flanks_meet);
    set_number(L, "crease_deg", e.crease_deg);
    set_number(L, "fit_deviation", e.fit_deviation_mm);
    return 1;
  });
}

// ---- bliskrun.edge_finish ------------------------------------------------------

int w_edge_finish(lua_State* L) {
  return luax::guarded(L, [&] {
    const std::string what = "bliskrun.edge_finish";
    const luax::Options o(
        L, 1, what,
        {Field{"edge", Kind::Any, true, std::nullopt, std::nullopt, "edge region surface (bliskrun.edge_region(...).surface)", {}},
         Field{"flanks", Kind::Table, false, std::nullopt, std::nullopt,
               "{first, second} flanks the region was built from: condition ① checked on them too", {}},
         Field{"flank_span", Kind::Table, false, std::nullopt, std::nullopt, "the region's flank u range (default {0, 1})", {}},
         Field{"tool", Kind::Any, true, std::nullopt, std::nullopt, "a flat-end mill (bliskrun.tool.flat_end_mill)", {}},
         Field{"world", Kind::Any, true, std::nullopt, std::nullopt, "check surfaces: neighbouring blades, hub, own blade", {}},
         Field{"name", Kind::String, false, std::nullopt, std::nullopt, "name used in reports", {}},
         Field{"span", Kind::Table, false, std::nullopt, std::nullopt, "edge-region v window {from, to} (default {0, 1}: the whole edge, hub to casing)", {}},
         Field{"hub", Kind::Any, false, std::nullopt, std::nullopt,
               "hub (surface of revolution): the first row as low as the cutter clears it; the strip below reported", {}},
         Field{"casing", Kind::Any, false, std::nullopt, std::nullopt,
               "casing (surface of revolution): the window ends where the edge passes it", {}},
         Field{"hub_clearance", Kind::Number, false, 0.0, 100.0, "cutter to hub on the first row, mm (default 0.05)", {}},
         Field{"reach", Kind::Table, false, std::nullopt, std::nullopt,
               "{axis = {x, y, z}, min = 0, max = deg}: every tool axis between min and max off axis (the machine's reach)", {}},
         Field{"e1", Kind::Number, false, -10.0, 0.0, "overcut limit, mm (<= 0, default -0.001)", {}},
         Field{"e2", Kind::Number, false, 1e-6, 10.0, "undercut limit, mm (default 0.02)", {}},
         Field{"r_e", Kind::Number, false, 1e-3, 100.0, "cutting-speed radius: l >= r_e, mm (default 1)", {}},
         Field{"l_count", Kind::Integer, false, 1, 100, "discretised l values in [r_e, R - r] (default 6)", {}},
         Field{"optimum", Kind::String, false, std::nullopt, std::nullopt,
               "\"paper\" (φ averaged over l, default) or \"joint\" (each l keeps its best φ)", {"paper", "joint"}},
         Field{"method", Kind::String, false, std::nullopt, std::nullopt,
               "\"bottom\" (the paper's, default) or \"side\" (the side-edge positioning, every step the same)",
               {"bottom", "side"}},
         Field{"chord_tol", Kind::Number, false, 1e-6, 1.0, "chord height around the edge, mm (default 0.001)", {}},
         Field{"max_step", Kind::Number, false, 1e-3, 100.0, "longest step along a row, mm (default 0.5)", {}},
         Field{"zigzag", Kind::Boolean, false, std::nullopt, std::nullopt, "alternate row direction (default true)", {}},
         Field{"side_min_lead", Kind::Number, false, 0.0, 60.0,
               "smallest lead of the side-edge comparison, degrees (default 3)", {}},
         Field{"half_width", Kind::Number, false, 0.01, 100.0, "strip samples across the feed each side, mm (default R + 1)", {}},
         Field{"across", Kind::Integer, false, 3, 10001, "strip samples across (odd, default 81)", {}},
         Field{"retract", Kind::Number, false, 0.01, 1000.0, "links: retract up the tool axis, mm (default 3)", {}},
         Field{"short_lift", Kind::Number, false, 0.0, 10.0,
               "near passes joined by a fed lift of this much up the axes, mm (default 0: none)", {}},
         Field{"cutter_clearance", Kind::Number, false, 0.0, 100.0, "cutter to check surfaces, mm (default 0)", {}},
         Field{"shank_clearance", Kind::Number, false, 0.0, 100.0, "shank to check surfaces, mm (default 0.1)", {}},
         Field{"holder_clearance", Kind::Number, false, 0.0, 100.0, "holder to check surfaces, mm (default 0.5)", {}},
         Field{"comparison_row", Kind::Integer, false, 1, 100000, "row of the strip-width comparison (default: middle)", {}},
         Field{"threads", Kind::Integer, false, 1, 256, "workers for a row's contacts (default: the run's --threads)", {}},
         Field{"tilt_lead_max", Kind::Number, false, 5.0, 89.0,
               "tilting clear of the world: largest corner lead θ, degrees (default 80)", {}},
         Field{"axis_limit", Kind::Table, false, std::nullopt, std::nullopt,
               "the machine's range for tilted axes {name=, rotary_axis=, reference=, min=, max=} degrees; default none", {}}});
    LuaEdgePlan p;
    p.name = o.string("name", "");
    p.edge = surface_option(L, o, "edge", what);
    if (o.has("flanks")) {
      o.push_raw("flanks");
      const int t = lua_gettop(L);
      for (int i = 1; i <= 2; ++i) {
        lua_rawgeti(L, t, i);
        const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
        if (!h) luax::error(L, what + ": option 'flanks': expected {first, second} bliskrun.Surface values");
        (i == 1 ? p.first : p.second) = h->surface;
        lua_pop(L, 1);
      }
      lua_pop(L, 1);
    }
    p.tool = tool_option(L, o, what, "a flat-end mill");
    if (p.tool->kind() != ToolKind::FlatEndMill)
      luax::error(L, what + ": option 'tool': expected a flat-end mill, got a " + to_string(p.tool->kind()));
    p.world = world_option(L, o, what);
    EdgeFinishRequest& rq = p.request;
    rq.edge = p.edge;
    rq.first = p.first;
    rq.second = p.second;
    const auto fspan = range_option(L, o, "flank_span", what, {0.0, 1.0});
    rq.span_u0 = fspan.first;
    rq.span_u1 = fspan.second;
    rq.tool = p.tool.get();
    rq.world = p.world.get();
    const auto span = range_option(L, o, "span", what, {0.0, 1.0});
    rq.v0 = span.first;
    rq.v1 = span.second;
    if (o.has("hub")) rq.hub = revolution_option(L, o, "hub", what);
    if (o.has("casing")) rq.casing = revolution_option(L, o, "casing", what);
    rq.hub_clearance_mm = o.number("hub_clearance", 0.05);
    if (o.has("reach")) {
      o.push_raw("reach");
      const int t = lua_gettop(L);
      lua_getfield(L, t, "axis");
      const Vec3 axis = luax::check_vec3(L, -1, (what + ": option 'reach'.axis").c_str());
      lua_pop(L, 1);
      lua_getfield(L, t, "max");
      if (!lua_isnumber(L, -1)) luax::error(L, what + ": option 'reach': expected max = degrees");
      const double max_deg = lua_tonumber(L, -1);
      lua_pop(L, 1);
      lua_getfield(L, t, "min");
      if (!lua_isnil(L, -1) && !lua_isnumber(L, -1)) luax::error(L, what + ": option 'reach': expected min = degrees");
      const double min_deg = lua_isnil(L, -1) ? 0.0 : lua_tonumber(L, -1);
      lua_pop(L, 2);
      if (!(axis.norm() > 1e-9)) luax::error(L, what + ": option 'reach'.axis: expected a non-zero direction");
      if (!(max_deg > 0 && max_deg <= 180)) luax::error(L, what + ": option 'reach'.max: expected degrees in (0, 180]");
      if (!(min_deg >= 0 && min_deg < max_deg))
        luax::error(L, what + ": option 'reach'.min: expected degrees in [0, max)");
      rq.reach_axis = axis.normalized();
      rq.reach_min_rad = deg_to_rad(min_deg);
      rq.reach_max_rad = deg_to_rad(max_deg);
    }
    rq.band.e1_mm = o.number("e1", -0.001);
    rq.band.e2_mm = o.number("e2", 0.02);
    rq.r_e_mm = o.number("r_e", 1.0);
    rq.l_count = static_cast<int>(o.integer("l_count", 6));
    rq.optimum = o.string("optimum", "paper") == "joint" ? EdgeOptimum::Joint : EdgeOptimum::Paper;
    rq.method = o.string("method", "bottom") == "side" ? EdgeMethod::Side : EdgeMethod::Bottom;
    rq.steps.chord_tol_mm = o.number("chord_tol", 0.001);
    rq.steps.max_step_mm = o.number("max_step", 0.5);
    rq.zigzag = o.boolean("zigzag", true);
    rq.side_min_lead_rad = deg_to_rad(o.number("side_min_lead", 3.0));
    const double R = p.tool->cutter().max_radius();
    rq.sampling.half_width_mm = o.number("half_width", R + 1);
    rq.sampling.gouge_half_mm = rq.sampling.half_width_mm;
    rq.sampling.across = static_cast<int>(o.integer("across", 81));
    if (rq.sampling.across % 2 == 0) luax::error(L, what + ": option 'across': expected an odd count");
    rq.retract_mm = o.number("retract", 3.0);
    rq.short_lift_mm = o.number("short_lift", 0.0);
    rq.clearances.cutter_mm = o.number("cutter_clearance", 0.0);
    rq.clearances.shank_mm = o.number("shank_clearance", 0.1);
    rq.clearances.holder_mm = o.number("holder_clearance", 0.5);
    rq.comparison_row = static_cast<int>(o.integer("comparison_row", 0)) - 1;
    rq.tilt_lead_max_rad = deg_to_rad(o.number("tilt_lead_max", 80));
    rq.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
    if (o.has("axis_limit")) {
      o.push_raw("axis_limit");
      rq.axis_limit = read_axis_limit(L, lua_gettop(L), what + ".axis_limit");
      lua_pop(L, 1);
    }
    p.result = std::make_shared<const EdgeFinishResult>(plan_edge_finish(rq, context(L).progress));
    luax::push_new(L, std::move(p));
    return 1;
  });
}

// ---- plan methods ----------------------------------------------------------------

LuaEdgePlan& check_plan(lua_State* L) { return luax::check<LuaEdgePlan>(L, 1); }

int w_plan_report(lua_State* L) {
  const LuaEdgePlan& p = check_plan(L);
  const EdgeFinishResult& r = *p.result;
  const EdgeFinishRequest& rq = p.request;
  lua_createtable(L, 0, 24);
  set_string(L, "name", p.name);
  set_string(L, "tool", rq.tool->description());
  set_number(L, "e1", rq.band.e1_mm);
  set_number(L, "e2", rq.band.e2_mm);
  set_number(L, "r_e", rq.r_e_mm);
  set_string(L, "optimum", rq.optimum == EdgeOptimum::Paper ? "paper" : "joint");
  set_string(L, "method", rq.method == EdgeMethod::Side ? "side" : "bottom");
  set_number(L, "chord_tol", rq.steps.chord_tol_mm);
  set_number(L, "span_v0", r.v0);
  set_number(L, "span_v1", r.v1);
  set_number(L, "hub_strip", r.hub_strip_mm);
  set_number(L, "top_strip", r.top_strip_mm);
  const EdgeProgramStats stats = edge_program_stats(r);
  set_integer(L, "passes", stats.passes);
  set_integer(L, "single_move_passes", stats.single_move_passes);
  set_integer(L, "direct_links", stats.direct_links);
  set_integer(L, "lifted_links", stats.lifted_links);
  set_number(L, "lift_length", stats.lift_mm);
  set_number(L, "cutting_length", stats.cutting_mm);
  set_number(L, "non_cutting_length", stats.non_cutting_mm);
  set_number(L, "rapid_length", stats.rapid_mm);
  set_number(L, "plunge_length", stats.plunge_mm);
  set_number(L, "checked_v0", r.checked_v0);
  set_number(L, "checked_v1", r.checked_v1);
  set_bool(L, "zigzag", rq.zigzag);
  set_integer(L, "row_count", static_cast<long long>(r.rows.size()) - r.infill_rows);
  set_integer(L, "infill_rows", r.infill_rows);
  set_integer(L, "lifted_contacts", r.lifted_contacts);
  set_integer(L, "simulated_infill_rows", r.simulated_infill_rows);
  set_integer(L, "side_rows", r.side_rows);
  set_number(L, "side_window", r.side_window_mm);
  set_number(L, "side_min_lead", rad_to_deg(rq.side_min_lead_rad));
  set_integer(L, "poses", r.total_poses);
  set_integer(L, "refusals", r.total_refusals);
  set_integer(L, "refused_links", r.refused_links);
  set_integer(L, "rearranged_rows", r.rearranged_rows);
  set_integer(L, "gouge_breaks", r.gouge_breaks);
  set_number(L, "max_deviation", r.max_deviation_mm);
  double wmin = std::numeric_limits<double>::infinity(), wmax = 0, smin = wmin, smax = 0;
  long bottom = 0, corner = 0, evals = 0, tilted = 0;
  lua_createtable(L, static_cast<int>(r.rows.size()), 0);
  for (size_t i = 0; i < r.rows.size(); ++i) {
    const EdgeFinishRow& row = r.rows[i];
    if (!row.infill) {  // the widths of the rows proper (a partial row's are its whole row's)
      wmin = std::min(wmin, row.width_mm);
      wmax = std::max(wmax, row.width_mm);
      smin = std::min(smin, row.side_width_mm);
      smax = std::max(smax, row.side_width_mm);
    }
    bottom += row.bottom_contacts;
    corner += row.corner_contacts;
    evals += row.strip_evaluations;
    tilted += row.tilted_contacts;
    lua_createtable(L, 0, 14);
    set_number(L, "v", row.v);
    set_number(L, "width", row.width_mm);
    set_number(L, "paper_width", row.paper_width_mm);
    set_number(L, "joint_width", row.joint_width_mm);
    set_number(L, "side_width", row.side_width_mm);
    set_number(L, "left_min", row.left_min_mm);
    set_number(L, "right_min", row.right_min_mm);
    set_number(L, "spacing", row.spacing_mm);
    set_integer(L, "poses", static_cast<long long>(row.poses.size()));
    set_integer(L, "bottom_contacts", row.bottom_contacts);
    set_integer(L, "corner_contacts", row.corner_contacts);
    set_integer(L, "refusals", static_cast<long long>(row.refusals.size()));
    set_number(L, "max_deviation", row.max_deviation_mm);
    set_bool(L, "reversed", row.reversed);
    set_bool(L, "infill", row.infill);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "rows");
  set_number(L, "width_min", r.rows.empty() ? 0 : wmin);
  set_number(L, "width_max", wmax);
  set_number(L, "side_width_min", r.rows.empty() ? 0 : smin);
  set_number(L, "side_width_max", smax);
  set_integer(L, "bottom_contacts", bottom);
  set_integer(L, "corner_contacts", corner);
  set_integer(L, "strip_evaluations", evals);
  set_integer(L, "tilted_contacts", tilted);
  set_refusal_reasons(L, r);
  lua_createtable(L, 0, 3);
  set_number(L, "rows", r.rows_seconds);
  set_number(L, "side", r.side_seconds);
  set_number(L, "checks", r.checks_seconds);
  set_number(L, "clear", r.clear_seconds);
  set_number(L, "simulation", r.simulation_seconds);
  lua_setfield(L, -2, "seconds");
  return 1;
}

// plan:comparison() -> the paper's Fig. 8 for one row: {row, v, u = {...},
// contact = {"bottom"|"corner"}, paper = {...}, joint = {...}, side = {...},
// emitted = {...}} (strip widths, mm, per contact).
int w_plan_comparison(lua_State* L) {
  const EdgeWidthComparison& c = check_plan(L).result->comparison;
  lua_createtable(L, 0, 8);
  set_integer(L, "row", c.row + 1);
  set_number(L, "v", c.v);
  for (const auto& [key, values] : {std::pair{"u", &c.u}, std::pair{"paper", &c.paper_mm}, std::pair{"joint", &c.joint_mm},
                                    std::pair{"side", &c.side_mm}, std::pair{"emitted", &c.bottom_mm}})
    set_numbers(L, key, *values);
  luax::set_strings(L, "contact", c.contact);
  return 1;
}

// plan:moves(): as the drum finish's (lua_api/finish_moves.h).
int w_plan_moves(lua_State* L) {
  push_finish_moves(L, edge_finish_moves(*check_plan(L).result));
  return 1;
}

int w_plan_write_apt(lua_State* L) {
  const LuaEdgePlan& p = check_plan(L);
  const std::string path = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  return luax::guarded(L, [&] {
    write_file_atomic(path, edge_finish_apt(*p.result, p.request, p.name));
    return 0;
  });
}

// The move (1-based, in edge_finish_moves order) a simulation's (pass, pose)
// is, with its motion and row.
struct LocatedMove {
  long move = 0;
  std::string motion;
  int row = -1;
};
LocatedMove locate(const Toolpath& moves, const ToolpathPasses& passes, int pass, long pose) {
  LocatedMove out;
  if (pass < 0 || pose < 0) return out;
  const long i = passes.first_move.at(static_cast<size_t>(pass)) + pose;
  out.move = i + 1;
  out.motion = moves.at(static_cast<size_t>(i)).motion;
  out.row = moves.at(static_cast<size_t>(i)).row;
  return out;
}

// plan:simulate{samples_u=, samples_v=, picture=, flanks = {s1, s2}}: the
// undercut simulation of every move (rows and links) on the edge region
// over the machined span window, and the overcut on the blade's flanks.
int w_plan_simulate(lua_State* L) {
  const LuaEdgePlan& p = check_plan(L);
  return luax::guarded(L, [&] {
    const luax::Options o(
        L, 2, "EdgeFinishPlan:simulate",
        {Field{"samples_u", Kind::Integer, false, 2, 5000, "design samples around the edge (default 200)", {}},
         Field{"samples_v", Kind::Integer, false, 2, 20000, "design samples along the span (default 400)", {}},
         Field{"sweep_step", Kind::Number, false, 1e-4, 10.0, "largest cutter-point motion between positions, mm (default 0.05)", {}},
         Field{"picture", Kind::String, false, std::nullopt, std::nullopt, "undercut map SVG file", {}},
         Field{"flanks", Kind::Table, false, std::nullopt, std::nullopt, "the blade's flank surfaces: overcut measured on them too", {}},
         Field{"threads", Kind::Integer, false, 1, 256, "worker threads (default: the run's --threads)", {}},
         Field{"thickness", Kind::Table, false, std::nullopt, std::nullopt,
               "{spans = {v...}, behind = {mm...}}: the edge's thickness after machining vs design", {}}});
    const EdgeFinishResult& r = *p.result;
    UndercutOptions so;
    so.samples_u = static_cast<int>(o.integer("samples_u", 200));
    so.samples_v = static_cast<int>(o.integer("samples_v", 400));
    so.sweep_step_mm = o.number("sweep_step", so.sweep_step_mm);
    so.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
    so.v0 = r.v0;
    so.v1 = r.v1;
    const Toolpath moves = edge_finish_moves(r);
    const ToolpathPasses split = toolpath_passes(moves);
    const std::vector<ToolPass>& passes = split.passes;
    const auto t0 = std::chrono::steady_clock::now();
    UndercutResult u = simulate_undercut(*p.edge, *p.tool, passes, so, context(L).progress);
    // The overcut beyond the window, where the first and last rows' discs
    // reach (EdgeFinishResult::checked_v0/v1): sampled as densely along the
    // span as the window, only gouges traced. The deepest anywhere is the
    // overcut reported.
    long overcut_at_v = -1;  // with the deepest beyond the window: its sample's span index in `beyond`
    UndercutOptions beyond_o;
    for (const auto& [a, b] : {std::pair{r.checked_v0, r.v0}, std::pair{r.v1, r.checked_v1}}) {
      if (!(b - a > 1e-9)) continue;
      UndercutOptions bo = so;
      bo.v0 = a;
      bo.v1 = b;
      bo.samples_v = std::max(4, static_cast<int>(std::ceil(so.samples_v * (b - a) / (so.v1 - so.v0))));
      bo.search_above_mm = 1e-3;  // material left there is the neighbouring operation's: gouges only
      const UndercutResult f = simulate_undercut(*p.edge, *p.tool, passes, bo, context(L).progress);
      if (f.overcut_mm < u.overcut_mm) {
        u.overcut_mm = f.overcut_mm;
        u.overcut_pass = f.overcut_pass;
        u.overcut_pose = f.overcut_pose;
        u.overcut_sample = f.overcut_sample;
        overcut_at_v = 1;
        beyond_o = bo;
      }
    }
    double flank_overcut = 0;
    LocatedMove flank_at;
    int flank_index = 0;
    double flank_u = 0, flank_v = 0;
    if (o.has("flanks")) {
      o.push_raw("flanks");
      const int t = lua_gettop(L);
      const lua_Integer n = luaL_len(L, t);
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, t, i);
        const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
        if (!h) luax::error(L, "EdgeFinishPlan:simulate: flanks[" + std::to_string(i) + "]: expected a bliskrun.Surface");
        UndercutOptions fo = so;
        fo.v0 = 0;
        fo.v1 = 1;
        fo.samples_u = 100;
        fo.samples_v = 500;
        const UndercutResult f = simulate_undercut(*h->surface, *p.tool, passes, fo, context(L).progress);
        if (f.overcut_mm < flank_overcut) {
          flank_overcut = f.overcut_mm;
          flank_at = locate(moves, split, f.overcut_pass, f.overcut_pose);
          flank_index = static_cast<int>(i);
          flank_u = static_cast<double>(f.overcut_sample / fo.samples_v) / (fo.samples_u - 1);
          flank_v = static_cast<double>(f.overcut_sample % fo.samples_v) / (fo.samples_v - 1);
        }
        lua_pop(L, 1);
      }
      lua_pop(L, 1);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    lua_createtable(L, 0, 12);
    set_undercut_stats(L, u);
    set_number(L, "flank_overcut", flank_overcut);
    // Where the deepest overcut is and which move cut it (edge_finish_moves
    // order, as plan:moves() lists them).
    const LocatedMove at = locate(moves, split, u.overcut_pass, u.overcut_pose);
    if (at.move > 0) {
      set_integer(L, "overcut_move", at.move);
      set_string(L, "overcut_motion", at.motion);
      set_integer(L, "overcut_row", at.row + 1);
      const UndercutOptions& at_o = overcut_at_v >= 0 ? beyond_o : so;
      set_number(L, "overcut_u", static_cast<double>(u.overcut_sample / at_o.samples_v) / (at_o.samples_u - 1));
      set_number(L, "overcut_v", at_o.v0 + (at_o.v1 - at_o.v0) * static_cast<double>(u.overcut_sample % at_o.samples_v) /
                                             (at_o.samples_v - 1));
      set_bool(L, "overcut_beyond_window", overcut_at_v >= 0);
    }
    if (flank_at.move > 0) {
      set_integer(L, "flank_overcut_move", flank_at.move);
      set_string(L, "flank_overcut_motion", flank_at.motion);
      set_integer(L, "flank_overcut_row", flank_at.row + 1);
      set_integer(L, "flank_overcut_flank", flank_index);
      set_number(L, "flank_overcut_u", flank_u);
      set_number(L, "flank_overcut_v", flank_v);
    }
    if (o.has("thickness")) {
      // {spans = {...}, behind = {...}}: both lists of numbers.
      o.push_raw("thickness");
      const int t = lua_gettop(L);
      auto numbers = [&](const char* key) {
        std::vector<double> xs;
        lua_getfield(L, t, key);
        if (!lua_istable(L, -1))
          luax::error(L, std::string("EdgeFinishPlan:simulate: option 'thickness': expected a list '") + key + "'");
        const lua_Integer n = luaL_len(L, -1);
        for (lua_Integer i = 1; i <= n; ++i) {
          lua_rawgeti(L, -1, i);
          if (!lua_isnumber(L, -1))
            luax::error(L, std::string("EdgeFinishPlan:simulate: thickness.") + key + "[" + std::to_string(i) +
                               "]: expected a number");
          xs.push_back(lua_tonumber(L, -1));
          lua_pop(L, 1);
        }
        lua_pop(L, 1);
        return xs;
      };
      const std::vector<double> spans = numbers("spans"), behind = numbers("behind");
      lua_pop(L, 1);
      const std::vector<EdgeThickness> th = edge_thickness(*p.edge, u, so, spans, behind);
      lua_createtable(L, static_cast<int>(th.size()), 0);
      for (size_t i = 0; i < th.size(); ++i) {
        lua_createtable(L, 0, 5);
        set_number(L, "v", th[i].v);
        set_number(L, "behind", th[i].behind_mm);
        set_bool(L, "measured", th[i].measured);
        if (th[i].measured) {
          set_number(L, "design", th[i].design_mm);
          set_number(L, "machined", th[i].machined_mm);
        }
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
      }
      lua_setfield(L, -2, "thickness");
    }
    // Where the most material is left (a touched sample's residual equal
    // to undercut_max): u around the edge, v along the span.
    if (u.undercut_max_mm > 0) {
      for (size_t i = 0; i < u.residual_mm.size(); ++i) {
        if (u.residual_mm[i] != u.undercut_max_mm) continue;
        set_number(L, "undercut_u", static_cast<double>(i / static_cast<size_t>(so.samples_v)) / (so.samples_u - 1));
        set_number(L, "undercut_v", so.v0 + (so.v1 - so.v0) * static_cast<double>(i % static_cast<size_t>(so.samples_v)) /
                                            (so.samples_v - 1));
        break;
      }
    }
    set_integer(L, "untouched", u.untouched);
    // Material left is traced this far above the design: a larger residual
    // (or none, untouched) reads as at least this.
    set_number(L, "undercut_cap", so.search_above_mm);
    set_number(L, "checked_v0", r.checked_v0);
    set_number(L, "checked_v1", r.checked_v1);
    set_integer(L, "samples", static_cast<long long>(u.samples_u) * u.samples_v);
    set_integer(L, "tool_positions", u.tool_positions);
    set_number(L, "seconds", seconds);
    if (o.has("picture")) {
      const std::string path = context(L).resolve_write(L, o.string("picture", ""));
      HeatMap map;
      map.rows = u.samples_u;
      map.cols = u.samples_v;
      map.values = u.residual_mm;
      HeatMapOptions h;
      h.title = "Edge region after the edge finish: material left (mm)";
      h.u_label = "u (around the edge)";
      h.v_label = "v (span, hub to tip)";
      h.value_label = "mm";
      char footer[240];
      std::snprintf(footer, sizeof footer,
                    "%d x %d samples, span v in [%.3f, %.3f]; undercut max %.2f, mean %.2f um; overcut %.2f um; "
                    "untouched %d",
                    map.rows, map.cols, so.v0, so.v1, 1e3 * u.undercut_max_mm, 1e3 * u.undercut_mean_mm,
                    1e3 * u.overcut_mm, u.untouched);
      h.footer = footer;
      h.scale_max = 2 * p.request.band.e2_mm;
      // The picture's format follows its name: .png raster, anything else SVG.
      if (path.size() >= 4 && path.compare(path.size() - 4, 4, ".png") == 0)
        write_heat_map_png(map, path, h);
      else
        write_heat_map_svg(map, path, h);
    }
    return 1;
  });
}

int w_plan_tostring(lua_State* L) {
  const LuaEdgePlan& p = check_plan(L);
  lua_pushfstring(L, "bliskrun.EdgeFinishPlan(%s%s%d rows, %d poses, %d refusals)", p.name.c_str(),
                  p.name.empty() ? "" : ": ", static_cast<int>(p.result->rows.size()), p.result->total_poses,
                  p.result->total_refusals);
  return 1;
}

}  // namespace

void open_edges(lua_State* L) {
  static const luaL_Reg plan_methods[] = {{"report", w_plan_report},       {"comparison", w_plan_comparison},
                                          {"moves", w_plan_moves},         {"write_apt", w_plan_write_apt},
                                          {"simulate", w_plan_simulate},   {nullptr, nullptr}};
  luax::register_type(L, luax::TypeName<LuaEdgePlan>::name, plan_methods, &luax::gc_value<LuaEdgePlan>,
                      w_plan_tostring);
  static const luaL_Reg functions[] = {
      {"edge_region", w_edge_region}, {"edge_finish", w_edge_finish}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
