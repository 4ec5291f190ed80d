// Blade repair (repair paper, SPEC §6.5): bliskrun.rebuild_sections, the
// blade lofted through measured sections and the measured points' deviation
// from it (core/repair/rebuild.h); the damaged blade, its measurement files,
// the rebuild of damaged sections and the damaged region
// (core/repair/damaged_blade.h, damaged_rebuild.h, damaged_region.h).
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <cstdio>
#include <filesystem>

#include "core/analysis/heat_map.h"
#include "core/io/rotor37_reader.h"
#include "core/parts/builtin_blisk.h"
#include "core/repair/damaged_blade.h"
#include "core/repair/damaged_rebuild.h"
#include "core/repair/damaged_region.h"
#include "core/repair/rebuild.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"
#include "lua_api/wrap_parts.h"

namespace bliskrun::lua_api {
struct DamagedBladeHandle {
  std::shared_ptr<const DamagedBlade> blade;
};
struct MeasurementHandle {
  std::shared_ptr<const SectionMeasurement> measurement;
};
struct RebuildHandle {
  std::shared_ptr<const DamagedRebuild> rebuild;
};
struct RegionHandle {
  std::shared_ptr<const DamagedRebuild> rebuild;  // the face refers to it
  std::shared_ptr<const DamageFace> face;
  std::shared_ptr<const DamagedRegion> region;
};
}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <> struct TypeName<lua_api::DamagedBladeHandle> { static constexpr const char* name = "bliskrun.DamagedBlade"; };
template <> struct TypeName<lua_api::MeasurementHandle> { static constexpr const char* name = "bliskrun.SectionMeasurement"; };
template <> struct TypeName<lua_api::RebuildHandle> { static constexpr const char* name = "bliskrun.DamagedRebuild"; };
template <> struct TypeName<lua_api::RegionHandle> { static constexpr const char* name = "bliskrun.DamagedRegion"; };
}  // namespace bliskrun::luax

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

// The options bliskrun.rebuild_sections and bliskrun.rebuild_damaged share
// (threads, smoothing, samples, align_samples, max_step, outlier) into ro.
void read_rebuild_options(lua_State* L, const luax::Options& o, RebuildOptions& ro) {
  ro.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
  ro.smoothing_mm = o.number("smoothing", ro.smoothing_mm);
  ro.loft.samples = static_cast<int>(o.integer("samples", ro.loft.samples));
  ro.align_samples = static_cast<int>(o.integer("align_samples", ro.align_samples));
  ro.order.max_step_mm = o.number("max_step", 0);
  ro.order.outlier_mm = o.number("outlier", 0);
}

// A new table {mean =, rms =, max =, points =}: how far the rebuilt loft
// lies from the measured points (mm), with room for `fields` in all.
void push_deviation(lua_State* L, const LoftDeviation& d, int fields) {
  lua_createtable(L, 0, fields);
  luax::set_number(L, "mean", d.mean_mm);
  luax::set_number(L, "rms", d.rms_mm);
  luax::set_number(L, "max", d.max_mm);
  luax::set_number(L, "points", d.points);
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
       Field{"threads", Kind::Integer, false, 1, 256,
             "sections processed on this many threads (default: the run's --threads); the result does not depend on it", {}},
       number_field("outlier", "distance from the neighbours' local curve that makes a stray, mm (default: from the noise)", 0, 1e4)});
  RebuildOptions ro;
  read_rebuild_options(L, o, ro);
  ro.axis = o.vec3("axis", ro.axis);

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
    push_deviation(L, blade->deviation, 8);
    luax::set_number(L, "worst", blade->deviation.worst + 1);
    luax::set_numbers(L, "section_u", blade->loft.section_u);
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


// ---- damaged blade, measurement, rebuild, region ----

