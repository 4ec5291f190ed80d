// Built-in parts in Lua: bliskrun.blisk{...} -> Blisk (a BliskPart: the
// built-in one here, one from CAD through push_blisk, wrap_cad.cpp); blade models lofted
// from section loops: bliskrun.loft_sections{...} and the result table the
// part readers share (wrap_parts.h). Lengths mm, angles
// degrees (converted here); blades are numbered 1..N in Lua (blade 1 is the
// core's blade 0, blade k+1 is blade 1 turned by k * 360°/N about Z).
#include <cmath>
#include <memory>
#include <sstream>

#include "core/geometry/revolution.h"
#include "core/parts/builtin_blisk.h"
#include "lua_api/modules.h"
#include "lua_api/wrap_geometry.h"
#include "lua_api/wrap_parts.h"

namespace bliskrun::lua_api {

struct BliskHandle {
  std::shared_ptr<const BliskPart> blisk;
};

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <> struct TypeName<lua_api::BliskHandle> { static constexpr const char* name = "bliskrun.Blisk"; };
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {

std::vector<std::vector<Vec3>> check_point_loops(lua_State* L, int t, const std::string& prefix, const char* option,
                                                 const char* item) {
  std::vector<std::vector<Vec3>> loops;
  const lua_Integer n = luaL_len(L, t);
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_rawgeti(L, t, k);
    if (!lua_istable(L, -1))
      luax::error(L, prefix + "option '" + option + "': entry " + std::to_string(k) + " is not a list of points");
    const int s = lua_gettop(L);
    std::vector<Vec3> loop;
    const lua_Integer m = luaL_len(L, s);
    for (lua_Integer i = 1; i <= m; ++i) {
      lua_rawgeti(L, s, i);
      Vec3 p = Vec3::Zero();
      bool ok = lua_istable(L, -1);
      for (int c = 0; ok && c < 3; ++c) {
        lua_rawgeti(L, -1, c + 1);
        ok = lua_type(L, -1) == LUA_TNUMBER && std::isfinite(lua_tonumber(L, -1));
        if (ok) p[c] = lua_tonumber(L, -1);
        lua_pop(L, 1);
      }
      if (!ok)
        luax::error(L, prefix + "option '" + option + "': " + item + " " + std::to_string(k) + ", point " +
                           std::to_string(i) + ": expected {x, y, z} of finite numbers");
      loop.push_back(p);
      lua_pop(L, 1);
    }
    loops.push_back(std::move(loop));
    lua_pop(L, 1);
  }
  return loops;
}

std::vector<luax::Field> loft_fields() {
  using luax::Field;
  using luax::Kind;
  return {Field{"cols", Kind::Integer, false, 4, 5000, "grid columns along the chord; default 200", {}},
          Field{"edge_margin", Kind::Number, false, 0, 0.49,
                "chord fraction of each side left out at the edge circles; default 0.03", {}},
          Field{"spacing", Kind::String, false, std::nullopt, std::nullopt,
                "grid columns along the chord: \"uniform\" (default) or \"cosine\" (dense at the edges; with "
                "edge_margin = 0 the flanks carry the edge rounds)",
                {"uniform", "cosine"}},
          Field{"span_extension", Kind::Number, false, 0, 0.5,
                "fraction of the span the flanks reach past the hub and tip sections; default 0.03", {}},
          Field{"chord_fraction", Kind::String, false, std::nullopt, std::nullopt,
                "how columns correspond across sections: \"projection\" on the chord (default) or \"arc_length\"",
                {"projection", "arc_length"}},
          Field{"cross_check", Kind::Boolean, false, std::nullopt, std::nullopt,
                "also measure each interior section against the loft of the others (fit.left_out); default false", {}}};
}

LoftOptions loft_options(const luax::Options& o) {
  LoftOptions l;
  l.cols = static_cast<int>(o.integer("cols", l.cols));
  l.edge_margin = o.number("edge_margin", l.edge_margin);
  l.span_extension = o.number("span_extension", l.span_extension);
  l.cross_check = o.boolean("cross_check", false);
  if (o.string("chord_fraction", "projection") == "arc_length") l.chord_fraction = ChordFraction::arc_length;
  if (o.string("spacing", "uniform") == "cosine") l.spacing = ColumnSpacing::cosine;
  return l;
}

namespace {

void push_fit(lua_State* L, const FitStats& f) {
  lua_createtable(L, 0, 3);
  luax::set_number(L, "max_mm", f.max_mm);
  luax::set_number(L, "rms_mm", f.rms_mm);
  luax::set_integer(L, "points", f.points);
}

void push_edge(lua_State* L, const EdgeCircle& e) {
  lua_createtable(L, 0, 5);
  luax::set_vec3(L, "centre", e.centre);
  luax::set_number(L, "radius", e.radius_mm);
  luax::set_number(L, "rms_mm", e.rms_mm);
  luax::set_integer(L, "point", e.point + 1);
  luax::set_integer(L, "fitted_points", e.fitted_points);
}

// A meridian line usable as a profile: consecutive repeats dropped.
std::vector<Vec2> distinct(const std::vector<Vec2>& m) {
  std::vector<Vec2> out;
  for (const Vec2& p : m)
    if (out.empty() || (p - out.back()).norm() > 1e-9) out.push_back(p);
  return out;
}

}  // namespace

void push_blade_model(lua_State* L, const BladeSections& blade, const LoftOptions& options) {
  const BladeLoft loft = loft_blade(blade, options);
  lua_createtable(L, 0, 16);
  luax::set_integer(L, "blades", blade.blade_count);
  luax::set_integer(L, "sections", blade.sections.size());
  push_grid(L, std::make_shared<PointGrid>(loft.pressure));
  lua_setfield(L, -2, "pressure");
  push_grid(L, std::make_shared<PointGrid>(loft.suction));
  lua_setfield(L, -2, "suction");
  luax::set_integer(L, "hub_row", loft.hub_row + 1);
  luax::set_integer(L, "tip_row", loft.tip_row + 1);
  luax::set_integer(L, "rotation", loft.rotation_sign);
  luax::set_string(L, "rotation_from", loft.rotation_given ? "data" : "camber");
  luax::set_bool(L, "camber_agrees", loft.camber_agrees);
  luax::set_string(L, "chord_fraction",
                   loft.chord_fraction == ChordFraction::projection ? "projection" : "arc_length");
  if (blade.hub_meridian.size() >= 2) {
    push_meridian(L, blade.hub_meridian);
    lua_setfield(L, -2, "hub_meridian");
    push_surface(L, std::make_shared<SurfaceOfRevolution>(distinct(blade.hub_meridian)));
    lua_setfield(L, -2, "hub");
  }
  if (blade.casing_meridian.size() >= 2) {
    push_meridian(L, blade.casing_meridian);
    lua_setfield(L, -2, "casing_meridian");
    push_surface(L, std::make_shared<SurfaceOfRevolution>(distinct(blade.casing_meridian)));
    lua_setfield(L, -2, "casing");
  }
  lua_createtable(L, static_cast<int>(loft.edges.size()), 0);
  for (size_t k = 0; k < loft.edges.size(); ++k) {
    lua_createtable(L, 0, 2);
    push_edge(L, loft.edges[k].leading);
    lua_setfield(L, -2, "leading");
    push_edge(L, loft.edges[k].trailing);
    lua_setfield(L, -2, "trailing");
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_setfield(L, -2, "edges");
  push_fit(L, loft.fit);
  push_fit(L, loft.fit_pressure);
  lua_setfield(L, -2, "pressure");
  push_fit(L, loft.fit_suction);
  lua_setfield(L, -2, "suction");
  lua_createtable(L, static_cast<int>(loft.fit_sections.size()), 0);
  for (size_t k = 0; k < loft.fit_sections.size(); ++k) {
    push_fit(L, loft.fit_sections[k]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_setfield(L, -2, "sections");
  if (options.cross_check) {
    push_fit(L, loft.cross);
    lua_createtable(L, static_cast<int>(loft.cross_sections.size()), 0);
    for (size_t k = 0; k < loft.cross_sections.size(); ++k) {
      push_fit(L, loft.cross_sections[k]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "sections");
    lua_setfield(L, -2, "left_out");
  }
  lua_setfield(L, -2, "fit");
}

namespace {

using luax::Field;
using luax::Kind;

const BliskPart& check_blisk(lua_State* L) { return *luax::check<BliskHandle>(L, 1).blisk; }

// Blade number 1..N at `idx`, returned 0-based.
int check_blade(lua_State* L, int idx, const BliskPart& b) {
  const long long k = luax::check_integer(L, idx, "blade");
  if (k < 1 || k > b.blade_count())
    luax::error(L, "argument 'blade': " + std::to_string(k) + " is outside 1.." +
                       std::to_string(b.blade_count()));
  return static_cast<int>(k - 1);
}

FlankSide check_side(lua_State* L, int idx) {
  const std::string s = luax::check_string(L, idx, "side");
  if (s == "pressure") return FlankSide::kPressure;
  if (s == "suction") return FlankSide::kSuction;
  luax::error(L, "argument 'side': expected \"pressure\" or \"suction\", got \"" + s + "\"");
}

// bliskrun.blisk{...}: every BliskParams field, under the same name (so core
// errors and recipe keys agree), angles in degrees.
int w_blisk(lua_State* L) {
  const BliskParams d;
  auto num = [](const char* name, double fallback, const char* doc) {
    std::ostringstream s;
    s << doc << "; default " << fallback;
    return Field{name, Kind::Number, false, std::nullopt, std::nullopt, s.str(), {}};
  };
  auto deg = [&](const char* name, double fallback_rad, const char* doc) {
    return num(name, rad_to_deg(fallback_rad), doc);
  };
  const luax::Options o(
      L, 1, "bliskrun.blisk",
      {Field{"blade_count", Kind::Integer, false, 2, 400, "number of blades; default 22", {}},
       num("z_inlet", d.z_inlet_mm, "axial position of the inlet plane, mm"),
       num("z_outlet", d.z_outlet_mm, "axial position of the outlet plane, mm"),
       num("hub_radius_inlet", d.hub_radius_inlet_mm, "hub radius at z_inlet, mm"),
       num("hub_radius_outlet", d.hub_radius_outlet_mm, "hub radius at z_outlet, mm"),
       num("casing_radius_inlet", d.casing_radius_inlet_mm, "casing (blade tip) radius at z_inlet, mm"),
       num("casing_radius_outlet", d.casing_radius_outlet_mm, "casing radius at z_outlet, mm"),
       num("chord", d.chord_mm, "chord of the camber arc, mm"),
       deg("stagger_hub", d.stagger_hub_rad, "chord angle to the Z axis at the hub, degrees"),
       deg("stagger_tip", d.stagger_tip_rad, "chord angle to the Z axis at the tip, degrees"),
       deg("camber_hub", d.camber_hub_rad, "turning of the camber arc at the hub, degrees"),
       deg("camber_tip", d.camber_tip_rad, "turning of the camber arc at the tip, degrees"),
       num("max_thickness_hub", d.max_thickness_hub_mm, "section max thickness at the hub, mm"),
       num("max_thickness_tip", d.max_thickness_tip_mm, "section max thickness at the tip, mm"),
       num("le_radius", d.le_radius_mm, "leading-edge circle radius, mm"),
       num("te_radius", d.te_radius_mm, "trailing-edge circle radius, mm"),
       Field{"grid_rows", Kind::Integer, false, 4, 1e5, "flank grid points along u (span); default 100", {}},
       Field{"grid_cols", Kind::Integer, false, 4, 1e5, "flank grid points along v (chord); default 500", {}},
       num("span_extension", d.span_extension_mm, "how far the grid reaches below the hub and above the casing, mm")});
  BliskParams p;
  p.blade_count = static_cast<int>(o.integer("blade_count", d.blade_count));
  p.z_inlet_mm = o.number("z_inlet", d.z_inlet_mm);
  p.z_outlet_mm = o.number("z_outlet", d.z_outlet_mm);
  p.hub_radius_inlet_mm = o.number("hub_radius_inlet", d.hub_radius_inlet_mm);
  p.hub_radius_outlet_mm = o.number("hub_radius_outlet", d.hub_radius_outlet_mm);
  p.casing_radius_inlet_mm = o.number("casing_radius_inlet", d.casing_radius_inlet_mm);
  p.casing_radius_outlet_mm = o.number("casing_radius_outlet", d.casing_radius_outlet_mm);
  p.chord_mm = o.number("chord", d.chord_mm);
  p.stagger_hub_rad = deg_to_rad(o.number("stagger_hub", rad_to_deg(d.stagger_hub_rad)));
  p.stagger_tip_rad = deg_to_rad(o.number("stagger_tip", rad_to_deg(d.stagger_tip_rad)));
  p.camber_hub_rad = deg_to_rad(o.number("camber_hub", rad_to_deg(d.camber_hub_rad)));
  p.camber_tip_rad = deg_to_rad(o.number("camber_tip", rad_to_deg(d.camber_tip_rad)));
  p.max_thickness_hub_mm = o.number("max_thickness_hub", d.max_thickness_hub_mm);
  p.max_thickness_tip_mm = o.number("max_thickness_tip", d.max_thickness_tip_mm);
  p.le_radius_mm = o.number("le_radius", d.le_radius_mm);
  p.te_radius_mm = o.number("te_radius", d.te_radius_mm);
  p.grid_rows = static_cast<int>(o.integer("grid_rows", d.grid_rows));
  p.grid_cols = static_cast<int>(o.integer("grid_cols", d.grid_cols));
  p.span_extension_mm = o.number("span_extension", d.span_extension_mm);
  return luax::guarded(L, [&] {
    luax::push_new(L, BliskHandle{std::make_shared<const BuiltinBlisk>(p)});
    return 1;
  });
}

int w_blisk_blade_count(lua_State* L) {
  lua_pushinteger(L, check_blisk(L).blade_count());
  return 1;
}

int w_flank_grid(lua_State* L) {
  const BliskPart& b = check_blisk(L);
  const int blade = check_blade(L, 2, b);
  const FlankSide side = check_side(L, 3);
  return luax::guarded(L, [&] {
    push_grid(L, std::make_shared<PointGrid>(b.flank_grid(blade, side)));
    return 1;
  });
}

int w_flank(lua_State* L) {
  const BliskPart& b = check_blisk(L);
  const int blade = check_blade(L, 2, b);
  const FlankSide side = check_side(L, 3);
  return luax::guarded(L, [&] {
    push_surface(L, b.flank_surface(blade, side));
    return 1;
  });
}

int w_blisk_hub_meridian(lua_State* L) {
  push_meridian(L, check_blisk(L).hub_meridian());
  return 1;
}

int w_casing_meridian(lua_State* L) {
  push_meridian(L, check_blisk(L).casing_meridian());
  return 1;
}

int w_blisk_hub(lua_State* L) {
  const BliskPart& b = check_blisk(L);
  return luax::guarded(L, [&] {
    push_surface(L, b.hub());
    return 1;
  });
}

int w_casing(lua_State* L) {
  const BliskPart& b = check_blisk(L);
  return luax::guarded(L, [&] {
    push_surface(L, b.casing());
    return 1;
  });
}

int w_hub_radius(lua_State* L) {
  const BliskPart& b = check_blisk(L);
  const double z = luax::check_number(L, 2, "z");
  return luax::guarded(L, [&] {
    lua_pushnumber(L, b.hub_radius_at(z));
    return 1;
  });
}

int w_casing_radius(lua_State* L) {
  const BliskPart& b = check_blisk(L);
  const double z = luax::check_number(L, 2, "z");
  return luax::guarded(L, [&] {
    lua_pushnumber(L, b.casing_radius_at(z));
    return 1;
  });
}

int w_blisk_narrowest_passage(lua_State* L) {
  const BliskPart& b = check_blisk(L);
  return luax::guarded(L, [&] {
    lua_pushnumber(L, b.narrowest_passage_mm());
    return 1;
  });
}

// bliskrun.loft_sections{sections = {{{x, y, z}, ...}, ...}, blades=,
// rotation=, cols=, edge_margin=, span_extension=} -> blade model table.
int w_loft_sections(lua_State* L) {
  std::vector<Field> fields = loft_fields();
  fields.push_back(Field{"sections", Kind::Table, true, std::nullopt, std::nullopt,
                         "closed section loops hub -> tip, each a list of {x, y, z} points, mm", {}});
  fields.push_back(Field{"blades", Kind::Integer, false, 1, 1000, "blade count; default 1", {}});
  fields.push_back(Field{"rotation", Kind::Integer, false, -1, 1,
                         "+1: the rotor turns towards +theta, -1: towards -theta, 0: from the camber (default)", {}});
  fields.push_back(Field{"hub_meridian", Kind::Table, false, std::nullopt, std::nullopt, "{{z, r}, ...}, mm", {}});
  fields.push_back(Field{"casing_meridian", Kind::Table, false, std::nullopt, std::nullopt, "{{z, r}, ...}, mm", {}});
  const luax::Options o(L, 1, "bliskrun.loft_sections", fields);
  BladeSections b;
  b.source = "bliskrun.loft_sections";
  b.blade_count = static_cast<int>(o.integer("blades", 1));
  b.rotation_sign = static_cast<int>(o.integer("rotation", 0));
  o.push_raw("sections");
  b.sections = check_point_loops(L, lua_gettop(L), "", "sections", "section");
  lua_pop(L, 1);
  for (const char* key : {"hub_meridian", "casing_meridian"}) {
    o.push_raw(key);
    if (lua_istable(L, -1)) {
      std::vector<Vec2>& m = std::string(key) == "hub_meridian" ? b.hub_meridian : b.casing_meridian;
      const int mt = lua_gettop(L);
      for (lua_Integer i = 1; i <= luaL_len(L, mt); ++i) {
        lua_rawgeti(L, mt, i);
        lua_rawgeti(L, -1, 1);
        lua_rawgeti(L, -2, 2);
        if (!lua_isnumber(L, -1) || !lua_isnumber(L, -2))
          luax::error(L, std::string("option '") + key + "': entry " + std::to_string(i) + " is not {z, r}");
        m.emplace_back(lua_tonumber(L, -2), lua_tonumber(L, -1));
        lua_pop(L, 3);
      }
    }
    lua_pop(L, 1);
  }
  const LoftOptions lo = loft_options(o);
  return luax::guarded(L, [&] {
    push_blade_model(L, b, lo);
    return 1;
  });
}

int w_blisk_tostring(lua_State* L) {
  lua_pushstring(L, check_blisk(L).description().c_str());
  return 1;
}

}  // namespace

void push_blisk(lua_State* L, std::shared_ptr<const BliskPart> blisk) {
  luax::push_new(L, BliskHandle{std::move(blisk)});
}

void open_parts(lua_State* L) {
  static const luaL_Reg methods[] = {{"blade_count", w_blisk_blade_count},
                                     {"flank_grid", w_flank_grid},
                                     {"flank", w_flank},
                                     {"hub", w_blisk_hub},
                                     {"casing", w_casing},
                                     {"hub_meridian", w_blisk_hub_meridian},
                                     {"casing_meridian", w_casing_meridian},
                                     {"hub_radius", w_hub_radius},
                                     {"casing_radius", w_casing_radius},
                                     {"narrowest_passage", w_blisk_narrowest_passage},
                                     {nullptr, nullptr}};
  luax::register_type(L, luax::TypeName<BliskHandle>::name, methods, &luax::gc_value<BliskHandle>,
                      w_blisk_tostring);
  static const luaL_Reg functions[] = {{"blisk", w_blisk}, {"loft_sections", w_loft_sections}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
