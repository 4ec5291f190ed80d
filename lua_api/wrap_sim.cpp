// bliskrun.simulate: the undercut simulation (core/sim) of any surface under
// any toolpath, each pass with its own tool — what a job needs to measure
// the material its operations leave on a part that no planner's own
// simulation covers (an impeller's hub and faces after notching, widening
// and flank finishing).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/common/fixed_text.h"
#include "core/sim/undercut.h"
#include "lua_api/lua_tool.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/undercut_map.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;
using luax::number_field;

// The passes of one group: consecutive passes with the same tool form one
// run; `global` maps the group's pass numbers to the order given.
struct PassGroup {
  std::string name;
  std::vector<std::vector<ToolPass>> run_passes;
  std::vector<const Tool*> run_tools;
  std::vector<int> global;
};

// Pushes a result table (the figures, where the deepest overcut is, the map).
void push_result(lua_State* L, UndercutResult u, const UndercutOptions& so, const Surface& design, long poses,
                 double seconds) {
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
  long highest_at = -1;  // the sample with the most material left (a seam's report says where)
  for (size_t i = 0; i < u.residual_mm.size(); ++i) {
    const double x = u.residual_mm[i];
    if (!std::isfinite(x)) continue;
    lowest = std::min(lowest, x);
    if (x > highest) highest = x, highest_at = static_cast<long>(i);
  }
  const auto sample_uv = [&](long sample) {
    const long row = sample / so.samples_v, col = sample % so.samples_v;
    return std::make_pair(so.u0 + (so.u1 - so.u0) * static_cast<double>(row) / (so.samples_u - 1),
                          so.v0 + (so.v1 - so.v0) * static_cast<double>(col) / (so.samples_v - 1));
  };
  lua_createtable(L, 0, 20);
  set_undercut_stats(L, u);
  // The material left over the samples the tools reached (nil if none).
  if (std::isfinite(lowest)) {
    luax::set_number(L, "residual_min", lowest);
    luax::set_number(L, "residual_max", highest);
    const auto [hu, hv] = sample_uv(highest_at);
    luax::set_number(L, "residual_max_u", hu);
    luax::set_number(L, "residual_max_v", hv);
    luax::set_vec3(L, "residual_max_point", design.point(hu, hv));
  }
  if (u.overcut_sample >= 0) {
    // Which motion cut deepest: pass (1-based, in the order given) and the
    // pose its motion ends at (1-based; the motion from pose k - 1 to k) —
    // unknown (-1) when `keep` dropped the sample the sweep found deepest.
    if (u.overcut_pass >= 0) {
      luax::set_integer(L, "overcut_pass", u.overcut_pass + 1);
      luax::set_integer(L, "overcut_pose", u.overcut_pose + 1);
    }
    const auto [su, sv] = sample_uv(u.overcut_sample);
    luax::set_number(L, "overcut_u", su);
    luax::set_number(L, "overcut_v", sv);
    luax::set_vec3(L, "overcut_point", design.point(su, sv));
  }
  set_undercut_counts(L, u);
  luax::set_integer(L, "poses", poses);
  luax::set_number(L, "seconds", seconds);
  char head[120];
  std::snprintf(head, sizeof head, "%d x %d samples (u %.3f-%.3f up, v %.3f-%.3f across); ", u.samples_u, u.samples_v,
                so.u0, so.u1, so.v0, so.v1);
  const auto um = [](double mm) { return significant_text(1e3 * mm) + " µm"; };
  const std::string footer = head + ("undercut max " + um(u.undercut_max_mm) + ", mean " + um(u.undercut_mean_mm) +
                                     "; overcut " + um(u.overcut_mm) + "; untouched " + std::to_string(u.untouched));
  push_undercut_map(L, u.samples_u, u.samples_v, std::move(u.residual_mm), footer);
  lua_setfield(L, -2, "map");
}

