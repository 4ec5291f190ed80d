// CAD files in Lua: bliskrun.read_cad(path) -> {units=, file_units=, format=,
// faces = {{name=, entity=, surface=, bounds=, boundary_uv=, boundary=}, ...},
// curves = {{name=, entity=, curve=}, ...}}. Surfaces are the kernel's exact
// NURBS (core/cad), usable wherever a Surface is accepted; lengths in mm.
#include <memory>

#include "core/cad/cad.h"
#include "core/common/error.h"
#include "core/parts/cad_blade.h"
#include "core/parts/cad_blisk.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"
#include "lua_api/wrap_parts.h"

namespace bliskrun::lua_api {

namespace {

void push_pair(lua_State* L, double a, double b) { luax::push(L, std::vector<double>{a, b}); }

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
    // Which parameter of `airfoil` runs around it (the other hub -> tip).
    luax::set_string(L, "around", b.closed_in_u ? "u" : "v");
    for (int k = 0; k < 2; ++k)
      if (curves[k]) {
        push_surface(L, std::make_shared<SurfaceOfRevolution>(revolution_from_curve(*curves[k], opts)));
        lua_setfield(L, -2, keys[k]);
      }
    return 1;
  });
}

// The surface at the top of the stack, or an error naming `what`.
std::shared_ptr<const Surface> surface_at_top(lua_State* L, const std::string& what) {
  if (SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1)) return h->surface;
  luax::error(L, what + ": expected a Surface, got " + luaL_typename(L, -1));
}

// A hub or casing at the top of the stack: a meridian Curve (turned into a
// surface of revolution later, through `frame`) or a surface of revolution
// (cad_blade's hub and casing).
struct CadMeridianArg {
  std::shared_ptr<const Curve> curve;
  std::shared_ptr<const SurfaceOfRevolution> revolution;
};
CadMeridianArg meridian_at_top(lua_State* L, const std::string& what) {
  if (CurveHandle* c = luax::test<CurveHandle>(L, -1)) return {c->curve, nullptr};
  SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
  if (h)
    if (auto rev = std::dynamic_pointer_cast<const SurfaceOfRevolution>(h->surface)) return {nullptr, rev};
  luax::error(L, what + ": expected the meridian as a Curve (a read_cad curve) or a surface of revolution "
                        "(cad_blade's hub/casing), got " +
                     (h ? std::string("another Surface") : std::string(luaL_typename(L, -1))));
}

