// bliskrun.write_vtk{path = "run.pvd", blocks = {...}}: one .vtp per block
// beside a .pvd collection that ParaView opens in one go (core/io/vtk.h).
//
// A block is one of
//   {name=, surface= [, map=] [, samples_u=, samples_v=]}  the surface as a grid
//        mesh over its unit square; with an UndercutMap (over that surface, e.g.
//        plan:trimmed()), point data "undercut" (mm, NaN where never reached),
//        each grid point the nearest map sample
//   {name=, mesh=}                                    a Mesh as it is
//   {name=, moves=}                                   plan:moves() as one polyline with
//        per-point tool_axis (vector), feed (1 feed, 0 rapid) and row
//   {name=, points=, reason=}                         a point set (refused poses) with
//        a reason per point: point data "reason" (code), names in the file
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/io/vtk.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/undercut_map.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;

// Grid of (rows x cols) samples over the unit square, rows along u, as triangles.
VtkPolyData surface_grid(const Surface& s, int rows, int cols) {
  VtkPolyData d;
  d.points.reserve(static_cast<size_t>(rows) * cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      d.points.push_back(s.point(rows == 1 ? 0 : double(i) / (rows - 1), cols == 1 ? 0 : double(j) / (cols - 1)));
  for (int i = 0; i + 1 < rows; ++i)
    for (int j = 0; j + 1 < cols; ++j) {
      const int a = i * cols + j, b = a + 1, c = a + cols, e = c + 1;
      d.triangles.push_back({a, b, e});
      d.triangles.push_back({a, e, c});
    }
  return d;
}

// Element k (1-based) of the table at idx, as a table, on top of the stack.
void push_element(lua_State* L, int idx, lua_Integer k, const std::string& where) {
  if (lua_geti(L, idx, k) != LUA_TTABLE)
    throw ParameterError(where + "[" + std::to_string(k) + "]", "expected a table");
}

VtkPolyData toolpath(lua_State* L, int idx, const std::string& where) {
  VtkPolyData d;
  VtkPointArray axis{"tool_axis", 3, {}}, feed{"feed", 1, {}}, row{"row", 1, {}};
  const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, idx));
  if (n < 2) throw ParameterError(where, "expected at least 2 moves (plan:moves())");
  for (lua_Integer k = 1; k <= n; ++k) {
    push_element(L, idx, k, where);
    const std::string at = where + "[" + std::to_string(k) + "]";
    lua_getfield(L, -1, "tip");
    d.points.push_back(luax::check_vec3(L, lua_gettop(L), (at + ".tip").c_str()));
    lua_getfield(L, -2, "axis");
    const Vec3 a = luax::check_vec3(L, lua_gettop(L), (at + ".axis").c_str());
    axis.values.insert(axis.values.end(), {a.x(), a.y(), a.z()});
    lua_getfield(L, -3, "kind");
    const char* kind = lua_tostring(L, -1);
    if (!kind || (std::string(kind) != "feed" && std::string(kind) != "rapid"))
      throw ParameterError(at + ".kind", "expected \"feed\" or \"rapid\"");
    feed.values.push_back(std::string(kind) == "feed" ? 1 : 0);
    lua_getfield(L, -4, "row");
    row.values.push_back(lua_isnumber(L, -1) ? lua_tonumber(L, -1) : 0);
    lua_pop(L, 5);
  }
  d.lines.emplace_back();
  for (int i = 0; i < static_cast<int>(n); ++i) d.lines.back().push_back(i);
  d.point_data = {axis, feed, row};
  return d;
}

VtkPolyData point_set(lua_State* L, int points_idx, int reason_idx, const std::string& where) {
  VtkPolyData d;
  d.vertices = true;
  const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, points_idx));
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_geti(L, points_idx, k);
    d.points.push_back(luax::check_vec3(L, lua_gettop(L), (where + ".points[" + std::to_string(k) + "]").c_str()));
    lua_pop(L, 1);
  }
  if (lua_istable(L, reason_idx)) {
    if (static_cast<lua_Integer>(lua_rawlen(L, reason_idx)) != n)
      throw ParameterError(where + ".reason", "expected one reason per point (" + std::to_string(n) + ")");
    std::map<std::string, int> codes;
    VtkPointArray reason{"reason", 1, {}};
    for (lua_Integer k = 1; k <= n; ++k) {
      lua_geti(L, reason_idx, k);
      const char* r = lua_tostring(L, -1);
      if (!r) throw ParameterError(where + ".reason[" + std::to_string(k) + "]", "expected a string");
      const auto [it, fresh] = codes.emplace(r, static_cast<int>(codes.size()));
      if (fresh) d.code_names.push_back(r);
      reason.values.push_back(it->second);
      lua_pop(L, 1);
    }
    d.point_data.push_back(reason);
  }
  return d;
}

std::string slug(const std::string& name) {
  std::string s;
  for (char c : name) s += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::tolower(c)) : '_';
  return s;
}