// bliskrun.simulate{surface=, passes = {{tool=, poses = {...}, group=}, ...}, ...}
int w_simulate(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.simulate",
      {Field{"surface", Kind::Any, true, std::nullopt, std::nullopt, "design surface (Surface)", {}},
       Field{"passes", Kind::Table, true, std::nullopt, std::nullopt,
             "list of {tool = Tool, poses = {{tip=, axis=}, ...}, group = name}: each pass moves pose to pose as "
             "the machine does", {}},
       Field{"samples_u", Kind::Integer, false, 2, 5000, "design samples along u (default 100)", {}},
       Field{"samples_v", Kind::Integer, false, 2, 20000, "design samples along v (default 400)", {}},
       Field{"u", Kind::Table, false, std::nullopt, std::nullopt, "sampled u window {lo, hi} (default {0, 1})", {}},
       Field{"v", Kind::Table, false, std::nullopt, std::nullopt, "sampled v window {lo, hi} (default {0, 1})", {}},
       Field{"flip_normal", Kind::Boolean, false, std::nullopt, std::nullopt,
             "the normal out of the material is -(pu x pv) (default false)", {}},
       number_field("search_above", "how far above the surface material is tracked, mm (default 1)", 1e-4, 100),
       number_field("search_below", "how deep a gouge is measured, mm (default 0.5)", 1e-4, 100),
       number_field("sweep_step", "largest cutter-point motion between positions, mm (default 0.05)", 1e-4, 10),
       Field{"threads", Kind::Integer, false, 1, 256, "worker threads (default: the run's --threads)", {}},
       Field{"keep", Kind::Table, false, std::nullopt, std::nullopt,
             "{true|false, ...} per sample, row-major (u outer): the region measured; the others are NaN in the "
             "map and in no figure", {}}});
  o.push_raw("surface");
  const SurfaceHandle* surface = luax::test<SurfaceHandle>(L, -1);
  if (!surface) luax::error(L, "bliskrun.simulate: option 'surface': expected a bliskrun.Surface");
  const std::shared_ptr<const Surface> design = surface->surface;
  lua_pop(L, 1);

  std::vector<PassGroup> groups;
  bool labelled = false;
  o.push_raw("passes");
  const int passes = lua_gettop(L);
  const lua_Integer n = luaL_len(L, passes);
  long poses_total = 0;
  std::vector<long> group_poses;
  for (lua_Integer i = 1; i <= n; ++i) {
    const std::string what = "bliskrun.simulate: passes[" + std::to_string(i) + "]";
    lua_rawgeti(L, passes, i);
    const int pass = lua_gettop(L);
    if (!lua_istable(L, pass)) luax::error(L, what + ": expected {tool = Tool, poses = {...}}");
    lua_getfield(L, pass, "tool");
    const LuaTool* tool = luax::test<LuaTool>(L, -1);
    if (!tool) luax::error(L, what + ".tool: expected a bliskrun.Tool");
    lua_pop(L, 1);
    lua_getfield(L, pass, "group");
    const bool has_group = !lua_isnil(L, -1);
    if (has_group && !lua_isstring(L, -1)) luax::error(L, what + ".group: expected a name");
    if (i > 1 && has_group != labelled) luax::error(L, what + ".group: every pass or none has a group");
    labelled = has_group;
    const std::string name = has_group ? lua_tostring(L, -1) : "";
    lua_pop(L, 1);
    lua_getfield(L, pass, "poses");
    const int poses = lua_gettop(L);
    if (!lua_istable(L, poses)) luax::error(L, what + ".poses: expected a list of poses");
    ToolPass p;
    const lua_Integer m = luaL_len(L, poses);
    p.reserve(static_cast<size_t>(m));
    for (lua_Integer k = 1; k <= m; ++k) {
      lua_rawgeti(L, poses, k);
      p.push_back(pose_from_table(L, -1, (what + ".poses[" + std::to_string(k) + "]").c_str()));
      lua_pop(L, 1);
    }
    poses_total += static_cast<long>(m);
    size_t g = 0;
    while (g < groups.size() && groups[g].name != name) ++g;
    if (g == groups.size()) {
      groups.push_back(PassGroup{name, {}, {}, {}});
      group_poses.push_back(0);
    }
    PassGroup& group = groups[g];
    group_poses[g] += static_cast<long>(m);
    if (group.run_tools.empty() || group.run_tools.back() != &tool->tool) {
      group.run_tools.push_back(&tool->tool);
      group.run_passes.emplace_back();
    }
    group.run_passes.back().push_back(std::move(p));
    group.global.push_back(static_cast<int>(i - 1));
    lua_pop(L, 2);
  }
  lua_pop(L, 1);
  if (groups.empty()) groups.push_back(PassGroup{});
  group_poses.resize(groups.size(), 0);

  UndercutOptions so;
  so.samples_u = static_cast<int>(o.integer("samples_u", 100));
  so.samples_v = static_cast<int>(o.integer("samples_v", 400));
  read_unit_window(L, o, "bliskrun.simulate", "u", so.u0, so.u1);
  read_unit_window(L, o, "bliskrun.simulate", "v", so.v0, so.v1);
  so.flip_normal = o.boolean("flip_normal", false);
  so.search_above_mm = o.number("search_above", 1.0);
  so.search_below_mm = o.number("search_below", 0.5);
  so.sweep_step_mm = o.number("sweep_step", so.sweep_step_mm);
  so.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
  // The region measured: a sample outside it becomes NaN after the sweep
  // (summarise_residual leaves NaN out of every figure).
  std::vector<char> keep;
  if (o.has("keep")) {
    o.push_raw("keep");
    const lua_Unsigned n = lua_rawlen(L, -1);
    if (n != static_cast<lua_Unsigned>(so.samples_u) * static_cast<lua_Unsigned>(so.samples_v))
      luax::error(L, "bliskrun.simulate: option 'keep': expected samples_u x samples_v = " +
                         std::to_string(static_cast<long>(so.samples_u) * so.samples_v) + " booleans, got " +
                         std::to_string(static_cast<unsigned long long>(n)));
    keep.resize(n);
    for (lua_Unsigned i = 1; i <= n; ++i) {
      lua_rawgeti(L, -1, static_cast<lua_Integer>(i));
      keep[i - 1] = lua_toboolean(L, -1) ? 1 : 0;
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  const auto apply_keep = [&](UndercutResult& r) {
    if (keep.empty()) return;
    const long deepest = r.overcut_sample;
    for (size_t i = 0; i < keep.size(); ++i)
      if (!keep[i]) r.residual_mm[i] = std::numeric_limits<double>::quiet_NaN();
    summarise_residual(r, so);
    // The motion that cut deepest is known only for the sample the sweep found.
    if (r.overcut_sample != deepest) r.overcut_pass = r.overcut_pose = -1;
  };
  return luax::guarded(L, [&] {
    // Each group swept on its own; the whole is the lowest of the groups'
    // maps (every motion belongs to one group), not a second sweep.
    std::vector<UndercutResult> results;
    std::vector<double> seconds;
    for (const PassGroup& g : groups) {
      std::vector<ToolRun> runs;
      for (size_t r = 0; r < g.run_tools.size(); ++r) runs.push_back(ToolRun{g.run_tools[r], &g.run_passes[r]});
      const auto t0 = std::chrono::steady_clock::now();
      results.push_back(simulate_undercut(*design, runs, so, context(L).progress));
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      if (results.back().overcut_pass >= 0) results.back().overcut_pass = g.global[results.back().overcut_pass];
      apply_keep(results.back());
    }
    UndercutResult whole = results.front();
    double whole_seconds = seconds.front();
    for (size_t k = 1; k < results.size(); ++k) {
      for (size_t i = 0; i < whole.residual_mm.size(); ++i)
        whole.residual_mm[i] = std::min(whole.residual_mm[i], results[k].residual_mm[i]);
      whole.tool_positions += results[k].tool_positions;
      whole.line_evaluations += results[k].line_evaluations;
      whole_seconds += seconds[k];
    }
    if (results.size() > 1) {
      summarise_residual(whole, so);
      whole.overcut_pass = whole.overcut_pose = -1;
      for (const UndercutResult& r : results)  // the first group (in the order given) that cut that deep there
        if (whole.overcut_sample >= 0 && r.overcut_sample >= 0 &&
            r.residual_mm[whole.overcut_sample] <= whole.overcut_mm) {
          whole.overcut_pass = r.overcut_pass;
          whole.overcut_pose = r.overcut_pose;
          break;
        }
    }
    push_result(L, std::move(whole), so, *design, poses_total, whole_seconds);
    if (labelled) {
      lua_createtable(L, static_cast<int>(groups.size()), 0);
      for (size_t k = 0; k < groups.size(); ++k) {
        push_result(L, std::move(results[k]), so, *design, group_poses[k], seconds[k]);
        luax::set_string(L, "name", groups[k].name);
        lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
      }
      lua_setfield(L, -2, "groups");
    }
    return 1;
  });
}

// bliskrun.map_mosaic{rows = {{tile, ...}, ...}, gap = 2, footer =, u_label =,
// v_label =} -> UndercutMap: several maps as one picture, the tiles of a row
// side by side (left to right), the rows top to bottom (the first row drawn
// highest), each tile at its own samples; a tile is a map or {map =,
// transpose = bool, label = text} (rows and columns swapped, e.g. an edge
// region's u around / v span set beside flanks' u span / v across; the
// label written in the tile's top-left corner, e.g. its surface). The cells
// between and around tiles are NaN ("not part of this map", hatched), so
// they do not read as "never reached"; the axes are named by the options,
// without 0..1 ticks (no one parameter runs across a mosaic).
int w_map_mosaic(lua_State* L) {
  const luax::Options o(L, 1, "bliskrun.map_mosaic",
                        {Field{"rows", Kind::Table, true, std::nullopt, std::nullopt,
                               "{{map | {map =, transpose =}, ...}, ...}: tiles left to right, rows top to bottom", {}},
                         Field{"gap", Kind::Integer, false, 0, 1000, "NaN cells between tiles (default 2)", {}},
                         Field{"footer", Kind::String, false, std::nullopt, std::nullopt, "line under the picture", {}},
                         Field{"u_label", Kind::String, false, std::nullopt, std::nullopt,
                               "what runs up the tiles (default \"up: each tile's own parameter\")", {}},
                         Field{"v_label", Kind::String, false, std::nullopt, std::nullopt,
                               "what runs across the tiles (default \"across: each tile's own parameter\")", {}}});
  struct Tile {
    const HeatMap* map;
    bool transpose;
    std::string label;
    int rows() const { return transpose ? map->cols : map->rows; }
    int cols() const { return transpose ? map->rows : map->cols; }
    double at(int i, int j) const { return transpose ? map->at(j, i) : map->at(i, j); }
  };
  std::vector<std::vector<Tile>> rows;
  o.push_raw("rows");
  const int rows_idx = lua_gettop(L);
  const lua_Unsigned nr = lua_rawlen(L, rows_idx);
  if (nr == 0) luax::error(L, "bliskrun.map_mosaic: option 'rows': expected at least one row of maps");
  for (lua_Unsigned r = 1; r <= nr; ++r) {
    lua_rawgeti(L, rows_idx, static_cast<lua_Integer>(r));
    const std::string where = "bliskrun.map_mosaic: rows[" + std::to_string(r) + "]";
    if (!lua_istable(L, -1)) luax::error(L, where + ": expected a list of maps");
    rows.emplace_back();
    const lua_Unsigned nt = lua_rawlen(L, -1);
    for (lua_Unsigned t = 1; t <= nt; ++t) {
      lua_rawgeti(L, -1, static_cast<lua_Integer>(t));
      Tile tile{nullptr, false, {}};
      if (const auto* m = luax::test<LuaUndercutMap>(L, -1)) {
        tile.map = &m->map;
      } else if (lua_istable(L, -1)) {
        lua_getfield(L, -1, "map");
        if (const auto* m2 = luax::test<LuaUndercutMap>(L, -1)) tile.map = &m2->map;
        lua_getfield(L, -2, "transpose");
        tile.transpose = lua_toboolean(L, -1);
        lua_getfield(L, -3, "label");
        if (!lua_isnil(L, -1) && !lua_isstring(L, -1))
          luax::error(L, where + "[" + std::to_string(t) + "].label: expected text");
        if (!lua_isnil(L, -1)) tile.label = lua_tostring(L, -1);
        lua_pop(L, 3);
      }
      if (!tile.map || tile.map->rows < 1 || tile.map->cols < 1)
        luax::error(L, where + "[" + std::to_string(t) + "]: expected an UndercutMap or {map = UndercutMap, transpose =}");
      rows.back().push_back(tile);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  const int gap = static_cast<int>(o.integer("gap", 2));
  int height = gap, width = 0;
  for (const auto& row : rows) {
    int h = 0, w = gap;
    for (const Tile& t : row) h = std::max(h, t.rows()), w += t.cols() + gap;
    height += h + gap;
    width = std::max(width, w);
  }
  // Map rows are drawn bottom up (row 0 lowest), so the first mosaic row
  // goes at the top: fill from the last row of cells down.
  std::vector<double> values(static_cast<size_t>(height) * width, std::numeric_limits<double>::quiet_NaN());
  std::vector<HeatMapLabel> labels;
  int top = height - gap;  // one past the highest cell row of the next mosaic row
  for (const auto& row : rows) {
    int h = 0;
    for (const Tile& t : row) h = std::max(h, t.rows());
    int left = gap;
    for (const Tile& t : row) {
      const int base = top - h;  // tiles sit on the row's bottom
      for (int i = 0; i < t.rows(); ++i)
        for (int j = 0; j < t.cols(); ++j)
          values[static_cast<size_t>(base + i) * width + left + j] = t.at(i, j);
      if (!t.label.empty())
        labels.push_back(HeatMapLabel{static_cast<double>(left) / width,
                                      static_cast<double>(base + t.rows()) / height, t.label});
      left += t.cols() + gap;
    }
    top -= h + gap;
  }
  LuaUndercutMap mosaic;
  mosaic.map.rows = height;
  mosaic.map.cols = width;
  mosaic.map.values = std::move(values);
  mosaic.footer = o.string("footer", "");
  mosaic.labels = std::move(labels);
  mosaic.u_label = o.string("u_label", "up: each tile's own parameter");
  mosaic.v_label = o.string("v_label", "across: each tile's own parameter");
  mosaic.fraction_ticks = false;
  luax::push_new(L, std::move(mosaic));
  return 1;
}

}  // namespace

void open_sim(lua_State* L) {
  static const luaL_Reg functions[] = {{"simulate", w_simulate}, {"map_mosaic", w_map_mosaic}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
