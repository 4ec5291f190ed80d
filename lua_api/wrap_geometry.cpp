// Geometry in Lua: point grids, interpolation, surface evaluation and
// curvature, projection, surfaces of revolution, intersection, meshes.
// Parameters u, v, t are on [0, 1]; lengths in mm; curvature in 1/mm.
#include "lua_api/wrap_geometry.h"

#include "core/geometry/differential.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/projection.h"
#include "core/geometry/registration.h"
#include "core/geometry/reparametrised.h"
#include "core/geometry/revolution.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"

namespace bliskrun::lua_api {

void push_surface(lua_State* L, std::shared_ptr<const Surface> s) { luax::push_new(L, SurfaceHandle{std::move(s)}); }
void push_grid(lua_State* L, std::shared_ptr<const PointGrid> g) { luax::push_new(L, GridHandle{std::move(g)}); }
void push_mesh(lua_State* L, std::shared_ptr<const TriangleMesh> m) { luax::push_new(L, MeshHandle{std::move(m)}); }

void push_meridian(lua_State* L, const std::vector<Vec2>& meridian) {
  lua_createtable(L, static_cast<int>(meridian.size()), 0);
  for (size_t i = 0; i < meridian.size(); ++i) {
    lua_createtable(L, 2, 0);
    lua_pushnumber(L, meridian[i].x());
    lua_rawseti(L, -2, 1);
    lua_pushnumber(L, meridian[i].y());
    lua_rawseti(L, -2, 2);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
}

std::shared_ptr<const SurfaceOfRevolution> revolution_option(lua_State* L, const luax::Options& o,
                                                             const std::string& key, const std::string& what) {
  o.push_raw(key);
  const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
  auto s = h ? std::dynamic_pointer_cast<const SurfaceOfRevolution>(h->surface) : nullptr;
  if (!s)
    luax::error(L, what + ": option '" + key +
                       "': expected a surface of revolution (blisk:hub(), blisk:casing() or "
                       "bliskrun.surface_of_revolution)");
  lua_pop(L, 1);
  return s;
}

void read_unit_window(lua_State* L, const luax::Options& o, const std::string& what, const char* key, double& lo,
                      double& hi) {
  if (!o.has(key)) return;
  o.push_raw(key);
  const int t = lua_gettop(L);
  const std::string where = what + ": option '" + key + "'";
  if (luaL_len(L, t) != 2) luax::error(L, where + ": expected {lo, hi} with 0 <= lo < hi <= 1");
  lua_rawgeti(L, t, 1);
  lua_rawgeti(L, t, 2);
  if (!lua_isnumber(L, -2) || !lua_isnumber(L, -1)) luax::error(L, where + ": expected two numbers");
  lo = lua_tonumber(L, -2);
  hi = lua_tonumber(L, -1);
  if (!(lo >= 0 && lo < hi && hi <= 1)) luax::error(L, where + ": expected {lo, hi} with 0 <= lo < hi <= 1");
  lua_pop(L, 3);
}

namespace {

double check_param(lua_State* L, int idx, const char* name) {
  const double x = luax::check_number(L, idx, name);
  if (x < 0 || x > 1) luax::error(L, std::string("argument '") + name + "': " + std::to_string(x) + " is outside [0, 1]");
  return x;
}

using luax::set_number;
using luax::set_vec3;

std::vector<Vec3> check_points(lua_State* L, int idx, const char* name) {
  luaL_checktype(L, idx, LUA_TTABLE);
  std::vector<Vec3> pts;
  const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, idx));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, i);
    pts.push_back(luax::check_vec3(L, lua_gettop(L), name));
    lua_pop(L, 1);
  }
  return pts;
}

// ---- point grids ------------------------------------------------------------