// bliskrun.cad_blisk{blade = cad_blade's result | faces = {a, b}, hub=,
// casing=, blade_count=, coordinates=, axial_origin=, grid_rows=,
// grid_cols=, name=} -> Blisk (bliskrun.blisk{}'s type).
int w_cad_blisk(lua_State* L) {
  const std::string what = "bliskrun.cad_blisk";
  const luax::Options o(
      L, 1, what,
      {Field{"blade", Kind::Table, false, std::nullopt, std::nullopt,
             "one blade: {pressure =, suction =} flanks in bliskrun's frame (bliskrun.cad_blade's result; its hub "
             "and casing are used unless given)", {}},
       Field{"faces", Kind::Table, false, std::nullopt, std::nullopt,
             "one blade as its two flank faces from the file ({face.surface, face.surface}), told apart and "
             "oriented here; coordinates and axial_origin map them", {}},
       Field{"blade_count", Kind::Integer, true, 2, 400, "number of blades (blade k = blade 1 turned by (k-1) 360/N deg)", {}},
       Field{"hub", Kind::Any, false, std::nullopt, std::nullopt,
             "hub meridian: a read_cad Curve (mapped by coordinates) or a surface of revolution", {}},
       Field{"casing", Kind::Any, false, std::nullopt, std::nullopt,
             "casing meridian (the blade tip's line): a Curve or a surface of revolution", {}},
       Field{"coordinates", Kind::String, false, std::nullopt, std::nullopt,
             "\"cartesian\" (axis Z; default) or \"x_rtheta_r\" (x axial, y = R theta, z = R), for faces and curves",
             {"cartesian", "x_rtheta_r"}},
       luax::number_field("axial_origin", "the file's axial coordinate that becomes z = 0 (x_rtheta_r), mm; default 0"),
       Field{"grid_rows", Kind::Integer, false, 4, 1e5, "flank_grid points along the span; default 100", {}},
       Field{"grid_cols", Kind::Integer, false, 4, 1e5, "flank_grid points along the chord; default 500", {}},
       Field{"name", Kind::String, false, std::nullopt, std::nullopt, "where the blade came from, for tostring", {}}});
  if (o.has("blade") == o.has("faces"))
    luax::error(L, what + ": expected one of 'blade' (bliskrun.cad_blade's result) or 'faces' (two flank faces)" +
                       (o.has("blade") ? std::string(", got both") : std::string(", got neither")));
  CadBladeOptions frame;
  if (o.string("coordinates", "cartesian") == "x_rtheta_r") frame.coordinates = CadCoordinates::kAxialRthetaR;
  frame.axial_origin_mm = o.number("axial_origin", 0);
  std::shared_ptr<const Surface> flank[2];
  CadMeridianArg rev[2];
  const char* rev_keys[2] = {"hub", "casing"};
  if (o.has("blade")) {
    o.push_raw("blade");
    const char* keys[2] = {"pressure", "suction"};
    for (int k = 0; k < 2; ++k) {
      lua_getfield(L, -1, keys[k]);
      flank[k] = surface_at_top(L, what + ": option 'blade': field '" + keys[k] + "'");
      lua_pop(L, 1);
    }
    for (int k = 0; k < 2; ++k) {
      lua_getfield(L, -1, rev_keys[k]);
      if (!lua_isnil(L, -1)) rev[k] = meridian_at_top(L, what + ": option 'blade': field '" + rev_keys[k] + "'");
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  } else {
    o.push_raw("faces");
    if (luaL_len(L, -1) != 2)
      luax::error(L, what + ": option 'faces': expected the blade's two flank faces, got " +
                         std::to_string(luaL_len(L, -1)));
    for (int k = 0; k < 2; ++k) {
      lua_rawgeti(L, -1, k + 1);
      // A read_cad face table or its surface.
      const bool table = lua_istable(L, -1);
      if (table) lua_getfield(L, -1, "surface");
      flank[k] = surface_at_top(L, what + ": option 'faces': entry " + std::to_string(k + 1));
      lua_pop(L, table ? 2 : 1);
    }
    lua_pop(L, 1);
  }
  for (int k = 0; k < 2; ++k)
    if (o.has(rev_keys[k])) {
      o.push_raw(rev_keys[k]);
      rev[k] = meridian_at_top(L, what + ": option '" + rev_keys[k] + "'");
      lua_pop(L, 1);
    }
  CadBliskOptions opts;
  opts.grid_rows = static_cast<int>(o.integer("grid_rows", opts.grid_rows));
  opts.grid_cols = static_cast<int>(o.integer("grid_cols", opts.grid_cols));
  opts.source = o.string("name", "");
  const int n = static_cast<int>(o.integer("blade_count", 0));
  const bool from_faces = o.has("faces");
  return luax::guarded(L, [&] {
    if (from_faces) {
      const CadBlade b = cad_blade_from_flanks(flank[0], flank[1], frame);
      flank[0] = b.pressure;
      flank[1] = b.suction;
    }
    std::shared_ptr<const SurfaceOfRevolution> surfaces[2];
    for (int k = 0; k < 2; ++k) {
      surfaces[k] = rev[k].revolution;
      if (rev[k].curve) try {
          surfaces[k] = std::make_shared<const SurfaceOfRevolution>(revolution_from_curve(*rev[k].curve, frame));
        } catch (const ParameterError& e) {
          throw ParameterError(rev_keys[k], e.what());
        }
    }
    push_blisk(L, std::make_shared<const CadBlisk>(flank[0], flank[1], surfaces[0], surfaces[1], n, opts));
    return 1;
  });
}

}  // namespace

void open_cad(lua_State* L) {
  static const luaL_Reg functions[] = {
      {"read_cad", w_read_cad}, {"cad_blade", w_cad_blade}, {"cad_blisk", w_cad_blisk}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