int w_write_vtk(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.write_vtk",
      {Field{"path", Kind::String, true, std::nullopt, std::nullopt, "the collection, a .pvd file", {}},
       Field{"blocks", Kind::Table, true, std::nullopt, std::nullopt, "list of {name=, surface=|mesh=|moves=|points=}", {}}});
  const std::string path = context(L).resolve_write(L, o.string("path", ""));
  if (path.size() < 4 || path.compare(path.size() - 4, 4, ".pvd") != 0)
    luax::error(L, "bliskrun.write_vtk: path: expected a .pvd file name, got \"" + o.string("path", "") + "\"");
  o.push_raw("blocks");
  const int blocks = lua_gettop(L);
  return luax::guarded(L, [&] {
    const std::filesystem::path pvd(path);
    const std::string stem = pvd.stem().string();
    std::vector<std::pair<std::string, std::string>> listed;
    const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, blocks));
    if (n < 1) throw ParameterError("blocks", "expected at least one block");
    for (lua_Integer k = 1; k <= n; ++k) {
      const std::string where = "blocks[" + std::to_string(k) + "]";
      push_element(L, blocks, k, where);
      const int b = lua_gettop(L);
      const luax::Options bo(
          L, b, "bliskrun.write_vtk " + where,
          {Field{"name", Kind::String, true, std::nullopt, std::nullopt, "block name shown in ParaView", {}},
           Field{"surface", Kind::Any, false, std::nullopt, std::nullopt, "a Surface, drawn as a grid mesh", {}},
           Field{"map", Kind::Any, false, std::nullopt, std::nullopt, "an UndercutMap over the surface", {}},
           Field{"samples_u", Kind::Integer, false, 2, 2000, "grid rows; default 60, or the map's rows", {}},
           Field{"samples_v", Kind::Integer, false, 2, 2000, "grid columns; default 120, or the map's columns", {}},
           Field{"mesh", Kind::Any, false, std::nullopt, std::nullopt, "a Mesh", {}},
           Field{"moves", Kind::Table, false, std::nullopt, std::nullopt, "plan:moves()", {}},
           Field{"points", Kind::Table, false, std::nullopt, std::nullopt, "{{x, y, z}, ...}", {}},
           Field{"reason", Kind::Table, false, std::nullopt, std::nullopt, "one string per point", {}}});
      const int kinds = bo.has("surface") + bo.has("mesh") + bo.has("moves") + bo.has("points");
      if (kinds != 1) throw ParameterError(where, "expected exactly one of surface, mesh, moves, points");
      VtkPolyData d;
      if (bo.has("surface")) {
        bo.push_raw("surface");
        const auto surface = luax::check<SurfaceHandle>(L, -1).surface;
        if (bo.has("map")) {
          bo.push_raw("map");
          const HeatMap& m = luax::check<LuaUndercutMap>(L, -1).map;
          // At the map's resolution unless told otherwise (a 200 x 1000 map is
          // ~25 MB of ASCII); each grid point takes the nearest map sample.
          const int rows = static_cast<int>(bo.integer("samples_u", m.rows));
          const int cols = static_cast<int>(bo.integer("samples_v", m.cols));
          d = surface_grid(*surface, rows, cols);
          VtkPointArray undercut{"undercut", 1, {}};
          for (int i = 0; i < rows; ++i)
            for (int j = 0; j < cols; ++j)
              undercut.values.push_back(undercut_map_nearest(m, i, rows, j, cols));
          d.point_data.push_back(undercut);
          lua_pop(L, 1);
        } else {
          d = surface_grid(*surface, static_cast<int>(bo.integer("samples_u", 60)),
                           static_cast<int>(bo.integer("samples_v", 120)));
        }
        lua_pop(L, 1);
      } else if (bo.has("mesh")) {
        bo.push_raw("mesh");
        const auto mesh = luax::check<MeshHandle>(L, -1).mesh;
        d.points = mesh->vertices;
        for (const auto& t : mesh->triangles) d.triangles.push_back({t[0], t[1], t[2]});
        lua_pop(L, 1);
      } else if (bo.has("moves")) {
        bo.push_raw("moves");
        d = toolpath(L, lua_gettop(L), where + ".moves");
        lua_pop(L, 1);
      } else {
        bo.push_raw("points");
        bo.push_raw("reason");
        d = point_set(L, lua_gettop(L) - 1, lua_gettop(L), where);
        lua_pop(L, 2);
      }
      const std::string file = stem + "_" + std::to_string(k) + "_" + slug(bo.string("name", "")) + ".vtp";
      write_vtp(d, (pvd.parent_path() / file).string());
      listed.emplace_back(bo.string("name", ""), file);
      lua_pop(L, 1);
    }
    // The collection last, so it never lists a file that is not there.
    write_pvd(listed, path);
    lua_pushstring(L, path.c_str());
    return 1;
  });
}

}  // namespace

void open_vtk(lua_State* L) {
  static const luaL_Reg functions[] = {{"write_vtk", w_write_vtk}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