// bliskrun.point_grid{rows=, cols=, points={{x,y,z}, ...}} (row-major: all
// points of u-row 1 along v first).
int w_point_grid(lua_State* L) {
  const luax::Options o(L, 1, "bliskrun.point_grid",
                        {{"rows", luax::Kind::Integer, true, 2, 1e6, "points along u (span)", {}},
                         {"cols", luax::Kind::Integer, true, 2, 1e6, "points along v (chord)", {}},
                         {"points", luax::Kind::Table, true, {}, {}, "rows*cols points {x, y, z}, mm, row-major", {}}});
  auto g = std::make_shared<PointGrid>(static_cast<int>(o.integer("rows", 0)), static_cast<int>(o.integer("cols", 0)));
  o.push_raw("points");
  const std::vector<Vec3> pts = check_points(L, lua_gettop(L), "points");
  lua_pop(L, 1);
  if (pts.size() != g->points.size())
    luax::error(L, "bliskrun.point_grid: 'points' holds " + std::to_string(pts.size()) +
                       " points, expected rows * cols = " + std::to_string(g->points.size()));
  g->points = pts;
  push_grid(L, std::move(g));
  return 1;
}

int w_grid_size(lua_State* L) {
  const PointGrid& g = *luax::check<GridHandle>(L, 1).grid;
  lua_pushinteger(L, g.rows);
  lua_pushinteger(L, g.cols);
  return 2;
}

int w_grid_point(lua_State* L) {
  const PointGrid& g = *luax::check<GridHandle>(L, 1).grid;
  const long long i = luax::check_integer(L, 2, "i"), j = luax::check_integer(L, 3, "j");
  if (i < 1 || i > g.rows || j < 1 || j > g.cols)
    luax::error(L, "grid:point(" + std::to_string(i) + ", " + std::to_string(j) + "): indices run 1.." +
                       std::to_string(g.rows) + ", 1.." + std::to_string(g.cols));
  luax::push(L, g.at(static_cast<int>(i - 1), static_cast<int>(j - 1)));
  return 1;
}

// grid:rotated(angle_deg) -> the grid turned about the Z (rotor) axis: the
// same flank on another blade.
int w_grid_rotated(lua_State* L) {
  const PointGrid& g = *luax::check<GridHandle>(L, 1).grid;
  const double a = deg_to_rad(luax::check_number(L, 2, "angle"));
  auto out = std::make_shared<PointGrid>(g);
  const Eigen::AngleAxisd turn(a, Vec3::UnitZ());
  for (Vec3& p : out->points) p = turn * p;
  push_grid(L, std::move(out));
  return 1;
}

// ---- interpolation ----------------------------------------------------------

int w_interpolate_grid(lua_State* L) {
  const auto grid = luax::check<GridHandle>(L, 1).grid;
  return luax::guarded(L, [&] {
    push_surface(L, std::make_shared<BSplineSurface>(interpolate_grid(*grid)));
    return 1;
  });
}

int w_interpolate_curve(lua_State* L) {
  const std::vector<Vec3> pts = check_points(L, 1, "points");
  const luax::Options o(L, 2, "bliskrun.interpolate_curve",
                        {{"start_tangent", luax::Kind::Vec3, false, {}, {}, "dC/dt at t = 0", {}},
                         {"end_tangent", luax::Kind::Vec3, false, {}, {}, "dC/dt at t = 1", {}}});
  EndTangents ends;
  if (o.has("start_tangent")) ends.start = o.vec3("start_tangent", Vec3::Zero());
  if (o.has("end_tangent")) ends.end = o.vec3("end_tangent", Vec3::Zero());
  return luax::guarded(L, [&] {
    luax::push_new(L, CurveHandle{std::make_shared<BSplineCurve>(interpolate_cubic(pts, {}, ends))});
    return 1;
  });
}

// ---- surfaces ------------------------------------------------------------------

int w_surface_eval(lua_State* L) {
  const Surface& s = *luax::check<SurfaceHandle>(L, 1).surface;
  const double u = check_param(L, 2, "u"), v = check_param(L, 3, "v");
  return luax::guarded(L, [&] {
    const SurfaceDerivs d = s.eval(u, v);
    lua_createtable(L, 0, 7);
    set_vec3(L, "point", d.p);
    set_vec3(L, "pu", d.pu);
    set_vec3(L, "pv", d.pv);
    set_vec3(L, "puu", d.puu);
    set_vec3(L, "puv", d.puv);
    set_vec3(L, "pvv", d.pvv);
    const Vec3 n = d.pu.cross(d.pv);
    set_vec3(L, "normal", n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero());
    return 1;
  });
}

