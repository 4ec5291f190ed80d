// Repair toolpaths (repair paper §2, SPEC §6.5): bliskrun.close_blade, the
// blade's side surface closed around its section (core/parts/closed_blade.h),
// and bliskrun.repair_paths, the offset layers of zigzag or spiral ball-end
// paths over a region of it (core/planning/repair_paths.h).
#include <memory>
#include <string>
#include <vector>

#include "core/parts/closed_blade.h"
#include "core/planning/repair_paths.h"
#include "core/toolpath/move.h"
#include "lua_api/lua_tool.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/refusal_reasons.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_collision.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;
using luax::number_field;

std::shared_ptr<const Surface> surface_option(lua_State* L, const luax::Options& o, const char* what,
                                              const char* key) {
  o.push_raw(key);
  const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
  if (!h) luax::error(L, std::string(what) + ": option '" + key + "': expected a bliskrun.Surface");
  std::shared_ptr<const Surface> s = h->surface;
  lua_pop(L, 1);
  return s;
}

// bliskrun.close_blade{pressure=, suction=, u = {u0, u1}, sections=, face_samples=, edge_samples=, samples=}
// -> Surface, {le_v, te_v, perimeter, edge_kink, section_u = {...}}
int w_close_blade(lua_State* L) {
  static const char* what = "bliskrun.close_blade";
  const luax::Options o(
      L, 1, what,
      {Field{"pressure", Kind::Any, true, std::nullopt, std::nullopt,
             "pressure flank face (Surface): u span, v LE -> TE, pu x pv out of the material", {}},
       Field{"suction", Kind::Any, true, std::nullopt, std::nullopt,
             "suction flank face (Surface): u span, v TE -> LE, pu x pv out of the material", {}},
       Field{"u", Kind::Table, false, std::nullopt, std::nullopt, "span window of the faces {u0, u1} (default {0, 1})",
             {}},
       Field{"sections", Kind::Integer, false, 2, 1000, "sections lofted (default 31)", {}},
       Field{"face_samples", Kind::Integer, false, 8, 20000, "points per face per section (default 300)", {}},
       Field{"edge_samples", Kind::Integer, false, 3, 2000, "points per edge half circle (default 24)", {}},
       Field{"samples", Kind::Integer, false, 16, 20000, "loft samples around (default 512)", {}}});
  ClosedBladeOptions co;
  const std::shared_ptr<const Surface> pressure = surface_option(L, o, what, "pressure");
  const std::shared_ptr<const Surface> suction = surface_option(L, o, what, "suction");
  read_unit_window(L, o, what, "u", co.u0, co.u1);
  co.sections = static_cast<int>(o.integer("sections", co.sections));
  co.face_samples = static_cast<int>(o.integer("face_samples", co.face_samples));
  co.edge_samples = static_cast<int>(o.integer("edge_samples", co.edge_samples));
  co.loft.samples = static_cast<int>(o.integer("samples", co.loft.samples));
  return luax::guarded(L, [&] {
    ClosedBlade b = close_blade(*pressure, *suction, co);
    const std::vector<double> section_u = b.loft.section_u;
    push_surface(L, std::make_shared<const BSplineSurface>(std::move(b.loft.surface)));
    lua_createtable(L, 0, 5);
    luax::set_number(L, "le_v", b.le_v);
    luax::set_number(L, "te_v", b.te_v);
    luax::set_number(L, "perimeter", b.perimeter_mm);
    luax::set_number(L, "edge_kink", b.edge_kink_deg);
    luax::set_numbers(L, "section_u", section_u);
    return 2;
  });
}


