// bliskrun.belt_paths{...}: contact-wheel paths over a blade face for robotic
// belt grinding (belt paper §2, core/planning/belt_paths.h).
#include <memory>
#include <string>

#include "core/planning/belt_paths.h"
#include "lua_api/lua_tool.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;

using luax::number_field;

void push_points(lua_State* L, const std::vector<Vec3>& points) {
  lua_createtable(L, static_cast<int>(points.size()), 0);
  for (size_t i = 0; i < points.size(); ++i) {
    luax::push(L, points[i]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
}

// bliskrun.belt_paths{face=, wheel={radius=, width=}, chord_tol=, scallop=, ...} -> plan table
int w_belt_paths(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.belt_paths",
      {Field{"face", Kind::Any, true, std::nullopt, std::nullopt, "the face to grind (Surface)", {}},
       Field{"wheel", Kind::Any, true, std::nullopt, std::nullopt,
             "contact wheel (bliskrun.contact_wheel{radius, width}); its width lies along the path", {}},
       number_field("chord_tol", "chord error along a path (eq. 1-2), mm; default 0.01", 1e-6, 10),
       number_field("scallop", "scallop height between paths (eq. 3-5), mm; default 0.005", 1e-6, 10),
       Field{"along", Kind::String, false, std::nullopt, std::nullopt,
             "paths run along \"v\" (chord, at constant u) or \"u\"; default \"v\"", {"u", "v"}},
       Field{"normal", Kind::String, false, std::nullopt, std::nullopt,
             "the wheel's side: \"pu_x_pv\" (default) or \"reversed\"", {"pu_x_pv", "reversed"}},
       Field{"correction", Kind::Boolean, false, std::nullopt, std::nullopt,
             "the paper's eq. 6 (larger curvature of this and the predicted point); default true", {}},
       Field{"guarantee", Kind::Boolean, false, std::nullopt, std::nullopt,
             "shorten steps / step-overs whose measured chord / scallop exceeds the tolerance; default true", {}},
       number_field("max_step", "longest step along a path, mm; default 20", 1e-3, 1000),
       Field{"scallop_samples", Kind::Integer, false, 4, 1000,
             "cross-section samples per point when measuring the scallop; default 24", {}}});
  o.push_raw("face");
  const std::shared_ptr<const Surface> face = luax::check<SurfaceHandle>(L, -1).surface;
  lua_pop(L, 1);
  // The wheel is the one tool model of a contact wheel (bliskrun.contact_wheel).
  ContactWheel wheel;
  o.push_raw("wheel");
  {
    const Tool& t = luax::check<LuaTool>(L, -1).tool;
    if (t.kind() != ToolKind::ContactWheel)
      luax::error(L, "bliskrun.belt_paths: option 'wheel': expected a contact wheel (bliskrun.contact_wheel), got " +
                         t.description());
    wheel.radius_mm = t.radius_at(t.flank_contact_height());
    wheel.width_mm = t.cutter().z_max() - t.cutter().z_min();
  }
  lua_pop(L, 1);
  BeltPathOptions bo;
  bo.chord_tol_mm = o.number("chord_tol", bo.chord_tol_mm);
  bo.scallop_mm = o.number("scallop", bo.scallop_mm);
  bo.direction = o.string("along", "v") == "v" ? BeltPathDirection::AlongV : BeltPathDirection::AlongU;
  bo.normal_along_pu_x_pv = o.string("normal", "pu_x_pv") == "pu_x_pv";
  bo.paper_correction = o.boolean("correction", true);
  bo.guarantee = o.boolean("guarantee", true);
  bo.max_step_mm = o.number("max_step", bo.max_step_mm);
  bo.scallop_samples = static_cast<int>(o.integer("scallop_samples", bo.scallop_samples));
  return luax::guarded(L, [&] {
    const BeltPlan plan = plan_belt_paths(*face, wheel, bo, context(L).progress);
    lua_createtable(L, 0, 8);
    luax::set_number(L, "points", static_cast<double>(plan.points));
    luax::set_number(L, "chord_max", plan.chord_max_mm);
    luax::set_number(L, "scallop_max", plan.scallop_max_mm);
    luax::set_number(L, "step_halvings", plan.step_halvings);
    luax::set_number(L, "step_over_shrinks", plan.step_over_shrinks);
    lua_createtable(L, static_cast<int>(plan.paths.size()), 0);
    for (size_t j = 0; j < plan.paths.size(); ++j) {
      const BeltPath& p = plan.paths[j];
      lua_createtable(L, 0, 10);
      luax::set_number(L, "across", p.across);
      luax::set_number(L, "length", p.length_mm);
      luax::set_number(L, "chord_max", p.chord_max_mm);
      luax::set_number(L, "scallop_max", p.scallop_max_mm);
      luax::set_numbers(L, "along", p.along);
      push_points(L, p.points);
      lua_setfield(L, -2, "points");
      push_points(L, p.normals);
      lua_setfield(L, -2, "normals");
      push_points(L, p.tangents);
      lua_setfield(L, -2, "tangents");
      luax::set_numbers(L, "step_over", p.step_over_mm);
      luax::set_numbers(L, "chord", p.chord_mm);
      lua_rawseti(L, -2, static_cast<lua_Integer>(j + 1));
    }
    lua_setfield(L, -2, "paths");
    return 1;
  });
}

}  // namespace

void open_belt(lua_State* L) {
  static const luaL_Reg functions[] = {{"belt_paths", w_belt_paths}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