int w_surface_point(lua_State* L) {
  const Surface& s = *luax::check<SurfaceHandle>(L, 1).surface;
  const double u = check_param(L, 2, "u"), v = check_param(L, 3, "v");
  return luax::guarded(L, [&] {
    luax::push(L, s.point(u, v));
    return 1;
  });
}

// surface:rotated(deg) -> the surface turned by deg about +Z, exactly.
int w_surface_rotated(lua_State* L) {
  const std::shared_ptr<const Surface> s = luax::check<SurfaceHandle>(L, 1).surface;
  const double deg = luax::check_number(L, 2, "angle");
  push_surface(L, std::make_shared<RotatedSurface>(s, deg_to_rad(deg)));
  return 1;
}

// surface:reoriented{swap=, flip_u=, flip_v=} -> the same surface with its
// parameters swapped and/or reversed (exact; a CAD face turned so that u
// runs hub -> tip and pu x pv out of the material).
int w_surface_reoriented(lua_State* L) {
  const std::shared_ptr<const Surface> s = luax::check<SurfaceHandle>(L, 1).surface;
  using luax::Field;
  using luax::Kind;
  const luax::Options o(L, 2, "Surface:reoriented",
                        {Field{"swap", Kind::Boolean, false, std::nullopt, std::nullopt, "swap u and v (first)", {}},
                         Field{"flip_u", Kind::Boolean, false, std::nullopt, std::nullopt, "u -> 1 - u (after the swap)", {}},
                         Field{"flip_v", Kind::Boolean, false, std::nullopt, std::nullopt, "v -> 1 - v (after the swap)", {}}});
  push_surface(L, std::make_shared<ReorientedSurface>(s, o.boolean("swap", false), o.boolean("flip_u", false),
                                                      o.boolean("flip_v", false)));
  return 1;
}

int w_surface_curvature(lua_State* L) {
  const Surface& s = *luax::check<SurfaceHandle>(L, 1).surface;
  const double u = check_param(L, 2, "u"), v = check_param(L, 3, "v");
  return luax::guarded(L, [&] {
    const SurfaceCurvature c = curvature(s.eval(u, v));
    lua_createtable(L, 0, 14);
    set_number(L, "K", c.K);
    set_number(L, "H", c.H);
    set_number(L, "k1", c.k1);
    set_number(L, "k2", c.k2);
    set_vec3(L, "dir1", c.dir1);
    set_vec3(L, "dir2", c.dir2);
    set_vec3(L, "normal", c.normal);
    set_number(L, "E", c.E);
    set_number(L, "F", c.F);
    set_number(L, "G", c.G);
    set_number(L, "L", c.L);
    set_number(L, "M", c.M);
    set_number(L, "N", c.N);
    return 1;
  });
}

int w_surface_normal_curvature(lua_State* L) {
  const Surface& s = *luax::check<SurfaceHandle>(L, 1).surface;
  const double u = check_param(L, 2, "u"), v = check_param(L, 3, "v");
  const Vec3 dir = luax::check_vec3(L, 4, "direction");
  return luax::guarded(L, [&] {
    lua_pushnumber(L, normal_curvature(s.eval(u, v), dir));
    return 1;
  });
}

// surface:project(p) -> {u, v, point, distance, on_boundary} or nil, reason
int w_surface_project(lua_State* L) {
  const Surface& s = *luax::check<SurfaceHandle>(L, 1).surface;
  const Vec3 q = luax::check_vec3(L, 2, "point");
  return luax::guarded(L, [&] {
    const SurfaceProjection p = project_to_surface(s, q);
    if (!p.ok) {
      lua_pushnil(L);
      lua_pushstring(L, p.failure.c_str());
      return 2;
    }
    lua_createtable(L, 0, 5);
    set_number(L, "u", p.u);
    set_number(L, "v", p.v);
    set_vec3(L, "point", p.point);
    set_number(L, "distance", p.distance);
    luax::set_bool(L, "on_boundary", p.on_boundary);
    return 1;
  });
}

int w_surface_tessellate(lua_State* L) {
  const Surface& s = *luax::check<SurfaceHandle>(L, 1).surface;
  const double tol = luax::check_number(L, 2, "chord_tol");
  if (!(tol > 0)) luax::error(L, "argument 'chord_tol': must be > 0 mm");
  return luax::guarded(L, [&] {
    push_mesh(L, std::make_shared<TriangleMesh>(tessellate(s, tol, 0, 1, 0, 1, context(L).progress)));
    return 1;
  });
}