void push_result(lua_State* L, const RepairPathResult& r) {
  lua_createtable(L, 0, 24);
  luax::set_string(L, "pattern", repair_pattern_name(r.pattern));
  int poses = 0, tilted = 0;
  lua_createtable(L, static_cast<int>(r.layers.size()), 0);
  for (size_t i = 0; i < r.layers.size(); ++i) {
    const RepairLayer& l = r.layers[i];
    poses += l.poses;
    tilted += l.tilted;
    lua_createtable(L, 0, 13);
    luax::set_number(L, "offset", l.offset_mm);
    luax::set_bool(L, "finishing", l.finishing);
    luax::set_number(L, "scallop", l.scallop_mm);
    luax::set_number(L, "chord_tol", l.chord_tol_mm);
    luax::set_number(L, "passes", l.passes);
    luax::set_number(L, "poses", l.poses);
    luax::set_number(L, "tilted", l.tilted);
    luax::set_number(L, "refusals", l.refusals);
    luax::set_number(L, "max_deviation", l.max_deviation_mm);
    luax::set_number(L, "step_over_min", l.step_over_min_mm);
    luax::set_number(L, "step_over_max", l.step_over_max_mm);
    luax::set_number(L, "turns", l.turns);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "layers");
  luax::set_number(L, "passes", static_cast<double>(r.passes.size()));
  luax::set_number(L, "poses", poses);
  luax::set_number(L, "tilted", tilted);
  luax::set_number(L, "bridges", r.bridges);
  luax::set_number(L, "links", r.links);
  luax::set_number(L, "refused_connections", r.refused_connections);
  luax::set_number(L, "gouge_refusals", r.gouge_refusals);
  luax::set_number(L, "gouge_splits", r.gouge_splits);
  luax::set_number(L, "tilt_fills", r.tilt_fills);
  luax::set_number(L, "lifted", r.lifted);
  luax::set_number(L, "max_lift", r.max_lift_mm);
  luax::set_number(L, "max_deviation", r.max_deviation_mm);
  luax::set_number(L, "guard_spacing", r.guard_spacing_mm);
  luax::set_number(L, "paths_seconds", r.paths_seconds);
  luax::set_number(L, "connect_seconds", r.connect_seconds);
  lua_createtable(L, static_cast<int>(r.refusals.size()), 0);
  for (size_t i = 0; i < r.refusals.size(); ++i) {
    const RepairRefusal& f = r.refusals[i];
    lua_createtable(L, 0, 5);
    luax::set_number(L, "layer", f.layer + 1);
    luax::set_number(L, "u", f.u);
    luax::set_number(L, "v", f.v);
    luax::set_vec3(L, "point", f.contact);
    luax::set_string(L, "reason", f.reason);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "refusals");
  // The connections that were refused, with why.
  set_refused_connections(L, "refused", r.connections);
  // Per pass: its layer, u, direction, poses and the step-over to the next.
  lua_createtable(L, static_cast<int>(r.passes.size()), 0);
  for (size_t i = 0; i < r.passes.size(); ++i) {
    const RepairPass& p = r.passes[i];
    lua_createtable(L, 0, 6);
    luax::set_number(L, "layer", p.layer + 1);
    luax::set_number(L, "u", p.u);
    luax::set_bool(L, "reversed", p.reversed);
    luax::set_number(L, "poses", static_cast<double>(p.poses.size()));
    luax::set_number(L, "step_over", p.step_over_mm);
    luax::set_number(L, "max_deviation", p.max_deviation_mm);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "pass_list");
  const RepairMoves m = repair_moves(r);
  long first_finish = 0;
  lua_createtable(L, static_cast<int>(m.moves.size()), 0);
  for (size_t i = 0; i < m.moves.size(); ++i) {
    const Move& mv = m.moves[i];
    const int layer = m.layer_of[i];
    if (!first_finish && r.layers[layer].finishing) first_finish = static_cast<long>(i + 1);
    lua_createtable(L, 0, 7);
    luax::set_string(L, "kind", to_string(mv.kind));
    luax::set_string(L, "motion", mv.motion);
    if (mv.kind != Move::Kind::Stop) {
      luax::set_vec3(L, "tip", mv.pose.tip);
      luax::set_vec3(L, "axis", mv.pose.axis);
    } else {
      luax::set_string(L, "reason", mv.reason);
    }
    luax::set_number(L, "row", mv.row + 1);
    luax::set_number(L, "layer", layer + 1);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "moves");
  luax::set_number(L, "first_finishing_move", static_cast<double>(first_finish));
}