// bliskrun.damaged_blade{rotor37 = path, design_sections = 25, twist = deg, bend = mm,
// deform_from = s, tip_span = s, tip_tilt = deg, edge_from = s, edge_to = s, edge_depth = mm,
// te_from = s, te_to = s, te_depth = mm, dent_depth = mm, dent_radius = mm, dent_span = s, dent_chord =, dent_side = ±1}
int w_damaged_blade(lua_State* L) {
  static const char* what = "bliskrun.damaged_blade";
  const luax::Options o(
      L, 1, what,
      {Field{"rotor37", Kind::String, false, std::nullopt, std::nullopt,
             "Rotor 37 rotor37geometry.dat (or its folder): the blade to damage instead of the built-in blisk's blade 1", {}},
       Field{"loops", Kind::Table, false, std::nullopt, std::nullopt,
             "closed section loops hub -> tip ({{{x, y, z}, ...}, ...}, mm; first point not repeated): any blade, e.g. "
             "one from CAD, instead of the built-in blisk's blade 1", {}},
       Field{"design_sections", Kind::Integer, false, 4, 400, "built-in blade: section loops of its design loft (default 25)", {}},
       number_field("twist", "twist of the tip section about the stacking axis, degrees (default 0)", -20, 20),
       number_field("bend", "bend of the tip section across the chord, mm (default 0)", -50, 50),
       number_field("deform_from", "span fraction where the twist and bend start (default 0.3)", 0, 0.99),
       number_field("tip_span", "tip broken off above this span fraction (no tip damage without it)", 0, 1),
       number_field("tip_tilt", "tilt of the break plane towards the flow, degrees (default 0)", -45, 45),
       number_field("edge_from", "leading-edge nick from this span fraction (default 0.4)", 0, 1),
       number_field("edge_to", "... to this one (default 0.65)", 0, 1),
       number_field("edge_depth", "nick depth along the chord, mm (no edge damage without it)", 0, 100),
       number_field("te_from", "trailing-edge nick from this span fraction (default 0.4)", 0, 1),
       number_field("te_to", "... to this one (default 0.65)", 0, 1),
       number_field("te_depth", "trailing-edge nick depth along the chord, mm (no trailing-edge nick without it)", 0, 100),
       number_field("dent_depth", "spherical nick (dent) in a flank, its depth, mm (no dent without it)", 0, 100),
       number_field("dent_radius", "the dent's sphere radius, mm (default 3)", 0, 1000),
       number_field("dent_span", "the dent's span fraction (default 0.5)", 0, 1),
       number_field("dent_chord", "the dent's place along the chord, a fraction from the leading edge (default 0.5)", 0, 1),
       Field{"dent_side", Kind::Integer, false, -1, 1, "the dent's flank: 1 the side of +e2, -1 of -e2 (default 1)", {}}});
  BladeDamage d;
  d.twist_rad = deg_to_rad(o.number("twist", 0));
  d.bend_mm = o.number("bend", 0);
  d.deform_from = o.number("deform_from", d.deform_from);
  d.tip = o.has("tip_span");
  d.tip_span = o.number("tip_span", d.tip_span);
  d.tip_tilt_rad = deg_to_rad(o.number("tip_tilt", 0));
  d.edge = o.has("edge_depth");
  d.edge_from = o.number("edge_from", d.edge_from);
  d.edge_to = o.number("edge_to", d.edge_to);
  d.edge_depth_mm = o.number("edge_depth", d.edge_depth_mm);
  d.te_edge = o.has("te_depth");
  d.te_from = o.number("te_from", d.te_from);
  d.te_to = o.number("te_to", d.te_to);
  d.te_depth_mm = o.number("te_depth", d.te_depth_mm);
  d.dent = o.has("dent_depth");
  d.dent_depth_mm = o.number("dent_depth", d.dent_depth_mm);
  d.dent_radius_mm = o.number("dent_radius", d.dent_radius_mm);
  d.dent_span = o.number("dent_span", d.dent_span);
  d.dent_chord = o.number("dent_chord", d.dent_chord);
  d.dent_side = static_cast<int>(o.integer("dent_side", d.dent_side));
  std::string rotor37;
  if (o.has("rotor37")) {
    namespace fs = std::filesystem;
    rotor37 = context(L).resolve_read(L, o.string("rotor37", ""));
    if (fs::is_directory(rotor37)) {
      for (const std::string& c : {rotor37 + "/rotor37geometry.dat", rotor37 + "/agard_table/rotor37geometry.dat",
                                  rotor37 + "/nasa_rotor37/agard_table/rotor37geometry.dat"})
        if (fs::is_regular_file(c)) rotor37 = c;
      if (fs::is_directory(rotor37)) luax::error(L, std::string(what) + ": option 'rotor37': no rotor37geometry.dat in '" + rotor37 + "'");
    }
  }
  std::vector<std::vector<Vec3>> loops;
  if (o.has("loops")) {
    if (o.has("rotor37")) luax::error(L, std::string(what) + ": give 'rotor37' or 'loops', not both");
    o.push_raw("loops");
    loops = check_point_loops(L, lua_gettop(L), std::string(what) + ": ", "loops", "loop");
    lua_pop(L, 1);
  }
  const int design_sections = static_cast<int>(o.integer("design_sections", 25));
  return luax::guarded(L, [&] {
    DesignBlade design;
    if (!loops.empty()) {
      design = design_blade(loops);
    } else if (rotor37.empty()) {
      design = builtin_design_blade(BuiltinBlisk(), 0, design_sections);
    } else {
      const std::string folder = std::filesystem::path(rotor37).parent_path().string();
      design = design_blade(read_rotor37(rotor37, folder + "/rotor37hub-shroud.dat"));
    }
    luax::push_new(L, DamagedBladeHandle{std::make_shared<DamagedBlade>(std::move(design), d)});
    return 1;
  });
}