// ---- curves ---------------------------------------------------------------------

int w_curve_eval(lua_State* L) {
  const Curve& c = *luax::check<CurveHandle>(L, 1).curve;
  const double t = check_param(L, 2, "t");
  return luax::guarded(L, [&] {
    const CurveDerivs d = c.eval(t);
    lua_createtable(L, 0, 3);
    set_vec3(L, "point", d.p);
    set_vec3(L, "dt", d.dt);
    set_vec3(L, "dtt", d.dtt);
    return 1;
  });
}

int w_curve_project(lua_State* L) {
  const Curve& c = *luax::check<CurveHandle>(L, 1).curve;
  const Vec3 q = luax::check_vec3(L, 2, "point");
  return luax::guarded(L, [&] {
    const CurveProjection p = project_to_curve(c, q);
    if (!p.ok) {
      lua_pushnil(L);
      lua_pushstring(L, p.failure.c_str());
      return 2;
    }
    lua_createtable(L, 0, 3);
    set_number(L, "t", p.t);
    set_vec3(L, "point", p.point);
    set_number(L, "distance", p.distance);
    return 1;
  });
}

// ---- revolution and intersection ---------------------------------------------------

int w_surface_of_revolution(lua_State* L) {
  const luax::Options o(L, 1, "bliskrun.surface_of_revolution",
                        {{"meridian", luax::Kind::Table, true, {}, {}, "{{z, r}, ...} along the profile, mm", {}}});
  o.push_raw("meridian");
  const int idx = lua_gettop(L);
  std::vector<Vec2> m;
  const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, idx));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, i);
    lua_rawgeti(L, -1, 1);
    lua_rawgeti(L, -2, 2);
    if (lua_type(L, -1) != LUA_TNUMBER || lua_type(L, -2) != LUA_TNUMBER)
      luax::error(L, "bliskrun.surface_of_revolution: meridian[" + std::to_string(i) + "] must be {z, r}");
    m.emplace_back(lua_tonumber(L, -2), lua_tonumber(L, -1));
    lua_pop(L, 3);
  }
  lua_pop(L, 1);
  return luax::guarded(L, [&] {
    push_surface(L, std::make_shared<SurfaceOfRevolution>(m));
    return 1;
  });
}

// bliskrun.offset_revolution(revolution, d) -> the surface of revolution d mm
// along its normal (the normal eval returns; d < 0 the other way).
int w_offset_revolution(lua_State* L) {
  const auto* rev = dynamic_cast<const SurfaceOfRevolution*>(luax::check<SurfaceHandle>(L, 1).surface.get());
  if (!rev) luax::error(L, "bliskrun.offset_revolution: argument 1: expected a surface of revolution");
  const double d = luaL_checknumber(L, 2);
  return luax::guarded(L, [&] {
    push_surface(L, std::make_shared<SurfaceOfRevolution>(rev->offset(d)));
    return 1;
  });
}

// bliskrun.intersect_revolution(flank, revolution [, {samples=200}])
int w_intersect_revolution(lua_State* L) {
  const Surface& s = *luax::check<SurfaceHandle>(L, 1).surface;
  const auto* rev = dynamic_cast<const SurfaceOfRevolution*>(luax::check<SurfaceHandle>(L, 2).surface.get());
  if (!rev) luax::error(L, "argument 2: expected a surface of revolution");
  const luax::Options o(L, 3, "bliskrun.intersect_revolution",
                        {{"samples", luax::Kind::Integer, false, 2, 100000, "iso-v lines searched (default 200)", {}}});
  const int samples = static_cast<int>(o.integer("samples", 200));
  return luax::guarded(L, [&] {
    const SurfaceCurveOnSurface c = intersect_with_revolution(s, *rev, samples);
    lua_createtable(L, 0, 3);
    for (const char* key : {"u", "v"}) {
      const auto& values = std::string(key) == "u" ? c.u : c.v;
      luax::set_numbers(L, key, values);
    }
    lua_createtable(L, static_cast<int>(c.points.size()), 0);
    for (size_t i = 0; i < c.points.size(); ++i) {
      luax::push(L, c.points[i]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "points");
    return 1;
  });
}

// ---- meshes ----------------------------------------------------------------------

int w_mesh_write_stl(lua_State* L) {
  const TriangleMesh& m = *luax::check<MeshHandle>(L, 1).mesh;
  const std::string target = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  return luax::guarded(L, [&] {
    write_stl(m, target);
    lua_pushstring(L, target.c_str());
    return 1;
  });
}

int w_mesh_size(lua_State* L) {
  const TriangleMesh& m = *luax::check<MeshHandle>(L, 1).mesh;
  lua_pushinteger(L, static_cast<lua_Integer>(m.vertices.size()));
  lua_pushinteger(L, static_cast<lua_Integer>(m.triangles.size()));
  return 2;
}

}  // namespace

