// CAD files in Lua: bliskrun.read_cad(path) -> {units=, file_units=, format=,
// faces = {{name=, entity=, surface=, bounds=, boundary_uv=, boundary=}, ...},
// curves = {{name=, entity=, curve=}, ...}}. Surfaces are the kernel's exact
// NURBS (core/cad), usable wherever a Surface is accepted; lengths in mm.
#include <memory>

#include "core/cad/cad.h"
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

}  // namespace

void open_cad(lua_State* L) {
  static const luaL_Reg functions[] = {{"read_cad", w_read_cad}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
