// Point grids from CAD in Lua: bliskrun.read_point_grid, write_point_grid;
// measured point clouds: read_points (XYZ, CSV, PLY, STL);
// real parts: read_rotor37, read_rotor67, read_hecc (blade models, wrap_parts.h).
// Reads resolve inside the recipe, data and out folders; writes go to the
// out folder (write_file_atomic). Data errors name the file:line.
#include <filesystem>
#include <memory>

#include "core/io/hecc_reader.h"
#include "core/io/point_cloud_reader.h"
#include "core/io/point_grid_reader.h"
#include "core/io/rotor37_reader.h"
#include "core/io/rotor67_reader.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"
#include "lua_api/wrap_parts.h"

namespace bliskrun::lua_api {

namespace {

namespace fs = std::filesystem;
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

// bliskrun.read_points(path [, {format="auto"|"xyz"|"csv"|"ply"|"stl", units="mm"|"in"|"inch"|"m"}])
// -> {{x,y,z}, ...} (mm: what register_scan's scan and a measured section's
// points take), {format=, count=, normals = {{x,y,z}, ...} or nil}
int w_read_points(lua_State* L) {
  const std::string path = context(L).resolve_read(L, luax::check_string(L, 1, "path"));
  const luax::Options o(
      L, 2, "bliskrun.read_points",
      {Field{"format", Kind::String, false, std::nullopt, std::nullopt,
             "\"auto\" (default: from the extension, else the content), \"xyz\", \"csv\", \"ply\" or \"stl\"",
             {"auto", "xyz", "csv", "ply", "stl"}},
       Field{"units", Kind::String, false, std::nullopt, std::nullopt,
             "the file's length unit: \"mm\" (default), \"in\" or \"inch\" (x 25.4), \"m\" (x 1000)",
             {"mm", "in", "inch", "m"}}});
  PointCloudReadOptions opts;
  const std::string format = o.string("format", "auto");
  for (PointCloudFormat f : {PointCloudFormat::kXyz, PointCloudFormat::kCsv, PointCloudFormat::kPly, PointCloudFormat::kStl})
    if (format == point_cloud_format_name(f)) opts.format = f;
  const std::string units = o.string("units", "mm");
  opts.mm_per_unit = units == "m" ? 1000.0 : units == "mm" ? 1.0 : 25.4;
  return luax::guarded(L, [&] {
    const PointCloud cloud = read_point_cloud(path, opts);
    auto push_cloud_list = [&](const std::vector<Vec3>& list) {
      lua_createtable(L, static_cast<int>(list.size()), 0);
      for (size_t i = 0; i < list.size(); ++i) {
        luax::push(L, list[i]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
      }
    };
    push_cloud_list(cloud.points);
    lua_createtable(L, 0, 3);
    lua_pushstring(L, point_cloud_format_name(cloud.format));
    lua_setfield(L, -2, "format");
    luax::set_number(L, "count", static_cast<double>(cloud.points.size()));
    if (!cloud.normals.empty()) {
      push_cloud_list(cloud.normals);
      lua_setfield(L, -2, "normals");
    }
    return 2;
  });
}

// bliskrun.read_rotor67(path [, {cols=200, edge_margin=0.03,
// span_extension=0.03}]) -> blade model table (wrap_parts.h)
int w_read_rotor67(lua_State* L) {
  const std::string path = luax::check_string(L, 1, "path");
  const luax::Options o(L, 2, "bliskrun.read_rotor67", loft_fields());
  const std::string file = context(L).resolve_read(L, path);
  const LoftOptions lo = loft_options(o);
  return luax::guarded(L, [&] {
    push_blade_model(L, blade_sections(read_rotor67(file)), lo);
    return 1;
  });
}

// The file `name` in `dir` or in `dir`/`sub`, or "".
std::string find_in(const std::string& dir, const std::string& sub, const std::string& name) {
  for (const std::string& c : {dir + "/" + name, dir + "/" + sub + "/" + name})
    if (fs::is_regular_file(c)) return c;
  return "";
}

// bliskrun.read_rotor37(path [, {hub_shroud=, cols=, edge_margin=,
// span_extension=}]): path is rotor37geometry.dat or a folder holding it
// (agard_table, or nasa_rotor37 above it).
int w_read_rotor37(lua_State* L) {
  const std::string path = luax::check_string(L, 1, "path");
  std::vector<Field> fields = loft_fields();
  fields.push_back(Field{"hub_shroud", Kind::String, false, std::nullopt, std::nullopt,
                         "Table V file; default rotor37hub-shroud.dat beside the geometry", {}});
  const luax::Options o(L, 2, "bliskrun.read_rotor37", fields);
  const std::string found = context(L).resolve_read(L, path);
  std::string geometry = found;
  if (fs::is_directory(found)) {
    geometry = find_in(found, "agard_table", "rotor37geometry.dat");
    if (geometry.empty()) luax::error(L, "no rotor37geometry.dat in '" + path + "' or its agard_table folder");
  }
  std::string hub_shroud = fs::path(geometry).parent_path().string() + "/rotor37hub-shroud.dat";
  if (o.has("hub_shroud")) hub_shroud = context(L).resolve_read(L, o.string("hub_shroud", ""));
  const LoftOptions lo = loft_options(o);
  return luax::guarded(L, [&] {
    push_blade_model(L, read_rotor37(geometry, hub_shroud), lo);
    return 1;
  });
}

// bliskrun.read_hecc(path [, {blade="main", set="design", cols=, ...}]):
// path is the nasa_hecc_impeller folder, or a file or folder inside it.
int w_read_hecc(lua_State* L) {
  const std::string path = luax::check_string(L, 1, "path");
  std::vector<Field> fields = loft_fields();
  fields.push_back(Field{"blade", Kind::String, false, std::nullopt, std::nullopt,
                         "\"main\" (default) or \"splitter\"", {"main", "splitter"}});
  fields.push_back(Field{"set", Kind::String, false, std::nullopt, std::nullopt,
                         "\"design\": design intent, hot, no fillets (default); \"cold\": as manufactured, with fillets",
                         {"design", "cold"}});
  const luax::Options o(L, 2, "bliskrun.read_hecc", fields);
  fs::path dir = context(L).resolve_read(L, path);
  for (int up = 0; up < 3 && !fs::is_directory(dir / "design_intent_hot_no_fillets"); ++up) dir = dir.parent_path();
  if (!fs::is_directory(dir / "design_intent_hot_no_fillets"))
    luax::error(L, "'" + path + "' is not in a HECC impeller folder (one holding design_intent_hot_no_fillets)");
  const HeccSet set = o.string("set", "design") == "cold" ? HeccSet::as_manufactured : HeccSet::design_intent;
  const HeccBlade blade = o.string("blade", "main") == "splitter" ? HeccBlade::splitter : HeccBlade::main;
  const LoftOptions lo = loft_options(o);
  return luax::guarded(L, [&] {
    push_blade_model(L, read_hecc_impeller(dir.string(), set, blade), lo);
    return 1;
  });
}

}  // namespace

void open_io(lua_State* L) {
  static const luaL_Reg functions[] = {{"read_point_grid", w_read_point_grid},
                                       {"write_point_grid", w_write_point_grid},
                                       {"read_rotor67", w_read_rotor67},
                                       {"read_rotor37", w_read_rotor37},
                                       {"read_hecc", w_read_hecc},
                                       {"read_points", w_read_points},
                                       {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
