// Point grids from CAD in Lua: bliskrun.read_point_grid, write_point_grid.
// Reads resolve inside the recipe, data and out folders; writes go to the
// out folder (write_file_atomic). Data errors name the file:line.
#include <memory>

#include "core/io/point_grid_reader.h"
#include "core/io/rotor67_reader.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;

// bliskrun.read_point_grid(path [, {rows=, cols=, order="row"|"column"}])
int w_read_point_grid(lua_State* L) {
  const std::string path = context(L).resolve_read(L, luax::check_string(L, 1, "path"));
  const luax::Options o(
      L, 2, "bliskrun.read_point_grid",
      {Field{"rows", Kind::Integer, false, 2, 1e7, "points along u (span); else from the '# grid' header", {}},
       Field{"cols", Kind::Integer, false, 2, 1e7, "points along v (chord); else from the header", {}},
       Field{"order", Kind::String, false, std::nullopt, std::nullopt,
             "\"row\": u-row 1 first along v (default); \"column\": v-column 1 first along u",
             {"row", "column"}}});
  PointGridReadOptions opts;
  if (o.has("rows")) opts.rows = static_cast<int>(o.integer("rows", 0));
  if (o.has("cols")) opts.cols = static_cast<int>(o.integer("cols", 0));
  if (o.has("order"))
    opts.order = o.string("order", "row") == "column" ? GridOrder::kColumnMajor : GridOrder::kRowMajor;
  return luax::guarded(L, [&] {
    push_grid(L, std::make_shared<PointGrid>(read_point_grid(path, opts)));
    return 1;
  });
}

// bliskrun.write_point_grid(grid, path) -> full path
int w_write_point_grid(lua_State* L) {
  const PointGrid& grid = *luax::check<GridHandle>(L, 1).grid;
  const std::string target = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  return luax::guarded(L, [&] {
    write_point_grid(grid, target);
    lua_pushstring(L, target.c_str());
    return 1;
  });
}


// bliskrun.read_rotor67(path [, {cols=200, edge_margin=0.03}]) -> {blades,
// sections, pressure, suction, hub_meridian, casing_meridian}
int w_read_rotor67(lua_State* L) {
  const std::string path = luax::check_string(L, 1, "path");
  const luax::Options o(L, 2, "bliskrun.read_rotor67",
                        {{"cols", luax::Kind::Integer, false, 4, 5000, "grid columns along the chord (200)", {}},
                         {"edge_margin", luax::Kind::Number, false, 0, 0.49,
                          "chord fraction left out at each edge circle (0.03)", {}}});
  const std::string file = context(L).resolve_read(L, path);
  const int cols = static_cast<int>(o.integer("cols", 200));
  const double margin = o.number("edge_margin", 0.03);
  return luax::guarded(L, [&] {
    const StreamSurfaceRotor rotor = read_rotor67(file);
    const RotorFlanks flanks = rotor_flank_grids(rotor, cols, margin);
    lua_createtable(L, 0, 6);
    lua_pushinteger(L, rotor.blade_count);
    lua_setfield(L, -2, "blades");
    lua_pushinteger(L, static_cast<lua_Integer>(rotor.surfaces.size()));
    lua_setfield(L, -2, "sections");
    push_grid(L, std::make_shared<PointGrid>(flanks.pressure));
    lua_setfield(L, -2, "pressure");
    push_grid(L, std::make_shared<PointGrid>(flanks.suction));
    lua_setfield(L, -2, "suction");
    push_meridian(L, rotor.hub_meridian);
    lua_setfield(L, -2, "hub_meridian");
    push_meridian(L, rotor.casing_meridian);
    lua_setfield(L, -2, "casing_meridian");
    return 1;
  });
}

}  // namespace

void open_io(lua_State* L) {
  static const luaL_Reg functions[] = {{"read_point_grid", w_read_point_grid},
                                       {"write_point_grid", w_write_point_grid},
                                       {"read_rotor67", w_read_rotor67},
                                       {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
