// Curvature analysis and drum-wheel design in Lua (blisk paper §2.2, Table 1
// and 2): bliskrun.curvature_stats, bliskrun.design_drum_wheel, and the
// curvature map's SVG picture (Fig. 11). Curvatures 1/mm, angles degrees.
#include <memory>

#include "core/analysis/curvature_map.h"
#include "core/analysis/curvature_stats.h"
#include "core/analysis/passage.h"
#include "core/analysis/wheel_design.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

struct CurvatureMapHandle {
  std::shared_ptr<const CurvatureStats> stats;
};

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <> struct TypeName<lua_api::CurvatureMapHandle> { static constexpr const char* name = "bliskrun.CurvatureMap"; };
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;

using luax::set_number;

void push_extreme(lua_State* L, const CurvatureExtreme& e) {
  lua_createtable(L, 0, 5);
  set_number(L, "value", e.value);
  set_number(L, "u", e.u);
  set_number(L, "v", e.v);
  set_number(L, "angle", rad_to_deg(e.angle_rad));
  luax::set_bool(L, "found", e.found);
}

// bliskrun.curvature_stats(surface [, {samples_u=, samples_v=, c_range=}])
int w_curvature_stats(lua_State* L) {
  const auto surface = luax::check<SurfaceHandle>(L, 1).surface;
  const luax::Options o(
      L, 2, "bliskrun.curvature_stats",
      {Field{"samples_u", Kind::Integer, false, 2, 1e5, "samples along u; default 100", {}},
       Field{"samples_v", Kind::Integer, false, 2, 1e5, "samples along v; default 500", {}},
       Field{"c_range", Kind::Number, false, 0, 180,
             "half-width of the allowed tool-axis range about the span direction, degrees; default 30", {}}});
  CurvatureStatsOptions opts;
  opts.samples_u = static_cast<int>(o.integer("samples_u", opts.samples_u));
  opts.samples_v = static_cast<int>(o.integer("samples_v", opts.samples_v));
  const double c_range_deg = o.number("c_range", 30.0);
  opts.c_range_rad = deg_to_rad(c_range_deg);
  return luax::guarded(L, [&] {
    auto st = std::make_shared<const CurvatureStats>(
        curvature_stats(*surface, opts, context(L).progress));
    lua_createtable(L, 0, 10);
    luax::set_integer(L, "samples_u", st->samples_u);
    luax::set_integer(L, "samples_v", st->samples_v);
    luax::set_integer(L, "negative_K_count", st->negative_K_count);
    set_number(L, "negative_K_fraction", st->negative_K_fraction);
    set_number(L, "K_min", st->K_min);
    set_number(L, "K_max", st->K_max);
    set_number(L, "c_range", c_range_deg);
    push_extreme(L, st->k1_max);
    lua_setfield(L, -2, "k1_max");
    push_extreme(L, st->k2_max);
    lua_setfield(L, -2, "k2_max");
    push_extreme(L, st->ke_max);
    lua_setfield(L, -2, "ke_max");
    luax::push_new(L, CurvatureMapHandle{std::move(st)});
    lua_setfield(L, -2, "map");
    return 1;
  });
}

const CurvatureStats& check_map(lua_State* L) { return *luax::check<CurvatureMapHandle>(L, 1).stats; }

int w_map_size(lua_State* L) {
  const CurvatureStats& st = check_map(L);
  lua_pushinteger(L, st.samples_u);
  lua_pushinteger(L, st.samples_v);
  return 2;
}

// map:at(i, j), 1-based: sample at u = (i-1)/(samples_u-1), v = (j-1)/(samples_v-1)
int w_map_at(lua_State* L) {
  const CurvatureStats& st = check_map(L);
  const long long i = luax::check_integer(L, 2, "i"), j = luax::check_integer(L, 3, "j");
  if (i < 1 || i > st.samples_u || j < 1 || j > st.samples_v)
    luax::error(L, "map:at(" + std::to_string(i) + ", " + std::to_string(j) + "): indices run 1.." +
                       std::to_string(st.samples_u) + ", 1.." + std::to_string(st.samples_v));
  const CurvatureSample& s = st.at(static_cast<int>(i - 1), static_cast<int>(j - 1));
  lua_createtable(L, 0, 5);
  set_number(L, "K", s.K);
  set_number(L, "H", s.H);
  set_number(L, "k1", s.k1);
  set_number(L, "k2", s.k2);
  set_number(L, "ke", s.ke);
  return 1;
}