namespace {

// bliskrun.register_scan{scan = {{x,y,z}, ...}, surfaces = {...}, samples = 300, ...}
// -> {transform = {origin, x, y, z}, iterations, converged, inliers, outliers, rms, median,
//     condition, sigma = {rotation, translation, point}, trusted, problems, ...}
int w_register_scan(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.register_scan",
      {luax::Field{"scan", luax::Kind::Table, true, std::nullopt, std::nullopt, "measured points {{x,y,z}, ...}, mm", {}},
       luax::Field{"surfaces", luax::Kind::Table, true, std::nullopt, std::nullopt,
                   "the model: a list of Surfaces in the frame the scan should land in", {}},
       luax::Field{"samples", luax::Kind::Integer, false, 10, 4000, "model samples per surface and direction; default 300", {}},
       luax::Field{"initial_reach", luax::Kind::Number, false, 1e-6, 1000,
                   "pairs farther than this are ignored at first by the fine ICP, mm; default 5", {}},
       luax::Field{"outlier_factor", luax::Kind::Number, false, 1, 100, "later: this times the median pair distance; default 3", {}},
       luax::Field{"pre_align", luax::Kind::Boolean, false, std::nullopt, std::nullopt,
                   "coarse pre-alignment from several starts first; default true", {}},
       luax::Field{"capture_angle", luax::Kind::Number, false, 0, 45, "clamping error the pre-alignment covers, deg; default 5", {}},
       luax::Field{"capture_offset", luax::Kind::Number, false, 0, 100, "... and offset, mm; default 5", {}},
       luax::Field{"noise", luax::Kind::Number, false, 1e-6, 10, "the scanner's stated noise (1 sigma), mm; default 0.005", {}},
       luax::Field{"rms_factor", luax::Kind::Number, false, 1, 1000, "trusted only if rms <= this x noise; default 3", {}},
       luax::Field{"max_condition", luax::Kind::Number, false, 1, 1e300, "trusted only if the condition is within; default 1e5", {}},
       luax::Field{"max_sigma", luax::Kind::Number, false, 1e-9, 1000,
                   "trusted only if a point's position sigma is within, mm; default 0.005", {}}});
  std::vector<Vec3> scan;
  o.push_raw("scan");
  const lua_Integer n = luaL_len(L, -1);
  scan.reserve(static_cast<size_t>(n));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    scan.push_back(luax::check_vec3(L, -1, "scan[i]"));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  std::vector<std::shared_ptr<const Surface>> surfaces;
  o.push_raw("surfaces");
  for (lua_Integer i = 1; i <= luaL_len(L, -1); ++i) {
    lua_rawgeti(L, -1, i);
    surfaces.push_back(luax::check<SurfaceHandle>(L, -1).surface);
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  const int samples = static_cast<int>(o.integer("samples", 300));
  RegistrationOptions ro;
  ro.initial_reach_mm = o.number("initial_reach", ro.initial_reach_mm);
  ro.outlier_factor = o.number("outlier_factor", ro.outlier_factor);
  ro.pre_align = o.boolean("pre_align", true);
  ro.capture_deg = o.number("capture_angle", ro.capture_deg);
  ro.capture_mm = o.number("capture_offset", ro.capture_mm);
  RegistrationLimits limits;
  limits.noise_mm = o.number("noise", limits.noise_mm);
  limits.rms_factor = o.number("rms_factor", limits.rms_factor);
  limits.max_condition = o.number("max_condition", limits.max_condition);
  limits.max_sigma_point_mm = o.number("max_sigma", limits.max_sigma_point_mm);
  return luax::guarded(L, [&] {
    ModelSample model;
    for (const auto& s : surfaces)
      for (int i = 0; i < samples; ++i)
        for (int j = 0; j < samples; ++j) {
          const SurfaceDerivs d = s->eval(static_cast<double>(i) / (samples - 1), static_cast<double>(j) / (samples - 1));
          const Vec3 nrm = d.pu.cross(d.pv);
          if (nrm.norm() < 1e-12) continue;
          model.points.push_back(d.p);
          model.normals.push_back(nrm.normalized());
        }
    const RegistrationResult r = register_points(scan, model, ro);
    lua_createtable(L, 0, 8);
    lua_createtable(L, 0, 4);
    luax::set_vec3(L, "origin", r.transform.translation());
    luax::set_vec3(L, "x", r.transform.linear().col(0));
    luax::set_vec3(L, "y", r.transform.linear().col(1));
    luax::set_vec3(L, "z", r.transform.linear().col(2));
    lua_setfield(L, -2, "transform");
    luax::set_number(L, "angle", rad_to_deg(Eigen::AngleAxisd(r.transform.linear()).angle()));
    luax::set_number(L, "iterations", r.iterations);
    luax::set_bool(L, "converged", r.converged);
    luax::set_number(L, "inliers", r.inliers);
    luax::set_number(L, "outliers", r.outliers);
    luax::set_number(L, "rms", r.rms_mm);
    luax::set_number(L, "median", r.median_mm);
    // The pose's uncertainty (inf where a direction is not fixed) and the verdict.
    const PoseUncertainty& u = r.uncertainty;
    luax::set_number(L, "condition", u.condition);
    luax::set_number(L, "unconstrained", u.unconstrained);
    lua_createtable(L, 0, 4);
    luax::set_vec3(L, "rotation", u.sigma_rotation_rad * (180.0 / kPi));
    luax::set_vec3(L, "translation", u.sigma_translation_mm);
    luax::set_number(L, "point", u.sigma_point_mm);
    luax::set_vec3(L, "centroid", u.centroid);
    lua_setfield(L, -2, "sigma");
    luax::set_number(L, "starts", r.starts);
    luax::set_number(L, "start", r.start);
    const RegistrationCheck check = check_registration(r, limits);
    luax::set_bool(L, "trusted", check.trusted);
    luax::set_strings(L, "problems", check.problems);
    return 1;
  });
}

}  // namespace

