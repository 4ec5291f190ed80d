// Built-in parts in Lua: bliskrun.blisk{...} -> Blisk. Lengths mm, angles
// degrees (converted here); blades are numbered 1..N in Lua (blade 1 is the
// core's blade 0, blade k+1 is blade 1 turned by k * 360°/N about Z).
#include <memory>
#include <sstream>

#include "core/geometry/revolution.h"
#include "core/parts/builtin_blisk.h"
#include "lua_api/modules.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

struct BliskHandle {
  std::shared_ptr<const BuiltinBlisk> blisk;
};

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <> struct TypeName<lua_api::BliskHandle> { static constexpr const char* name = "bliskrun.Blisk"; };
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;

const BuiltinBlisk& check_blisk(lua_State* L) { return *luax::check<BliskHandle>(L, 1).blisk; }

// Blade number 1..N at `idx`, returned 0-based.
int check_blade(lua_State* L, int idx, const BuiltinBlisk& b) {
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

int w_blade_count(lua_State* L) {
  lua_pushinteger(L, check_blisk(L).blade_count());
  return 1;
}

int w_flank_grid(lua_State* L) {
  const BuiltinBlisk& b = check_blisk(L);
  const int blade = check_blade(L, 2, b);
  const FlankSide side = check_side(L, 3);
  return luax::guarded(L, [&] {
    push_grid(L, std::make_shared<PointGrid>(b.flank_grid(blade, side)));
    return 1;
  });
}

int w_flank(lua_State* L) {
  const BuiltinBlisk& b = check_blisk(L);
  const int blade = check_blade(L, 2, b);
  const FlankSide side = check_side(L, 3);
  return luax::guarded(L, [&] {
    push_surface(L, b.flank_surface(blade, side));
    return 1;
  });
}

int w_hub_meridian(lua_State* L) {
  push_meridian(L, check_blisk(L).hub_meridian());
  return 1;
}

int w_casing_meridian(lua_State* L) {
  push_meridian(L, check_blisk(L).casing_meridian());
  return 1;
}

int w_hub(lua_State* L) {
  const BuiltinBlisk& b = check_blisk(L);
  return luax::guarded(L, [&] {
    push_surface(L, std::make_shared<SurfaceOfRevolution>(b.hub_meridian()));
    return 1;
  });
}

int w_casing(lua_State* L) {
  const BuiltinBlisk& b = check_blisk(L);
  return luax::guarded(L, [&] {
    push_surface(L, std::make_shared<SurfaceOfRevolution>(b.casing_meridian()));
    return 1;
  });
}

int w_hub_radius(lua_State* L) {
  const BuiltinBlisk& b = check_blisk(L);
  lua_pushnumber(L, b.hub_radius_at(luax::check_number(L, 2, "z")));
  return 1;
}

int w_casing_radius(lua_State* L) {
  const BuiltinBlisk& b = check_blisk(L);
  lua_pushnumber(L, b.casing_radius_at(luax::check_number(L, 2, "z")));
  return 1;
}

int w_narrowest_passage(lua_State* L) {
  const BuiltinBlisk& b = check_blisk(L);
  return luax::guarded(L, [&] {
    lua_pushnumber(L, b.narrowest_passage_mm());
    return 1;
  });
}

int w_tostring(lua_State* L) {
  const BliskParams& p = check_blisk(L).params();
  std::ostringstream s;
  s << "bliskrun.Blisk(" << p.blade_count << " blades, hub r " << p.hub_radius_inlet_mm << "->"
    << p.hub_radius_outlet_mm << " mm, casing r " << p.casing_radius_inlet_mm << "->"
    << p.casing_radius_outlet_mm << " mm, chord " << p.chord_mm << " mm, grid " << p.grid_rows
    << "x" << p.grid_cols << ")";
  lua_pushstring(L, s.str().c_str());
  return 1;
}

}  // namespace

void open_parts(lua_State* L) {
  static const luaL_Reg methods[] = {{"blade_count", w_blade_count},
                                     {"flank_grid", w_flank_grid},
                                     {"flank", w_flank},
                                     {"hub", w_hub},
                                     {"casing", w_casing},
                                     {"hub_meridian", w_hub_meridian},
                                     {"casing_meridian", w_casing_meridian},
                                     {"hub_radius", w_hub_radius},
                                     {"casing_radius", w_casing_radius},
                                     {"narrowest_passage", w_narrowest_passage},
                                     {nullptr, nullptr}};
  luax::register_type(L, luax::TypeName<BliskHandle>::name, methods, &luax::gc_value<BliskHandle>,
                      w_tostring);
  static const luaL_Reg functions[] = {{"blisk", w_blisk}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