// map:write_svg / map:write_png (path [, {title=, levels=, width=, height=}]) -> full path
int write_map(lua_State* L, const char* where, bool png) {
  const auto stats = luax::check<CurvatureMapHandle>(L, 1).stats;
  const std::string target = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  const luax::Options o(
      L, 3, where,
      {Field{"title", Kind::String, false, std::nullopt, std::nullopt, "picture title", {}},
       Field{"levels", Kind::Integer, false, 2, 1024, "colours in the scale; default 64", {}},
       Field{"width", Kind::Integer, false, 50, 10000, "plot width, px; default 800", {}},
       Field{"height", Kind::Integer, false, 50, 10000, "plot height, px; default 320", {}}});
  CurvatureMapOptions opts;
  opts.title = o.string("title", opts.title);
  opts.levels = static_cast<int>(o.integer("levels", opts.levels));
  opts.plot_width_px = static_cast<int>(o.integer("width", opts.plot_width_px));
  opts.plot_height_px = static_cast<int>(o.integer("height", opts.plot_height_px));
  return luax::guarded(L, [&] {
    if (png)
      write_curvature_map_png(*stats, target, opts);
    else
      write_curvature_map_svg(*stats, target, opts);
    lua_pushstring(L, target.c_str());
    return 1;
  });
}
int w_map_write_svg(lua_State* L) { return write_map(L, "map:write_svg", false); }
int w_map_write_png(lua_State* L) { return write_map(L, "map:write_png", true); }

void push_choice(lua_State* L, const WheelChoice& c) {
  lua_createtable(L, 0, 4);
  set_number(L, "radius_limit", c.radius_limit_mm);
  set_number(L, "barrel_radius", c.drum_radius_mm);
  set_number(L, "diameter_limit", c.diameter_limit_mm);
  set_number(L, "max_diameter", c.diameter_mm);
}

// bliskrun.design_drum_wheel{k1_max=, ke_max=, d_min=, clearance=, diameter_step=, radius_step=}
int w_design_drum_wheel(lua_State* L) {
  const WheelDesignOptions d;
  const luax::Options o(
      L, 1, "bliskrun.design_drum_wheel",
      {Field{"k1_max", Kind::Number, true, 0, std::nullopt, "|max k1| over K < 0, 1/mm", {}},
       Field{"ke_max", Kind::Number, true, 0, std::nullopt, "|max k_e| within the C range, 1/mm", {}},
       Field{"d_min", Kind::Number, true, 0, std::nullopt, "narrowest blade passage, mm", {}},
       Field{"clearance", Kind::Number, false, 0, std::nullopt, "safety distance taken off d_min, mm; default 2", {}},
       Field{"diameter_step", Kind::Number, false, 0, std::nullopt, "D_t is a multiple of this, mm; default 1", {}},
       Field{"radius_step", Kind::Number, false, 0, std::nullopt, "R_c is a multiple of this, mm; default 10", {}}});
  const WheelDesignInput in{o.number("k1_max", 0), o.number("ke_max", 0), o.number("d_min", 0)};
  WheelDesignOptions opts;
  opts.passage_clearance_mm = o.number("clearance", d.passage_clearance_mm);
  opts.diameter_step_mm = o.number("diameter_step", d.diameter_step_mm);
  opts.drum_radius_step_mm = o.number("radius_step", d.drum_radius_step_mm);
  return luax::guarded(L, [&] {
    const WheelDesign w = design_drum_wheel(in, opts);
    lua_createtable(L, 0, 2);
    push_choice(L, w.traditional);
    lua_setfield(L, -2, "traditional");
    push_choice(L, w.extended);
    lua_setfield(L, -2, "extended");
    return 1;
  });
}

// bliskrun.narrowest_passage(flank_a, flank_b) -> {distance, ua, va, ub, vb}
int w_narrowest_passage(lua_State* L) {
  const Surface& a = *luax::check<SurfaceHandle>(L, 1).surface;
  const Surface& b = *luax::check<SurfaceHandle>(L, 2).surface;
  return luax::guarded(L, [&] {
    const PassageDistance d = narrowest_passage(a, b);
    lua_createtable(L, 0, 5);
    luax::set_number(L, "distance", d.distance_mm);
    luax::set_number(L, "ua", d.ua);
    luax::set_number(L, "va", d.va);
    luax::set_number(L, "ub", d.ub);
    luax::set_number(L, "vb", d.vb);
    return 1;
  });
}

}  // namespace

void open_analysis(lua_State* L) {
  static const luaL_Reg map_methods[] = {{"size", w_map_size},
                                         {"at", w_map_at},
                                         {"write_svg", w_map_write_svg}, {"write_png", w_map_write_png},
                                         {nullptr, nullptr}};
  luax::register_type<CurvatureMapHandle>(L, map_methods);
  static const luaL_Reg functions[] = {{"curvature_stats", w_curvature_stats},
                                       {"design_drum_wheel", w_design_drum_wheel},
                                       {"narrowest_passage", w_narrowest_passage},
                                       {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