void open_geometry(lua_State* L) {
  static const luaL_Reg grid_methods[] = {{"size", w_grid_size}, {"point", w_grid_point},
                                          {"surface", w_interpolate_grid}, {"rotated", w_grid_rotated},
                                          {nullptr, nullptr}};
  luax::register_type<GridHandle>(L, grid_methods);
  static const luaL_Reg surface_methods[] = {{"eval", w_surface_eval},
                                             {"point", w_surface_point},
                                             {"curvature", w_surface_curvature},
                                             {"normal_curvature", w_surface_normal_curvature},
                                             {"project", w_surface_project},
                                             {"tessellate", w_surface_tessellate},
                                             {"rotated", w_surface_rotated},
                                             {"reoriented", w_surface_reoriented},
                                             {nullptr, nullptr}};
  luax::register_type<SurfaceHandle>(L, surface_methods);
  static const luaL_Reg curve_methods[] = {{"eval", w_curve_eval}, {"project", w_curve_project}, {nullptr, nullptr}};
  luax::register_type<CurveHandle>(L, curve_methods);
  static const luaL_Reg mesh_methods[] = {{"write_stl", w_mesh_write_stl}, {"size", w_mesh_size}, {nullptr, nullptr}};
  luax::register_type<MeshHandle>(L, mesh_methods);

  static const luaL_Reg functions[] = {{"point_grid", w_point_grid},
                                       {"interpolate_grid", w_interpolate_grid},
                                       {"interpolate_curve", w_interpolate_curve},
                                       {"surface_of_revolution", w_surface_of_revolution},
                                       {"intersect_revolution", w_intersect_revolution},
                                       {"offset_revolution", w_offset_revolution},
                                       {"register_scan", w_register_scan},
                                       {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
