// bliskrun.flank_mill{...}: five-axis flank milling of one ruled face
// (impeller paper §4.3, core/planning/flank_milling.h) with interference
// checks, lead-in/out, the residual along every axis (§5) and its map.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/planning/flank_milling.h"
#include "lua_api/lua_tool.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/undercut_map.h"
#include "lua_api/wrap_collision.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;

using luax::number_field;

void push_stats(lua_State* L, const ResidualStats& s) {
  lua_createtable(L, 0, 6);
  luax::set_number(L, "max", s.max_mm);
  luax::set_number(L, "min", s.min_mm);
  luax::set_number(L, "mean", s.mean_mm);
  luax::set_number(L, "std", s.std_mm);
  luax::set_number(L, "max_abs", s.max_abs_mm);
  luax::set_number(L, "samples", s.samples);
}

void push_departure(lua_State* L, const PlannedDeparture& d) {
  lua_createtable(L, 0, 4);
  luax::set_bool(L, "clear", d.clear);
  if (d.clear) {
    push_pose(L, d.away);
    lua_setfield(L, -2, "away");
  }
  luax::set_number(L, "offset", d.offset_mm);
  luax::set_string(L, "reason", d.reason);
}

// bliskrun.flank_mill{face=, hub=, tool=, ball_radius=, world=, ...} -> plan table
int w_flank_mill(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.flank_mill",
      {Field{"face", Kind::Any, true, std::nullopt, std::nullopt,
             "ruled face (Surface, u along the rulings hub -> shroud, normal out of the material)", {}},
       Field{"hub", Kind::Any, false, std::nullopt, std::nullopt,
             "hub surface of revolution (impeller:hub()); without it the ball centre is at D2", {}},
       Field{"tool", Kind::Any, true, std::nullopt, std::nullopt, "ball-end or tapered ball-end mill", {}},
       number_field("ball_radius", "radius of the tool's tip ball, mm (required)", 1e-6),
       Field{"world", Kind::Any, false, std::nullopt, std::nullopt,
             "CollisionWorld: neighbouring blades (all parts), this face and the hub (shank, holder)", {}},
       number_field("chord_tol", "chord tolerance along both boundary curves, mm; default 0.005", 1e-6, 10),
       number_field("max_step", "longest step along the chord, mm; default 5", 1e-3, 1000),
       number_field("clearance", "clearance of the shank and holder, mm; default 0.5", 0, 100),
       number_field("max_tilt", "largest tilt about the hub contact normal, degrees; default 10", 0, 60),
       number_field("tilt_step", "tilt step, degrees; default 1", 0.01, 30),
       number_field("lead_retract", "lead-in/out distance along the face normal, mm; default 5", 0.01, 1000),
       Field{"design", Kind::Any, false, std::nullopt, std::nullopt,
             "design face the residual is measured against (default: face), when face is a ruled fit of it", {}},
       Field{"balance", Kind::Boolean, false, std::nullopt, std::nullopt,
             "shift each axis along the mean face normal to centre its residual on zero; default false", {}},
       Field{"residual_points", Kind::Integer, false, 2, 10000,
             "points along each axis for the residual; default 40", {}},
       Field{"optimise", Kind::Boolean, false, std::nullopt, std::nullopt,
             "fit each untilted axis to the design face (least squares, then minimax); default true", {}},
       number_field("max_axis_correction", "largest turn of a fitted axis from the two-contact axis, degrees; default 0.5",
                    0, 10),
       number_field("overcut_weight", "overcut counts this many times material left in the fit (>= 1); default 1", 1,
                    100)});
  o.push_raw("face");
  const std::shared_ptr<const Surface> face = luax::check<SurfaceHandle>(L, -1).surface;
  lua_pop(L, 1);
  std::shared_ptr<const Surface> hub_surface;
  const SurfaceOfRevolution* hub = nullptr;
  if (o.has("hub")) {
    o.push_raw("hub");
    hub_surface = luax::check<SurfaceHandle>(L, -1).surface;
    lua_pop(L, 1);
    hub = dynamic_cast<const SurfaceOfRevolution*>(hub_surface.get());
    if (!hub) luax::error(L, "bliskrun.flank_mill: option 'hub': expected a surface of revolution (impeller:hub())");
  }
  o.push_raw("tool");
  LuaTool& tool = luax::check<LuaTool>(L, -1);
  lua_pop(L, 1);
  std::shared_ptr<const CollisionWorld> world;
  if (o.has("world")) {
    o.push_raw("world");
    world = luax::check<LuaWorld>(L, -1).world;
    lua_pop(L, 1);
  }
  std::shared_ptr<const Surface> design;
  if (o.has("design")) {
    o.push_raw("design");
    design = luax::check<SurfaceHandle>(L, -1).surface;
    lua_pop(L, 1);
  }
  if (!o.has("ball_radius")) luax::error(L, "bliskrun.flank_mill: missing required option 'ball_radius'");
  return luax::guarded(L, [&] {
    const FlankCutter cutter(tool.tool, o.number("ball_radius", 0));
    FlankFaceRequest rq;
    rq.face = face.get();
    rq.hub = hub;
    rq.cutter = &cutter;
    rq.world = world.get();
    rq.body = world ? &tool.body() : nullptr;
    const double clearance = o.number("clearance", 0.5);
    rq.clearances.shank_mm = rq.clearances.holder_mm = clearance;
    rq.steps.chord_tol_mm = o.number("chord_tol", 0.005);
    rq.steps.max_step_mm = o.number("max_step", 5.0);
    rq.max_tilt_rad = deg_to_rad(o.number("max_tilt", 10));
    rq.tilt_step_rad = deg_to_rad(o.number("tilt_step", 1));
    rq.lead.retract_mm = o.number("lead_retract", 5);
    rq.lead.min_retract_mm = std::min(rq.lead.min_retract_mm, rq.lead.retract_mm);
    rq.residual_points = static_cast<int>(o.integer("residual_points", 40));
    rq.design = design.get();
    rq.balance_residual = o.boolean("balance", false);
    rq.optimise = o.boolean("optimise", true);
    rq.fit.max_axis_correction_rad = deg_to_rad(o.number("max_axis_correction", 0.5));
    rq.fit.overcut_weight = o.number("overcut_weight", 1.0);
    const FlankFacePlan plan = plan_flank_face(rq);

    lua_createtable(L, 0, 16);
    luax::set_number(L, "stations", plan.stations);
    luax::set_number(L, "tilted", plan.tilted);
    luax::set_number(L, "min_margin", plan.min_margin_mm);
    luax::set_number(L, "pose_min_margin", plan.pose_min_margin_mm);
    if (std::isfinite(plan.lead_min_margin_mm)) luax::set_number(L, "lead_min_margin", plan.lead_min_margin_mm);
    lua_createtable(L, static_cast<int>(plan.axes.size()), 0);
    for (size_t i = 0; i < plan.axes.size(); ++i) {
      const FlankAxis& a = plan.axes[i];
      push_pose(L, a.pose);
      luax::set_number(L, "v", a.v);
      luax::set_number(L, "tilt", rad_to_deg(plan.tilt_rad[i]));
      luax::set_vec3(L, "d1", a.d1);
      luax::set_vec3(L, "d2", a.d2);
      luax::set_vec3(L, "ball_centre", a.ball_centre);
      luax::set_number(L, "s1", a.s1);
      luax::set_number(L, "correction", rad_to_deg(plan.correction_rad[i]));
      if (i < plan.root_corner_mm.size()) luax::set_number(L, "root_corner", plan.root_corner_mm[i]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "poses");
    lua_createtable(L, static_cast<int>(plan.refusals.size()), 0);
    for (size_t i = 0; i < plan.refusals.size(); ++i) {
      lua_createtable(L, 0, 2);
      luax::set_number(L, "v", plan.refusals[i].v);
      luax::set_string(L, "reason", plan.refusals[i].reason);
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "refusals");
    push_departure(L, plan.lead_in);
    lua_setfield(L, -2, "lead_in");
    push_departure(L, plan.lead_out);
    lua_setfield(L, -2, "lead_out");
    push_stats(L, plan.residual.stats);
    lua_setfield(L, -2, "residual");
    push_stats(L, plan.residual_unbalanced);
    lua_setfield(L, -2, "residual_unbalanced");
    luax::set_number(L, "balanced", plan.balanced);
    push_stats(L, plan.residual_before);
    lua_setfield(L, -2, "residual_before");
    luax::set_number(L, "optimised", plan.optimised);
    if (!plan.root_corner_mm.empty()) {
      push_stats(L, plan.root_corner);
      lua_setfield(L, -2, "root_corner");
    }
    // Residual per pose: {max, min, mean, std} along each axis.
    lua_createtable(L, plan.residual.axes, 0);
    for (int a = 0; a < plan.residual.axes; ++a) {
      const auto first = plan.residual.residual_mm.begin() + static_cast<long>(a) * plan.residual.points;
      push_stats(L, residual_stats(std::vector<double>(first, first + plan.residual.points)));
      lua_rawseti(L, -2, a + 1);
    }
    lua_setfield(L, -2, "residual_per_pose");
    luax::set_string(L, "apt", flank_face_apt(plan, "bliskrun flank finish", tool.tool.description()));
    // The residual map (map:write_png): chord across, hub at the bottom.
    if (plan.residual.axes > 0) {
      const int rows = plan.residual.points, cols = plan.residual.axes;
      std::vector<double> values(static_cast<size_t>(rows) * cols);
      for (int a = 0; a < cols; ++a)
        for (int k = 0; k < rows; ++k) values[static_cast<size_t>(k) * cols + a] = plan.residual.at(a, k);
      push_undercut_map(L, rows, cols, std::move(values),
                        "flank-milling residual (eq. 33-36), + undercut, - overcut; poses across (" +
                            std::to_string(cols) + "), points along each axis up (hub at the bottom)");
      lua_setfield(L, -2, "residual_map");
    }
    return 1;
  });
}

}  // namespace

void open_flank(lua_State* L) {
  static const luaL_Reg functions[] = {{"flank_mill", w_flank_mill}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