// bliskrun.repair_paths{design=, tool=, world=, pattern=, u=, v=, ...} -> plan table
int w_repair_paths(lua_State* L) {
  static const char* what = "bliskrun.repair_paths";
  const luax::Options o(
      L, 1, what,
      {Field{"design", Kind::Any, true, std::nullopt, std::nullopt,
             "design surface (Surface): u span, v around (closed: bliskrun.close_blade), pu x pv out of the material",
             {}},
       Field{"tool", Kind::Any, true, std::nullopt, std::nullopt, "a ball-end mill (bliskrun.ball_end_mill)", {}},
       Field{"world", Kind::Any, true, std::nullopt, std::nullopt,
             "CollisionWorld: the blade (shank and holder) and the fixture", {}},
       Field{"pattern", Kind::String, false, std::nullopt, std::nullopt,
             "\"zigzag\" (§2.1, edge) or \"spiral\" (§2.2, tip, once around); default \"zigzag\"",
             {"zigzag", "spiral"}},
       Field{"u", Kind::Table, false, std::nullopt, std::nullopt, "span window of the region {u0, u1}", {}},
       Field{"v", Kind::Table, false, std::nullopt, std::nullopt,
             "around window of the region {v0, v1} (zigzag; v0 > v1: through the seam v = 0, which the zigzag "
             "refuses; the spiral goes all the way round and ignores it)", {}},
       Field{"flip_normal", Kind::Boolean, false, std::nullopt, std::nullopt,
             "the design's pu x pv points into the material (default false)", {}},
       number_field("deposit", "largest deposit thickness over the region, mm (default 2)", 0, 100),
       number_field("layer", "depth of cut per roughing layer, mm (default 0.5)", 1e-3, 100),
       number_field("stock", "left for finishing by the last roughing layer, mm (default 0.2)", 0, 100),
       number_field("scallop", "finishing scallop height, mm (default 0.005)", 1e-6, 10),
       number_field("rough_scallop", "roughing scallop height, mm (default 0.05)", 1e-6, 10),
       number_field("chord_tol", "finishing chord tolerance, mm (default 0.002)", 1e-6, 10),
       number_field("rough_chord_tol", "roughing chord tolerance, mm (default 0.01)", 1e-6, 10),
       number_field("max_step", "longest step along a pass, mm (default 2)", 1e-3, 100),
       number_field("lead", "tool axis: the normal leaned towards the feed by this, degrees (default 10)", -60, 60),
       number_field("tilt_back", "where not clear: the lead reduced through the normal to this far back, degrees "
                    "(default 30)", 0, 80),
       number_field("lead_step", "step of that search, degrees (default 2)", 0.01, 45),
       number_field("side_tilt", "and turned sideways up to ± this, degrees (default 30; 0: none)", 0, 90),
       number_field("side_step", "step of the sideways turn, degrees (default 10)", 0.01, 90),
       number_field("clearance", "shank and holder clearance from the world, mm (default 0.5)", 0, 100),
       number_field("cutter_clearance", "cutter clearance from the world (the fixture), mm (default 0)", 0, 100),
       number_field("arc_radius", "lead-out / lead-in arc radius, mm (default 1)", 1e-3, 100),
       number_field("arc_angle", "arc angle, degrees (default 90)", 1, 180),
       Field{"arc_segments", Kind::Integer, false, 1, 1000, "moves per arc (default 6)", {}},
       Field{"bridge_segments", Kind::Integer, false, 2, 1000, "moves per bridge (default 12)", {}},
       number_field("retract", "links: largest offset along the normal, mm (default 5)", 1e-3, 1000),
       number_field("min_retract", "links: smallest offset tried, mm (default 0.1)", 1e-4, 1000),
       number_field("allowed_overcut", "how far a non-cutting move may dip below the design, mm (default 0.002)", 0,
                    1),
       number_field("guard_spacing", "design samples of the gouge guard, mm apart (default 0.1)", 0.005, 10),
       number_field("max_lift", "finishing: the most a contact is lifted off the design so the ball does not cut "
                    "the troughs beside it, mm (default 0.005; 0: refuse such contacts)", 0, 1),
       Field{"threads", Kind::Integer, false, 1, 256,
             "layers planned on this many threads (default: the run's --threads); the plan does not depend on it", {}}});
  RepairPathRequest rq;
  rq.design = surface_option(L, o, what, "design");
  o.push_raw("tool");
  LuaTool* lt = luax::test<LuaTool>(L, -1);
  if (!lt) luax::error(L, std::string(what) + ": option 'tool': expected a bliskrun.Tool (a ball-end mill)");
  lua_pop(L, 1);
  const std::shared_ptr<const CollisionWorld> world = world_option(L, o, what);
  rq.tool = &lt->tool;
  rq.world = world.get();
  rq.pattern = o.string("pattern", "zigzag") == "spiral" ? RepairPattern::Spiral : RepairPattern::Zigzag;
  read_unit_window(L, o, what, "u", rq.u0, rq.u1);
  if (o.has("v")) {
    // As read_unit_window, but v0 > v1 is a window through the seam: the
    // core takes it for the spiral and refuses it by name for the zigzag.
    o.push_raw("v");
    const int t = lua_gettop(L);
    const std::string where = std::string(what) + ": option 'v'";
    if (!lua_istable(L, t) || luaL_len(L, t) != 2) luax::error(L, where + ": expected {v0, v1} with v0, v1 in [0, 1]");
    lua_rawgeti(L, t, 1);
    lua_rawgeti(L, t, 2);
    if (!lua_isnumber(L, -2) || !lua_isnumber(L, -1)) luax::error(L, where + ": expected two numbers");
    rq.v0 = lua_tonumber(L, -2);
    rq.v1 = lua_tonumber(L, -1);
    if (!(rq.v0 >= 0 && rq.v0 <= 1 && rq.v1 >= 0 && rq.v1 <= 1 && rq.v0 != rq.v1))
      luax::error(L, where + ": expected {v0, v1} with v0, v1 in [0, 1] and v0 ~= v1 (v0 > v1: through the seam)");
    lua_pop(L, 3);
  }
  rq.flip_normal = o.boolean("flip_normal", false);
  rq.deposit_mm = o.number("deposit", rq.deposit_mm);
  rq.layer_mm = o.number("layer", rq.layer_mm);
  rq.stock_mm = o.number("stock", rq.stock_mm);
  rq.scallop_mm = o.number("scallop", rq.scallop_mm);
  rq.rough_scallop_mm = o.number("rough_scallop", rq.rough_scallop_mm);
  rq.steps.chord_tol_mm = o.number("chord_tol", rq.steps.chord_tol_mm);
  rq.rough_chord_tol_mm = o.number("rough_chord_tol", rq.rough_chord_tol_mm);
  rq.steps.max_step_mm = o.number("max_step", rq.steps.max_step_mm);
  const double lead = o.number("lead", 10);
  rq.tilt.lead0_rad = deg_to_rad(90 - lead);
  rq.tilt.lead_max_rad = deg_to_rad(90 + o.number("tilt_back", 30));
  if (rq.tilt.lead_max_rad < rq.tilt.lead0_rad) rq.tilt.lead_max_rad = rq.tilt.lead0_rad;
  rq.tilt.lead_step_rad = deg_to_rad(o.number("lead_step", 2));
  rq.tilt.tilt_range_rad = deg_to_rad(o.number("side_tilt", 30));
  rq.tilt.allow_tilt = rq.tilt.tilt_range_rad > 0;
  rq.tilt.tilt_step_rad = deg_to_rad(o.number("side_step", 10));
  rq.tilt.clearances.shank_mm = rq.tilt.clearances.holder_mm = o.number("clearance", 0.5);
  rq.tilt.clearances.cutter_mm = o.number("cutter_clearance", 0);
  rq.arc_radius_mm = o.number("arc_radius", rq.arc_radius_mm);
  rq.arc_angle_rad = deg_to_rad(o.number("arc_angle", 90));
  rq.arc_segments = static_cast<int>(o.integer("arc_segments", rq.arc_segments));
  rq.bridge_segments = static_cast<int>(o.integer("bridge_segments", rq.bridge_segments));
  rq.links.retract_mm = o.number("retract", rq.links.retract_mm);
  rq.links.min_retract_mm = o.number("min_retract", rq.links.min_retract_mm);
  rq.links.allowed_overcut_mm = o.number("allowed_overcut", rq.links.allowed_overcut_mm);
  rq.guard_spacing_mm = o.number("guard_spacing", rq.guard_spacing_mm);
  rq.max_lift_mm = o.number("max_lift", rq.max_lift_mm);
  rq.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
  return luax::guarded(L, [&] {
    const RepairPathResult r = plan_repair_paths(rq, context(L).progress);
    push_result(L, r);
    return 1;
  });
}

}  // namespace

void open_repair_paths(lua_State* L) {
  static const luaL_Reg functions[] = {
      {"close_blade", w_close_blade}, {"repair_paths", w_repair_paths}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
