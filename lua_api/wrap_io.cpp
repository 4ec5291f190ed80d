// Point grids from CAD in Lua: bliskrun.read_point_grid, write_point_grid.
// Reads resolve inside the recipe, data and out folders; writes go to the
// out folder (write_file_atomic). Data errors name the file:line.
#include <memory>

#include "core/io/point_grid_reader.h"
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

}  // namespace

void open_io(lua_State* L) {
  static const luaL_Reg functions[] = {{"read_point_grid", w_read_point_grid},
                                       {"write_point_grid", w_write_point_grid},
                                       {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
