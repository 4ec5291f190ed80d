// CAD files in Lua: bliskrun.read_cad(path) -> {units=, file_units=, format=,
// faces = {{name=, entity=, surface=, bounds=, boundary_uv=, boundary=}, ...},
// curves = {{name=, entity=, curve=}, ...}}. Surfaces are the kernel's exact
// NURBS (core/cad), usable wherever a Surface is accepted; lengths in mm.
#include <memory>

#include "core/cad/cad.h"
#include "core/parts/cad_blade.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

void push_pair(lua_State* L, double a, double b) {
  lua_createtable(L, 2, 0);
  lua_pushnumber(L, a);
  lua_rawseti(L, -2, 1);
  lua_pushnumber(L, b);
  lua_rawseti(L, -2, 2);
}

void push_face(lua_State* L, const CadFace& f) {
  lua_createtable(L, 0, 6);
  luax::set_string(L, "name", f.name);
  luax::set_string(L, "entity", f.entity);
  push_surface(L, f.surface);
  lua_setfield(L, -2, "surface");
  // {u = {lo, hi}, v = {lo, hi}}: the window options of the planners take it.
  lua_createtable(L, 0, 2);
  push_pair(L, f.u_min, f.u_max);
  lua_setfield(L, -2, "u");
  push_pair(L, f.v_min, f.v_max);
  lua_setfield(L, -2, "v");
  lua_setfield(L, -2, "bounds");
  lua_createtable(L, static_cast<int>(f.boundary_uv.size()), 0);
  for (size_t i = 0; i < f.boundary_uv.size(); ++i) {
    push_pair(L, f.boundary_uv[i].x(), f.boundary_uv[i].y());
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "boundary_uv");
  lua_createtable(L, static_cast<int>(f.boundary_mm.size()), 0);
  for (size_t i = 0; i < f.boundary_mm.size(); ++i) {
    luax::push(L, f.boundary_mm[i]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "boundary");
}

// bliskrun.read_cad(path): an IGES (.igs/.iges) or STEP (.stp/.step) file.
int w_read_cad(lua_State* L) {
  const std::string path = context(L).resolve_read(L, luax::check_string(L, 1, "path"));
  return luax::guarded(L, [&] {
    const CadModel m = read_cad(path);
    lua_createtable(L, 0, 6);
    luax::set_string(L, "units", "mm");
    luax::set_string(L, "file_units", m.file_units);
    luax::set_string(L, "format", m.format);
    luax::set_string(L, "path", m.path);
    lua_createtable(L, static_cast<int>(m.faces.size()), 0);
    for (size_t i = 0; i < m.faces.size(); ++i) {
      push_face(L, m.faces[i]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "faces");
    lua_createtable(L, static_cast<int>(m.curves.size()), 0);
    for (size_t i = 0; i < m.curves.size(); ++i) {
      lua_createtable(L, 0, 3);
      luax::set_string(L, "name", m.curves[i].name);
      luax::set_string(L, "entity", m.curves[i].entity);
      luax::push_new(L, CurveHandle{m.curves[i].curve});
      lua_setfield(L, -2, "curve");
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "curves");
    return 1;
  });
}

using luax::Field;
using luax::Kind;

// bliskrun.cad_blade{surface=, coordinates="cartesian"|"x_rtheta_r",
// axial_origin=0, hub=curve, casing=curve} -> {pressure, suction, airfoil,
// hub, casing, le, te}
int w_cad_blade(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.cad_blade",
      {Field{"surface", Kind::Any, true, std::nullopt, std::nullopt,
             "the closed airfoil surface (a read_cad face's surface): around in one parameter, hub to tip in the other", {}},
       Field{"coordinates", Kind::String, false, std::nullopt, std::nullopt,
             "\"cartesian\" (axis Z; default) or \"x_rtheta_r\" (x axial, y = R theta, z = R: NASA's E3 files)",
             {"cartesian", "x_rtheta_r"}},
       luax::number_field("axial_origin", "the file's axial coordinate that becomes z = 0 (x_rtheta_r), mm; default 0"),
       Field{"hub", Kind::Any, false, std::nullopt, std::nullopt, "hub meridian curve (a read_cad curve)", {}},
       Field{"casing", Kind::Any, false, std::nullopt, std::nullopt, "casing meridian curve (a read_cad curve)", {}}});
  o.push_raw("surface");
  const std::shared_ptr<const Surface> surface = luax::check<SurfaceHandle>(L, -1).surface;
  lua_pop(L, 1);
  CadBladeOptions opts;
  if (o.string("coordinates", "cartesian") == "x_rtheta_r") opts.coordinates = CadCoordinates::kAxialRthetaR;
  opts.axial_origin_mm = o.number("axial_origin", 0);
  std::shared_ptr<const Curve> curves[2];
  const char* keys[2] = {"hub", "casing"};
  for (int k = 0; k < 2; ++k)
    if (o.has(keys[k])) {
      o.push_raw(keys[k]);
      curves[k] = luax::check<CurveHandle>(L, -1).curve;
      lua_pop(L, 1);
    }
  return luax::guarded(L, [&] {
    const CadBlade b = cad_blade(surface, opts);
    lua_createtable(L, 0, 7);
    push_surface(L, b.pressure);
    lua_setfield(L, -2, "pressure");
    push_surface(L, b.suction);
    lua_setfield(L, -2, "suction");
    push_surface(L, b.airfoil);
    lua_setfield(L, -2, "airfoil");
    luax::set_number(L, "le", b.le);
    luax::set_number(L, "te", b.te);
    for (int k = 0; k < 2; ++k)
      if (curves[k]) {
        push_surface(L, std::make_shared<SurfaceOfRevolution>(revolution_from_curve(*curves[k], opts)));
        lua_setfield(L, -2, keys[k]);
      }
    return 1;
  });
}

}  // namespace

void open_cad(lua_State* L) {
  static const luaL_Reg functions[] = {{"read_cad", w_read_cad}, {"cad_blade", w_cad_blade}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
