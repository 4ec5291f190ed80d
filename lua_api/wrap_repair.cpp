// Blade repair (repair paper, SPEC §6.5): bliskrun.rebuild_sections, the
// blade lofted through measured sections and the measured points' deviation
// from it (core/repair/rebuild.h).
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/repair/rebuild.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;
using luax::number_field;

// One point of a section at the top of the stack: {x, y, z}, or {x, y} on a
// section that gives its height.
// (has_z, z) rather than an optional: g++ 12 warns it maybe uninitialised.
Vec3 read_point(lua_State* L, const std::string& where, bool has_z, double z) {
  if (lua_istable(L, -1) && has_z && lua_rawlen(L, -1) == 2) {
    double c[2];
    for (int a = 0; a < 2; ++a) {
      lua_rawgeti(L, -1, a + 1);
      int ok = 0;
      c[a] = lua_tonumberx(L, -1, &ok);
      lua_pop(L, 1);
      if (!ok || !std::isfinite(c[a])) luax::error(L, where + ": expected {x, y} or {x, y, z} of finite numbers");
    }
    return Vec3(c[0], c[1], z);
  }
  if (!lua_istable(L, -1)) luax::error(L, where + ": expected " + (has_z ? "{x, y} or {x, y, z}" : "{x, y, z}"));
  Vec3 p = Vec3::Zero();
  for (int a = 0; a < 3; ++a) {
    lua_rawgeti(L, -1, a + 1);
    int ok = 0;
    p[a] = lua_tonumberx(L, -1, &ok);
    lua_pop(L, 1);
    if (!ok || !std::isfinite(p[a]))
      luax::error(L, where + ": expected " + (has_z ? "{x, y} or {x, y, z}" : "{x, y, z}") + " of finite numbers");
  }
  return p;
}

// bliskrun.rebuild_sections{sections = {{points = {{x,y,z}, ...}, z = h}, ...}, smoothing = L, ...}
// -> Surface, {mean, rms, max, points, worst, section_u, sections = {...}}
int w_rebuild_sections(lua_State* L) {
  static const char* what = "bliskrun.rebuild_sections";
  const luax::Options o(
      L, 1, what,
      {Field{"sections", Kind::Table, true, std::nullopt, std::nullopt,
             "the measured sections from the first (hub) to the last: {{points = {{x,y,z}, ...}, z = h}, ...}", {}},
       Field{"smoothing", Kind::Number, true, 0, 100,
             "smoothing length, mm: below the smallest edge radius, above the point spacing", {}},
       Field{"samples", Kind::Integer, false, 16, 100000, "loft samples per section at equal arc length (default 512)", {}},
       Field{"align_samples", Kind::Integer, false, 16, 1 << 20,
             "curvature samples per section for the start alignment (default 2048)", {}},
       Field{"axis", Kind::Vec3, false, std::nullopt, std::nullopt, "stacking direction, first section to last (default {0, 0, 1})", {}},
       number_field("max_step", "longest step between neighbouring points of a section, mm (default: from the spacing)", 0, 1e4),
       number_field("outlier", "distance from the neighbours' local curve that makes a stray, mm (default: from the noise)", 0, 1e4)});
  RebuildOptions ro;
  ro.smoothing_mm = o.number("smoothing", ro.smoothing_mm);
  ro.loft.samples = static_cast<int>(o.integer("samples", ro.loft.samples));
  ro.align_samples = static_cast<int>(o.integer("align_samples", ro.align_samples));
  ro.axis = o.vec3("axis", ro.axis);
  ro.order.max_step_mm = o.number("max_step", 0);
  ro.order.outlier_mm = o.number("outlier", 0);

  std::vector<std::vector<Vec3>> sections;
  o.push_raw("sections");
  const int list = lua_absindex(L, -1);
  const lua_Integer n = luaL_len(L, list);
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_rawgeti(L, list, k);
    const std::string where = std::string(what) + ": sections[" + std::to_string(k) + "]";
    if (!lua_istable(L, -1)) luax::error(L, where + ": expected {points = {...}, z = h}");
    const luax::Options s(L, lua_absindex(L, -1), where,
                          {Field{"points", Kind::Table, true, std::nullopt, std::nullopt,
                                 "the section's measured points {{x,y,z}, ...} (or {x, y} with z), mm, any order", {}},
                           number_field("z", "the section's height, mm, for points given as {x, y}")});
    const bool has_z = s.has("z");
    const double z = s.number("z", 0);
    s.push_raw("points");
    std::vector<Vec3> points;
    const lua_Integer m = luaL_len(L, -1);
    for (lua_Integer i = 1; i <= m; ++i) {
      lua_rawgeti(L, -1, i);
      points.push_back(read_point(L, where + ".points[" + std::to_string(i) + "]", has_z, z));
      lua_pop(L, 1);
    }
    lua_pop(L, 2);  // points, section
    sections.push_back(std::move(points));
  }
  lua_pop(L, 1);  // sections

  return luax::guarded(L, [&] {
    auto blade = std::make_shared<RebuiltBlade>(rebuild_blade(sections, ro));
    // The surface shares the rebuilt blade's lifetime through an aliasing pointer.
    push_surface(L, std::shared_ptr<const Surface>(blade, &blade->loft.surface));
    const LoftDeviation& d = blade->deviation;
    lua_createtable(L, 0, 8);
    luax::set_number(L, "mean", d.mean_mm);
    luax::set_number(L, "rms", d.rms_mm);
    luax::set_number(L, "max", d.max_mm);
    luax::set_number(L, "points", d.points);
    luax::set_number(L, "worst", d.worst + 1);
    lua_createtable(L, static_cast<int>(blade->loft.section_u.size()), 0);
    for (size_t k = 0; k < blade->loft.section_u.size(); ++k) {
      lua_pushnumber(L, blade->loft.section_u[k]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "section_u");
    lua_createtable(L, static_cast<int>(blade->sections.size()), 0);
    for (size_t k = 0; k < blade->sections.size(); ++k) {
      const RebuiltSection& s = blade->sections[k];
      lua_createtable(L, 0, 7);
      luax::set_number(L, "kept", s.kept);
      luax::set_number(L, "rejected", static_cast<double>(s.rejected.size()));
      luax::set_number(L, "spacing", s.spacing_mm);
      luax::set_number(L, "smoothing_shift", s.smoothing_shift_mm);
      luax::set_number(L, "start_shift", s.start_shift_mm);
      luax::set_number(L, "start_correlation", s.start_correlation);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "sections");
    return 2;
  });
}

}  // namespace

void open_repair(lua_State* L) {
  static const luaL_Reg functions[] = {{"rebuild_sections", w_rebuild_sections}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