// blade:design() -> Surface (the design loft, u hub -> tip, v around)
int w_blade_design(lua_State* L) {
  const auto& h = luax::check<DamagedBladeHandle>(L, 1);
  push_surface(L, std::shared_ptr<const Surface>(h.blade, &h.blade->design().loft.surface));
  return 1;
}

// blade:info() -> {h_lo, h_hi, origin, axis, e1, e2}
int w_blade_info(lua_State* L) {
  const DesignBlade& d = luax::check<DamagedBladeHandle>(L, 1).blade->design();
  lua_createtable(L, 0, 6);
  luax::set_number(L, "h_lo", d.h_lo);
  luax::set_number(L, "h_hi", d.h_hi);
  luax::set_vec3(L, "origin", d.frame.origin);
  luax::set_vec3(L, "axis", d.frame.axis);
  luax::set_vec3(L, "e1", d.frame.e1);
  luax::set_vec3(L, "e2", d.frame.e2);
  return 1;
}

// blade:measure{sections = 30, points = 2000, noise = 0.002, outliers = 0.005,
// unseen_arc = 0, face_points = 60, seed = 1, span_from = 0.03, span_to = 0.97}
int w_blade_measure(lua_State* L) {
  const auto& h = luax::check<DamagedBladeHandle>(L, 1);
  const luax::Options o(
      L, 2, "blade:measure",
      {Field{"sections", Kind::Integer, false, 2, 10000, "measurement planes (default 30)", {}},
       Field{"points", Kind::Integer, false, 16, 10000000, "points per section before the damage's gaps (default 2000)", {}},
       number_field("noise", "sigma of the probe's noise along the normal, mm (default 0.002)", 0, 0.1),
       number_field("outliers", "fraction of stray points (default 0.005)", 0, 0.1),
       number_field("unseen_arc", "an arc the probe misses, centred at the section's extreme along -e2, mm (default 0)", 0, 1000),
       Field{"face_points", Kind::Integer, false, 0, 100000, "points on a broken tip's fracture face (default 60)", {}},
       Field{"seed", Kind::Integer, false, 0, 1e15, "random seed (default 1)", {}},
       number_field("span_from", "lowest plane, span fraction (default 0.03)", 0, 1),
       number_field("span_to", "highest plane, span fraction (default 0.97)", 0, 1)});
  MeasurementOptions mo;
  mo.sections = static_cast<int>(o.integer("sections", mo.sections));
  mo.points = static_cast<int>(o.integer("points", mo.points));
  mo.noise_mm = o.number("noise", mo.noise_mm);
  mo.outlier_fraction = o.number("outliers", mo.outlier_fraction);
  mo.unseen_arc_mm = o.number("unseen_arc", mo.unseen_arc_mm);
  mo.face_points = static_cast<int>(o.integer("face_points", mo.face_points));
  mo.seed = static_cast<std::uint64_t>(o.integer("seed", 1));
  mo.span_from = o.number("span_from", mo.span_from);
  mo.span_to = o.number("span_to", mo.span_to);
  return luax::guarded(L, [&] {
    luax::push_new(L, MeasurementHandle{std::make_shared<SectionMeasurement>(measure_sections(*h.blade, mo))});
    return 1;
  });
}

// measurement:summary() -> {sections, points, face, heights = {...}, counts = {...}}
int w_measurement_summary(lua_State* L) {
  const SectionMeasurement& m = *luax::check<MeasurementHandle>(L, 1).measurement;
  lua_createtable(L, 0, 5);
  size_t points = 0;
  lua_createtable(L, static_cast<int>(m.sections.size()), 0);
  lua_createtable(L, static_cast<int>(m.sections.size()), 0);
  for (size_t k = 0; k < m.sections.size(); ++k) {
    points += m.sections[k].points.size();
    lua_pushnumber(L, m.sections[k].height_mm);
    lua_rawseti(L, -3, static_cast<lua_Integer>(k + 1));
    lua_pushinteger(L, static_cast<lua_Integer>(m.sections[k].points.size()));
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_setfield(L, -3, "counts");
  lua_setfield(L, -2, "heights");
  luax::set_number(L, "sections", static_cast<double>(m.sections.size()));
  luax::set_number(L, "points", static_cast<double>(points));
  luax::set_number(L, "face", static_cast<double>(m.face.size()));
  if (std::isfinite(m.planned_top_mm)) luax::set_number(L, "planned_top", m.planned_top_mm);
  return 1;
}

// bliskrun.read_sections(path) -> SectionMeasurement
int w_read_sections(lua_State* L) {
  const std::string path = context(L).resolve_read(L, luax::check_string(L, 1, "path"));
  return luax::guarded(L, [&] {
    luax::push_new(L, MeasurementHandle{std::make_shared<SectionMeasurement>(read_section_measurement(path))});
    return 1;
  });
}

// bliskrun.write_sections(path, measurement) -> full path
int w_write_sections(lua_State* L) {
  const std::string path = context(L).resolve_write(L, luax::check_string(L, 1, "path"));
  const auto& m = luax::check<MeasurementHandle>(L, 2);
  return luax::guarded(L, [&] {
    write_section_measurement(path, *m.measurement);
    lua_pushstring(L, path.c_str());
    return 1;
  });
}

const char* source_name(SectionSource s) {
  switch (s) {
    case SectionSource::measured: return "measured";
    case SectionSource::completed: return "completed";
    case SectionSource::extended: return "extended";
  }
  return "?";
}

// bliskrun.rebuild_damaged{measurement=, blade=, smoothing = 0.1, samples = 512,
// align_samples = 2048, design_samples = 1024, max_step=, outlier=,
// between_tolerance = 0.01}
// -> Surface, report (with .quality: the check between sections), DamagedRebuild
int w_rebuild_damaged(lua_State* L) {
  static const char* what = "bliskrun.rebuild_damaged";
  const luax::Options o(
      L, 1, what,
      {Field{"measurement", Kind::Any, true, std::nullopt, std::nullopt, "the SectionMeasurement (blade:measure, bliskrun.read_sections)", {}},
       Field{"blade", Kind::Any, true, std::nullopt, std::nullopt, "the DamagedBlade whose design fills the damage", {}},
       number_field("smoothing", "smoothing length, mm (default 0.1)", 0, 100),
       Field{"samples", Kind::Integer, false, 16, 100000, "loft samples per section (default 512)", {}},
       Field{"align_samples", Kind::Integer, false, 16, 1 << 20, "curvature samples for the start alignment (default 2048)", {}},
       Field{"design_samples", Kind::Integer, false, 16, 1 << 20, "points of a design plane section for the ICP (default 1024)", {}},
       number_field("max_step", "longest step between neighbouring points of a section, mm (default: from the spacing)", 0, 1e4),
       Field{"threads", Kind::Integer, false, 1, 256,
             "sections processed on this many threads (default: the run's --threads); the result does not depend on it", {}},
       number_field("outlier", "distance from the neighbours' local curve that makes a stray, mm (default: from the noise)", 0, 1e4),
       number_field("between_tolerance",
                    "largest distance of the rebuilt blade's section midway between two sections from the design's "
                    "registered to it, for the rebuild to be trusted, mm (default 0.01)", 0, 100),
       number_field("dent_depth", "measured points this far inside the registered design, over at least min_dent of "
                    "the profile, are a dent's floor, mm (default 0.05; 0: no dents looked for)", 0, 100),
       number_field("min_dent", "shortest dent along the profile, mm (default 0.3)", 0, 1000),
       Field{"thin_above", Kind::Integer, false, 0, 1 << 30,
             "a section of more points is thinned on the way in (default 20000; 0: never)", {}},
       number_field("thin_spacing", "spacing of a thinned section's points, mm (default a quarter of the smoothing)", 0,
                    100),
       number_field("planned_top",
                    "the measurement plan's highest section, mm along the axis, when the measurement does not state it "
                    "(tells a broken tip from the plan's margin)", -1e6, 1e6)});
  o.push_raw("measurement");
  const auto m = luax::check<MeasurementHandle>(L, -1).measurement;
  lua_pop(L, 1);
  o.push_raw("blade");
  const auto b = luax::check<DamagedBladeHandle>(L, -1).blade;
  lua_pop(L, 1);
  DamagedRebuildOptions ro;
  read_rebuild_options(L, o, ro.rebuild);
  ro.design_samples = static_cast<int>(o.integer("design_samples", ro.design_samples));
  ro.between_tolerance_mm = o.number("between_tolerance", ro.between_tolerance_mm);
  ro.dent_depth_mm = o.number("dent_depth", ro.dent_depth_mm);
  ro.min_dent_mm = o.number("min_dent", ro.min_dent_mm);
  ro.rebuild.thin_above = static_cast<int>(o.integer("thin_above", ro.rebuild.thin_above));
  ro.rebuild.thin_spacing_mm = o.number("thin_spacing", ro.rebuild.thin_spacing_mm);
  ro.planned_top_mm = o.number("planned_top", ro.planned_top_mm);
  return luax::guarded(L, [&] {
    auto r = std::make_shared<DamagedRebuild>(rebuild_damaged(*m, b->design(), ro));
    push_surface(L, std::shared_ptr<const Surface>(r, &r->loft.surface));
    push_deviation(L, r->deviation, 10);
    luax::set_bool(L, "tip_extended", r->tip_extended);
    luax::set_number(L, "top_measured", r->top_measured_mm);
    luax::set_string(L, "tip_basis", r->tip_basis);
    lua_createtable(L, static_cast<int>(r->sections.size()), 0);
    for (size_t k = 0; k < r->sections.size(); ++k) {
      const DamagedSection& s = r->sections[k];
      lua_createtable(L, 0, 12);
      luax::set_number(L, "height", s.height_mm);
      luax::set_string(L, "source", source_name(s.source));
      luax::set_number(L, "index", s.index);
      luax::set_number(L, "thinned", s.thinned);
      luax::set_number(L, "kept", s.kept);
      luax::set_number(L, "rejected", s.rejected);
      luax::set_number(L, "gaps", s.gaps);
      luax::set_number(L, "gap", s.gap_mm);
      luax::set_number(L, "dents", s.dents);
      luax::set_bool(L, "registered", s.registered);
      luax::set_number(L, "angle", rad_to_deg(s.motion.angle_rad));
      luax::set_vec3(L, "shift", Vec3(s.motion.shift.x(), s.motion.shift.y(), 0));
      luax::set_number(L, "registration_rms", s.registration_rms_mm);
      luax::set_number(L, "start_correlation", s.start_correlation);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "sections");
    const RebuildQuality& q = r->quality;
    lua_createtable(L, 0, 10);
    luax::set_bool(L, "trusted", q.trusted);
    luax::set_string(L, "message", q.message);
    luax::set_string(L, "start_method", q.start_method);
    luax::set_number(L, "attempts", q.attempts);
    luax::set_number(L, "tolerance", q.tolerance_mm);
    luax::set_number(L, "between_max", q.between_max_mm);
    luax::set_number(L, "between_at", q.between_at_mm);
    luax::set_number(L, "least_correlation", q.least_correlation);
    luax::set_numbers(L, "attempt_max", q.attempt_max_mm);
    lua_createtable(L, static_cast<int>(q.between.size()), 0);
    for (size_t k = 0; k < q.between.size(); ++k) {
      lua_createtable(L, 0, 3);
      luax::set_number(L, "height", q.between[k].height_mm);
      luax::set_number(L, "max", q.between[k].max_mm);
      luax::set_number(L, "rms", q.between[k].rms_mm);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "between");
    lua_setfield(L, -2, "quality");
    luax::push_new(L, RebuildHandle{r});
    return 3;
  });
}

// rebuild:write_deviation_png(path [, {rows = 60, cols = 240, scale = mm}]):
// the measured points' signed deviation from the rebuilt surface, averaged
// per (u, v) cell (grey: no point).
int w_rebuild_deviation_png(lua_State* L) {
  const auto r = luax::check<RebuildHandle>(L, 1).rebuild;
  const std::string path = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  const luax::Options o(L, 3, "rebuild:write_deviation_png",
                        {Field{"rows", Kind::Integer, false, 2, 4000, "cells along u (span), default 60", {}},
                         Field{"cols", Kind::Integer, false, 2, 4000, "cells along v (around), default 240", {}},
                         number_field("scale", "colour scale half range, mm (default: the largest |mean|)", 0, 100)});
  HeatMap map;
  map.rows = static_cast<int>(o.integer("rows", 60));
  map.cols = static_cast<int>(o.integer("cols", 240));
  const double scale = o.number("scale", 0);
  return luax::guarded(L, [&] {
    std::vector<double> sum(static_cast<size_t>(map.rows) * map.cols, 0.0);
    std::vector<int> count(sum.size(), 0);
    for (const PointDeviation& p : r->point_deviations) {
      const int i = std::clamp(static_cast<int>(p.u * map.rows), 0, map.rows - 1);
      const int j = std::clamp(static_cast<int>(p.v * map.cols), 0, map.cols - 1);
      sum[static_cast<size_t>(i) * map.cols + j] += p.signed_mm * 1e3;
      ++count[static_cast<size_t>(i) * map.cols + j];
    }
    map.values.resize(sum.size());
    for (size_t c = 0; c < sum.size(); ++c) map.values[c] = count[c] ? sum[c] / count[c] : std::nan("");
    HeatMapOptions h;
    h.title = "Measured points - rebuilt blade: signed deviation (um), u span up, v around the section";
    h.value_label = "um";
    char footer[200];
    std::snprintf(footer, sizeof footer, "%d points: mean |d| %.2f um, rms %.2f um, max %.2f um; %d x %d cells",
                  r->deviation.points, 1e3 * r->deviation.mean_mm, 1e3 * r->deviation.rms_mm, 1e3 * r->deviation.max_mm,
                  map.rows, map.cols);
    h.footer = footer;
    h.scale_max = scale * 1e3;
    write_heat_map_png(map, path, h);
    lua_pushstring(L, path.c_str());
    return 1;
  });
}

// bliskrun.damaged_region{rebuild=, measurement=, layer = 0.2, layers = 3,
// samples_u = 150, samples_v = 1200, slices = 200, min_gap = 0.3} -> report, DamagedRegion
int w_damaged_region(lua_State* L) {
  static const char* what = "bliskrun.damaged_region";
  const luax::Options o(
      L, 1, what,
      {Field{"rebuild", Kind::Any, true, std::nullopt, std::nullopt, "the DamagedRebuild (third result of rebuild_damaged)", {}},
       Field{"measurement", Kind::Any, true, std::nullopt, std::nullopt, "the SectionMeasurement it was rebuilt from", {}},
       number_field("layer", "offset layer thickness, mm (default 0.2)", 1e-6, 100),
       Field{"layers", Kind::Integer, false, 0, 1000, "offset layers (default 3)", {}},
       Field{"samples_u", Kind::Integer, false, 4, 100000, "thickness map rows along u (default 150)", {}},
       Field{"samples_v", Kind::Integer, false, 8, 100000, "thickness map columns along v (default 1200)", {}},
       Field{"slices", Kind::Integer, false, 4, 100000, "slices through a broken tip for its volume (default 200)", {}},
       number_field("min_gap", "shorter section gaps are not damage, mm (default 0.3)", 0, 1000)});
  o.push_raw("rebuild");
  const auto r = luax::check<RebuildHandle>(L, -1).rebuild;
  lua_pop(L, 1);
  o.push_raw("measurement");
  const auto m = luax::check<MeasurementHandle>(L, -1).measurement;
  lua_pop(L, 1);
  DamagedRegionOptions ro;
  ro.layer_mm = o.number("layer", ro.layer_mm);
  ro.layers = static_cast<int>(o.integer("layers", ro.layers));
  ro.samples_u = static_cast<int>(o.integer("samples_u", ro.samples_u));
  ro.samples_v = static_cast<int>(o.integer("samples_v", ro.samples_v));
  ro.slices = static_cast<int>(o.integer("slices", ro.slices));
  ro.min_gap_mm = o.number("min_gap", ro.min_gap_mm);
  return luax::guarded(L, [&] {
    auto region = std::make_shared<DamagedRegion>(damaged_region(*r, *m, ro));
    auto face = std::make_shared<DamageFace>(*r, *m, ro.min_gap_mm);
    const DamagedRegion& g = *region;
    lua_createtable(L, 0, 24);
    luax::set_bool(L, "empty", g.empty);
    luax::set_bool(L, "tip", g.tip);
    luax::set_vec3(L, "break_normal", g.break_normal);
    luax::set_number(L, "break_offset", g.break_offset);
    luax::set_number(L, "face_points", g.face_points);
    luax::set_number(L, "face_rms", g.face_rms_mm);
    luax::set_number(L, "tip_volume", g.tip_volume_mm3);
    luax::set_number(L, "nicked_sections", g.nicked_sections);
    luax::set_number(L, "nicks", g.nicks);
    luax::set_number(L, "dents", g.dents);
    luax::set_number(L, "skipped_gaps", g.skipped_gaps);
    luax::set_number(L, "edge_volume", g.edge_volume_mm3);
    luax::set_number(L, "volume", g.volume_mm3);
    luax::set_number(L, "max_thickness", g.max_thickness_mm);
    luax::set_number(L, "area", g.area_mm2);
    luax::set_number(L, "u_from", g.u_from);
    luax::set_number(L, "u_to", g.u_to);
    luax::set_number(L, "v_from", g.v_from);
    luax::set_number(L, "v_to", g.v_to);
    luax::set_number(L, "height_from", g.height_from_mm);
    luax::set_number(L, "height_to", g.height_to_mm);
    lua_createtable(L, static_cast<int>(g.layers.size()), 0);
    for (size_t k = 0; k < g.layers.size(); ++k) {
      lua_createtable(L, 0, 2);
      luax::set_number(L, "offset", g.layers[k].offset_mm);
      luax::set_number(L, "points", static_cast<double>(g.layers[k].points.size()));
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "layers");
    luax::push_new(L, RegionHandle{r, face, region});
    return 2;
  });
}

// region:thickness(u, v) -> mm of missing material along the rebuilt surface's normal at (u, v)
int w_region_thickness(lua_State* L) {
  const auto& h = luax::check<RegionHandle>(L, 1);
  const double u = luax::check_number(L, 2, "u"), v = luax::check_number(L, 3, "v");
  if (!(u >= 0 && u <= 1 && std::isfinite(v))) luax::error(L, "region:thickness: expected u in [0, 1] and a finite v");
  const SurfaceDerivs d = h.rebuild->loft.surface.eval(u, v - std::floor(v));
  std::vector<Vec2> section;
  lua_pushnumber(L, normal_thickness(*h.face, d.p, d.pu.cross(d.pv).normalized(), section));
  return 1;
}

// The rebuilt surface over the region's (u, v) box, reparametrised to [0, 1]^2.
class RegionPatch : public Surface {
 public:
  RegionPatch(std::shared_ptr<const DamagedRebuild> r, double u0, double u1, double v0, double v1)
      : r_(std::move(r)), u0_(u0), du_(u1 - u0), v0_(v0), dv_(v1 >= v0 ? v1 - v0 : v1 + 1 - v0) {}
  SurfaceDerivs eval(double u, double v) const override {
    double vv = v0_ + v * dv_;
    vv -= std::floor(vv);
    SurfaceDerivs d = r_->loft.surface.eval(u0_ + u * du_, vv);
    d.pu *= du_;
    d.pv *= dv_;
    d.puu *= du_ * du_;
    d.puv *= du_ * dv_;
    d.pvv *= dv_ * dv_;
    return d;
  }

 private:
  std::shared_ptr<const DamagedRebuild> r_;
  double u0_, du_, v0_, dv_;
};

// region:surface() -> Surface: the rebuilt blade over the region's (u, v) box
int w_region_surface(lua_State* L) {
  const auto& h = luax::check<RegionHandle>(L, 1);
  const DamagedRegion& g = *h.region;
  if (g.empty) luax::error(L, "region:surface: the region is empty");
  push_surface(L, std::make_shared<RegionPatch>(h.rebuild, g.u_from, g.u_to, g.v_from, g.v_to));
  return 1;
}

// region:layer(k) -> {offset = mm, points = {{x, y, z}, ...}, uv = {{u, v}, ...}}
int w_region_layer(lua_State* L) {
  const auto& h = luax::check<RegionHandle>(L, 1);
  const long long k = luax::check_integer(L, 2, "layer");
  if (k < 1 || k > static_cast<long long>(h.region->layers.size()))
    luax::error(L, "region:layer: expected a layer in [1, " + std::to_string(h.region->layers.size()) + "]");
  const OffsetLayer& l = h.region->layers[k - 1];
  lua_createtable(L, 0, 3);
  luax::set_number(L, "offset", l.offset_mm);
  lua_createtable(L, static_cast<int>(l.points.size()), 0);
  for (size_t i = 0; i < l.points.size(); ++i) {
    luax::push(L, l.points[i]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "points");
  lua_createtable(L, static_cast<int>(l.uv.size()), 0);
  for (size_t i = 0; i < l.uv.size(); ++i) {
    lua_createtable(L, 2, 0);
    lua_pushnumber(L, l.uv[i].x());
    lua_rawseti(L, -2, 1);
    lua_pushnumber(L, l.uv[i].y());
    lua_rawseti(L, -2, 2);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "uv");
  return 1;
}

// region:write_png(path) -> full path: the thickness map over the rebuilt surface
int w_region_png(lua_State* L) {
  const auto& h = luax::check<RegionHandle>(L, 1);
  const std::string path = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  const DamagedRegion& g = *h.region;
  return luax::guarded(L, [&] {
    HeatMap map;
    map.rows = g.map_u;
    map.cols = g.map_v;
    map.values = g.thickness_map;
    HeatMapOptions o;
    o.title = "Damaged region: material to deposit and machine (mm), u span up, v around the section";
    o.value_label = "mm";
    char footer[200];
    std::snprintf(footer, sizeof footer, "volume %.2f mm3, max thickness %.3f mm, u %.3f..%.3f, v %.3f..%.3f",
                  g.volume_mm3, g.max_thickness_mm, g.u_from, g.u_to, g.v_from, g.v_to);
    o.footer = footer;
    write_heat_map_png(map, path, o);
    lua_pushstring(L, path.c_str());
    return 1;
  });
}
}  // namespace

void open_repair(lua_State* L) {
  static const luaL_Reg blade_methods[] = {{"design", w_blade_design}, {"measure", w_blade_measure},
                                           {"info", w_blade_info}, {nullptr, nullptr}};
  luax::register_type<DamagedBladeHandle>(L, blade_methods);
  static const luaL_Reg measurement_methods[] = {{"summary", w_measurement_summary}, {nullptr, nullptr}};
  luax::register_type<MeasurementHandle>(L, measurement_methods);
  static const luaL_Reg rebuild_methods[] = {{"write_deviation_png", w_rebuild_deviation_png}, {nullptr, nullptr}};
  luax::register_type<RebuildHandle>(L, rebuild_methods);
  static const luaL_Reg region_methods[] = {{"thickness", w_region_thickness}, {"surface", w_region_surface},
                                            {"layer", w_region_layer}, {"write_png", w_region_png}, {nullptr, nullptr}};
  luax::register_type<RegionHandle>(L, region_methods);
  static const luaL_Reg functions[] = {{"rebuild_sections", w_rebuild_sections},
                                       {"damaged_blade", w_damaged_blade},
                                       {"read_sections", w_read_sections},
                                       {"write_sections", w_write_sections},
                                       {"rebuild_damaged", w_rebuild_damaged},
                                       {"damaged_region", w_damaged_region},
                                       {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
