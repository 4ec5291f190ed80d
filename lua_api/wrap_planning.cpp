// bliskrun.drum_finish{...} and bliskrun.drum_finish_all{...}: blisk flank
// finishing with a drum wheel (core/planning/drum_finish.h), the plan's
// report, APT/CL output and its undercut simulation (core/sim). Lengths in
// mm, angles in degrees. See docs/lua_api.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "core/analysis/heat_map.h"
#include "core/common/fixed_text.h"
#include "core/planning/drum_finish.h"
#include "core/sim/undercut.h"
#include "lua_api/finish_moves.h"
#include "lua_api/undercut_map.h"
#include "lua_api/lua_tool.h"
#include "lua_api/modules.h"
#include "lua_api/refusal_reasons.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_collision.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

// A plan and everything its request points to, kept alive together.
struct LuaDrumPlan {
  std::string name;
  std::shared_ptr<const Surface> flank, hub, casing;
  std::shared_ptr<const Tool> tool;
  std::shared_ptr<const CollisionWorld> world;
  DrumFinishRequest request;  // points into the members above
  std::shared_ptr<const DrumFinishResult> result;
};

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaDrumPlan> {
  static constexpr const char* name = "bliskrun.DrumFinishPlan";
};
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {
namespace {

using luax::Field;
using luax::Kind;
using luax::set_bool;
using luax::set_number;
using luax::set_string;

// ---- reading ---------------------------------------------------------------

// Keys every drum-finish call takes besides the per-flank ones.
std::vector<Field> common_fields() {
  std::vector<Field> f = tilt_option_fields();
  const std::vector<Field> own = {
      Field{"hub", Kind::Any, true, std::nullopt, std::nullopt, "hub as a surface of revolution (blisk:hub())", {}},
      Field{"casing", Kind::Any, true, std::nullopt, std::nullopt, "casing as a surface of revolution", {}},
      Field{"tool", Kind::Any, true, std::nullopt, std::nullopt, "a drum wheel (bliskrun.tool.drum_wheel)", {}},
      Field{"residual", Kind::Number, false, 1e-6, 10.0, "allowed residual (scallop) height, mm (default 0.014)", {}},
      Field{"chord_tol", Kind::Number, false, 1e-6, 10.0, "chord height tolerance along a row, mm (default 0.002)", {}},
      Field{"steps", Kind::String, false, std::nullopt, std::nullopt,
            "step along a row: \"variable\" (eq. 18-19, default) or \"constant\" (eq. 17)", {"variable", "constant"}},
      Field{"guarantee", Kind::Boolean, false, std::nullopt, std::nullopt,
            "measure every segment and shorten it to chord_tol (default true; false reproduces eq. 17 as written)", {}},
      Field{"max_step", Kind::Number, false, 1e-3, 1000.0, "longest step along a row, mm (default 5)", {}},
      Field{"zigzag", Kind::Boolean, false, std::nullopt, std::nullopt, "alternate row direction (default true)", {}},
      Field{"top_down", Kind::Boolean, false, std::nullopt, std::nullopt,
            "cut the rows from the tip down to the hub (default false: from the hub up)", {}},
      Field{"flip_normal", Kind::Boolean, false, std::nullopt, std::nullopt,
            "the flank's pu x pv points into the material (default false)", {}},
      Field{"width_samples", Kind::Integer, false, 2, 10000, "contacts per row sampled for the width (default 40)", {}},
      Field{"trim_samples", Kind::Integer, false, 4, 100000, "iso-v lines intersected with hub and casing (default 200)", {}},
      Field{"retract", Kind::Number, false, 1e-3, 1000.0,
            "largest offset a link between rows leaves the flank by, mm (default 5; halved until the link is proved)", {}},
      Field{"link", Kind::String, false, std::nullopt, std::nullopt,
            "how a link leaves the flank: \"normal\" (along the flank normal, default: a drum wheel cuts with its side) "
            "or \"axis\" (along the tool axis)", {"normal", "axis"}},
      Field{"link_overcut", Kind::Number, false, 0.0, 1.0,
            "how far a link may dip below the finished flank, mm (default: chord_tol)", {}},
      Field{"guard_spacing", Kind::Number, false, 0.01, 10.0,
            "spacing of the finished-flank samples every link is proved against, mm (default 0.1)", {}},
      Field{"hub_clearance", Kind::Number, false, 0.0, 100.0,
            "the first row is the lowest whose wheel clears the hub by this, mm (default 0.02)", {}},
      Field{"tool_tol", Kind::Number, false, 1e-5, 1.0, "tessellation tolerance of the tool's collision body, mm", {}},
  };
  f.insert(f.end(), own.begin(), own.end());
  return f;
}

// A plan with everything but the flank and the world.
LuaDrumPlan read_common(lua_State* L, const luax::Options& o, const std::string& what) {
  LuaDrumPlan p;
  p.hub = revolution_option(L, o, "hub", what);
  p.casing = revolution_option(L, o, "casing", what);
  p.tool = tool_option(L, o, what, "a drum wheel");
  if (p.tool->kind() != ToolKind::DrumWheel && p.tool->kind() != ToolKind::ConicalDrumWheel)
    luax::error(L, what + ": option 'tool': expected a drum wheel, got a " + to_string(p.tool->kind()));

  DrumFinishRequest& rq = p.request;
  rq.hub = static_cast<const SurfaceOfRevolution*>(p.hub.get());
  rq.casing = static_cast<const SurfaceOfRevolution*>(p.casing.get());
  rq.tool = p.tool.get();
  rq.residual_height_mm = o.number("residual", 0.014);
  rq.steps.chord_tol_mm = o.number("chord_tol", 0.002);
  rq.steps.method = o.string("steps", "variable") == "constant" ? ChordMethod::Constant : ChordMethod::Variable;
  rq.steps.guarantee_tolerance = o.boolean("guarantee", true);
  rq.steps.max_step_mm = o.number("max_step", 5.0);
  rq.zigzag = o.boolean("zigzag", true);
  rq.top_down = o.boolean("top_down", false);
  rq.flip_normal = o.boolean("flip_normal", false);
  rq.width_samples = static_cast<int>(o.integer("width_samples", 40));
  rq.trim_samples_v = static_cast<int>(o.integer("trim_samples", 200));
  rq.links.retract_mm = o.number("retract", 5.0);
  rq.links.min_retract_mm = std::min(rq.links.min_retract_mm, rq.links.retract_mm);
  rq.links.direction =
      o.string("link", "normal") == "axis" ? RetractDirection::ToolAxis : RetractDirection::SurfaceNormal;
  rq.links.allowed_overcut_mm = o.number("link_overcut", rq.steps.chord_tol_mm);
  rq.guard_spacing_mm = o.number("guard_spacing", 0.1);
  rq.hub_clearance_mm = o.number("hub_clearance", 0.02);
  rq.tool_tol_mm = o.number("tool_tol", 1e-3);
  rq.tilt = read_tilt_settings(L, o, what);
  return p;
}

void set_flank_and_world(lua_State* L, const luax::Options& o, const std::string& what, LuaDrumPlan& p) {
  o.push_raw("flank");
  const SurfaceHandle* s = luax::test<SurfaceHandle>(L, -1);
  if (!s) luax::error(L, what + ": option 'flank': expected a bliskrun.Surface");
  p.flank = s->surface;
  lua_pop(L, 1);
  p.world = world_option(L, o, what, " (neighbouring blades, hub)");
  p.request.flank = p.flank;
  p.request.world = p.world.get();
  p.name = o.string("name", "");
}

const std::vector<Field> kFlankFields = {
    Field{"flank", Kind::Any, true, std::nullopt, std::nullopt, "the flank to finish (u hub->tip, v along the chord)", {}},
    Field{"world", Kind::Any, true, std::nullopt, std::nullopt, "check surfaces: neighbouring blades and hub", {}},
    Field{"name", Kind::String, false, std::nullopt, std::nullopt, "name used in reports (default \"\")", {}},
};

int threads_option(const luax::Options& o, lua_State* L) {
  return static_cast<int>(o.integer("threads", context(L).options.threads));
}

// ---- functions -------------------------------------------------------------

int w_drum_finish(lua_State* L) {
  return luax::guarded(L, [&] {
    const std::string what = "bliskrun.drum_finish";
    std::vector<Field> fields = common_fields();
    fields.insert(fields.end(), kFlankFields.begin(), kFlankFields.end());
    const luax::Options o(L, 1, what, fields);
    LuaDrumPlan p = read_common(L, o, what);
    set_flank_and_world(L, o, what, p);
    p.result = std::make_shared<const DrumFinishResult>(plan_drum_finish(p.request, context(L).progress));
    luax::push_new(L, std::move(p));
    return 1;
  });
}

// bliskrun.trim_flank{flank=, hub=, casing=, samples=200} -> the flank
// between hub and casing (u' = 0 on the hub curve, 1 on the casing), the
// region a drum finish machines (Table 1 over the machined flank).
int w_trim_flank(lua_State* L) {
  return luax::guarded(L, [&] {
    const std::string what = "bliskrun.trim_flank";
    const luax::Options o(L, 1, what, {
        Field{"flank", Kind::Any, true, std::nullopt, std::nullopt, "the flank (u hub->tip, v along the chord)", {}},
        Field{"hub", Kind::Any, true, std::nullopt, std::nullopt, "hub as a surface of revolution (blisk:hub())", {}},
        Field{"casing", Kind::Any, true, std::nullopt, std::nullopt, "casing as a surface of revolution", {}},
        Field{"samples", Kind::Integer, false, 4, 100000, "iso-v lines intersected with hub and casing (default 200)", {}},
    });
    const std::shared_ptr<const Surface> hub = revolution_option(L, o, "hub", what);
    const std::shared_ptr<const Surface> casing = revolution_option(L, o, "casing", what);
    o.push_raw("flank");
    const SurfaceHandle* flank = luax::test<SurfaceHandle>(L, -1);
    if (!flank) luax::error(L, what + ": option 'flank': expected a bliskrun.Surface");
    const std::shared_ptr<const Surface> base = flank->surface;
    lua_pop(L, 1);
    push_surface(L, trim_between(base, static_cast<const SurfaceOfRevolution&>(*hub),
                                 static_cast<const SurfaceOfRevolution&>(*casing),
                                 static_cast<int>(o.integer("samples", 200))));
    return 1;
  });
}

int w_drum_finish_all(lua_State* L) {
  return luax::guarded(L, [&] {
    const std::string what = "bliskrun.drum_finish_all";
    std::vector<Field> fields = common_fields();
    fields.push_back(Field{"jobs", Kind::Table, true, std::nullopt, std::nullopt,
                           "list of {flank=, world=, name=, flip_normal=}", {}});
    fields.push_back(Field{"threads", Kind::Integer, false, 1, 256,
                           "worker threads (default: the run's --threads); outputs do not depend on it", {}});
    const luax::Options o(L, 1, what, fields);
    const LuaDrumPlan common = read_common(L, o, what);
    std::vector<LuaDrumPlan> plans;
    o.push_raw("jobs");
    const int jobs = lua_gettop(L);
    const lua_Integer n = luaL_len(L, jobs);
    if (n < 1) luax::error(L, what + ": option 'jobs': expected at least one {flank=, world=}");
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, jobs, i);
      const std::string jwhat = what + " jobs[" + std::to_string(i) + "]";
      std::vector<Field> jf = kFlankFields;
      jf.push_back(Field{"flip_normal", Kind::Boolean, false, std::nullopt, std::nullopt,
                         "overrides the common flip_normal", {}});
      jf.push_back(Field{"axis_limit", Kind::Table, false, std::nullopt, std::nullopt,
                         "this flank's rotary-axis limit, on top of the common ones", {}});
      const luax::Options j(L, lua_gettop(L), jwhat, jf);
      LuaDrumPlan p = common;
      set_flank_and_world(L, j, jwhat, p);
      p.request.flip_normal = j.boolean("flip_normal", common.request.flip_normal);
      if (j.has("axis_limit")) {
        j.push_raw("axis_limit");
        const AxisLimit own = read_axis_limit(L, lua_gettop(L), jwhat + ".axis_limit");
        lua_pop(L, 1);
        const AxisLimit shared = common.request.tilt.axis_limit;
        p.request.tilt.axis_limit = [own, shared](const Vec3& axis) {
          std::string why = shared ? shared(axis) : std::string();
          return why.empty() ? own(axis) : why;
        };
      }
      plans.push_back(std::move(p));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    std::vector<DrumFinishRequest> requests;
    for (const LuaDrumPlan& p : plans) requests.push_back(p.request);
    std::vector<DrumFinishResult> results = plan_drum_finish_all(requests, threads_option(o, L), context(L).progress);
    lua_createtable(L, static_cast<int>(plans.size()), 0);
    for (size_t k = 0; k < plans.size(); ++k) {
      plans[k].result = std::make_shared<const DrumFinishResult>(std::move(results[k]));
      luax::push_new(L, std::move(plans[k]));
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    return 1;
  });
}

// ---- plan methods ----------------------------------------------------------

LuaDrumPlan& check_drum_plan(lua_State* L) { return luax::check<LuaDrumPlan>(L, 1); }

int w_drum_plan_report(lua_State* L) {
  const LuaDrumPlan& p = check_drum_plan(L);
  const DrumFinishResult& r = *p.result;
  const DrumFinishRequest& rq = p.request;
  lua_createtable(L, 0, 24);
  set_string(L, "name", p.name);
  set_string(L, "tool", rq.tool->description());
  set_number(L, "residual", rq.residual_height_mm);
  set_number(L, "chord_tol", rq.steps.chord_tol_mm);
  set_string(L, "steps", rq.steps.method == ChordMethod::Constant ? "constant" : "variable");
  set_bool(L, "guarantee", rq.steps.guarantee_tolerance);
  set_bool(L, "zigzag", rq.zigzag);
  set_bool(L, "top_down", rq.top_down);
  luax::set_integer(L, "row_count", r.rows.size());
  luax::set_integer(L, "poses", r.total_poses);
  luax::set_integer(L, "refusals", r.total_refusals);
  luax::set_integer(L, "refused_links", r.refused_links);
  // How the links leave the flank and what proved them: the retract
  // direction, the smallest and largest offset used, the deepest sampled dip
  // below the finished flank over every link (<= 0) and the allowance.
  {
    double off_min = std::numeric_limits<double>::infinity(), off_max = 0, deepest = 0, turn_max = 0;
    int turned = 0;
    for (const DrumFinishLink& l : r.links) {
      if (!l.clear) continue;
      off_min = std::min(off_min, l.offset_mm);
      off_max = std::max(off_max, l.offset_mm);
      deepest = std::min(deepest, l.deepest_cut_mm);
      turned += l.turn_rad > 0;
      turn_max = std::max(turn_max, l.turn_rad);
    }
    for (const DrumFinishEnd* e : {&r.lead_in, &r.lead_out}) {
      if (!e->clear) continue;
      deepest = std::min(deepest, e->deepest_cut_mm);
      turned += e->turn_rad > 0;
      turn_max = std::max(turn_max, e->turn_rad);
    }
    lua_createtable(L, 0, 6);
    set_string(L, "retract", rq.links.direction == RetractDirection::SurfaceNormal ? "normal" : "axis");
    set_number(L, "offset_min", off_max > 0 ? off_min : 0);
    set_number(L, "offset_max", off_max);
    set_number(L, "deepest_cut", deepest);
    set_number(L, "allowed_overcut", rq.links.allowed_overcut_mm);
    set_number(L, "guard_spacing", r.guard_spacing_mm);
    // Links and leads whose direction was turned from the normal up the axis
    // (a neighbouring surface in the way), and the largest turn, degrees.
    luax::set_integer(L, "turned", turned);
    set_number(L, "turn_max", rad_to_deg(turn_max));
    set_number(L, "lead_in", r.lead_in.clear ? r.lead_in.offset_mm : 0);    // offset, 0 when refused
    set_number(L, "lead_out", r.lead_out.clear ? r.lead_out.offset_mm : 0);
    lua_setfield(L, -2, "links");
  }
  set_number(L, "max_deviation", r.max_deviation_mm);
  set_number(L, "first_row_u", r.first_row_u);
  set_number(L, "hub_strip", r.hub_strip_mm);
  double wmin = std::numeric_limits<double>::infinity(), wmax = 0, lead_raised = 0;
  long contacts = 0, tilted = 0;
  lua_createtable(L, static_cast<int>(r.rows.size()), 0);
  for (size_t i = 0; i < r.rows.size(); ++i) {
    const DrumFinishRow& row = r.rows[i];
    wmin = std::min(wmin, row.width_mm);
    wmax = std::max(wmax, row.width_mm);
    contacts += row.contacts;
    lua_createtable(L, 0, 8);
    set_number(L, "u", row.u);
    set_number(L, "width", row.width_mm);
    set_number(L, "reach_below", row.reach_below_mm);
    set_number(L, "reach_above", row.reach_above_mm);
    set_number(L, "spacing_du", row.spacing_du);
    luax::set_integer(L, "contacts", row.contacts);
    luax::set_integer(L, "poses", row.poses.size());
    luax::set_integer(L, "refusals", row.refusals.size());
    set_number(L, "max_deviation", row.max_deviation_mm);
    set_bool(L, "reversed", row.reversed);
    // The largest lead the tilt loop needed on the row (0: the paper's
    // initial axis was clear everywhere), degrees.
    double lead = 0;
    for (const DrumFinishPose& dp : row.poses) {
      const double raised = std::abs(dp.lead_rad - rq.tilt.lead0_rad);
      lead = std::max(lead, raised);
      if (raised > 1e-12) ++tilted;
    }
    set_number(L, "lead_raised", rad_to_deg(lead));
    lead_raised = std::max(lead_raised, lead);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "rows");
  set_number(L, "lead_raised", rad_to_deg(lead_raised));
  luax::set_integer(L, "inserted_rows", r.inserted_rows);
  luax::set_integer(L, "uncovered_gaps", r.uncovered_gaps);
  luax::set_integer(L, "turn_splits", r.turn_splits);
  luax::set_integer(L, "gouge_splits", r.gouge_splits);
  luax::set_integer(L, "tilted_poses", tilted);
  luax::set_integer(L, "contacts", contacts);
  set_number(L, "width_min", r.rows.empty() ? 0 : wmin);
  set_number(L, "width_max", wmax);
  set_refusal_reasons(L, r);
  lua_createtable(L, 0, 4);
  set_number(L, "trim", r.trim_seconds);
  set_number(L, "rows", r.rows_seconds);
  set_number(L, "tilt", r.tilt_seconds);
  set_number(L, "links", r.link_seconds);
  lua_setfield(L, -2, "seconds");
  return 1;
}

// plan:row(i) -> {u, v = {...}, deviation = {...}}: the contact parameters
// of row i and the measured chord deviation of each segment (Fig. 13).
int w_drum_plan_row(lua_State* L) {
  const LuaDrumPlan& p = check_drum_plan(L);
  const lua_Integer i = luaL_checkinteger(L, 2);
  const auto& rows = p.result->rows;
  if (i < 1 || i > static_cast<lua_Integer>(rows.size()))
    luax::error(L, "DrumFinishPlan:row: row " + std::to_string(i) + " does not exist; rows are 1.." +
                       std::to_string(rows.size()));
  const DrumFinishRow& row = rows[static_cast<size_t>(i - 1)];
  lua_createtable(L, 0, 3);
  set_number(L, "u", row.u);
  luax::set_numbers(L, "v", row.v);
  luax::set_numbers(L, "deviation", row.deviation_mm);
  return 1;
}

// plan:moves() -> {{kind = "feed"|"rapid", tip =, axis =, row =}, ...}: the
// toolpath in cutting order, rows linked by their (proved) retract and
// approach moves, in the form bliskrun.post.write takes. A refused link ends
// the list there: nothing unproven is implied.
int w_drum_plan_moves(lua_State* L) {
  push_finish_moves(L, drum_finish_moves(*check_drum_plan(L).result));
  return 1;
}

int w_drum_plan_write_apt(lua_State* L) {
  const LuaDrumPlan& p = check_drum_plan(L);
  const std::string path = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  return luax::guarded(L, [&] {
    write_drum_finish_apt(path, *p.result, p.request);
    return 0;
  });
}

// plan:trimmed() -> the trimmed flank (u' = 0 on the hub curve, 1 on the casing).
int w_drum_plan_trimmed(lua_State* L) {
  push_surface(L, check_drum_plan(L).result->trimmed);
  return 1;
}

int w_drum_plan_simulate(lua_State* L) {
  const LuaDrumPlan& p = check_drum_plan(L);
  return luax::guarded(L, [&] {
    const luax::Options o(
        L, 2, "DrumFinishPlan:simulate",
        {Field{"samples_u", Kind::Integer, false, 2, 5000, "design samples along the span (default 200)", {}},
         Field{"samples_v", Kind::Integer, false, 2, 20000, "design samples along the chord (default 1000)", {}},
         Field{"search_above", Kind::Number, false, 1e-4, 10.0, "material tracked up to this above the design, mm (default 0.1)", {}},
         Field{"search_below", Kind::Number, false, 1e-4, 10.0, "gouges measured down to this, mm (default 0.1)", {}},
         Field{"sweep_step", Kind::Number, false, 1e-4, 10.0, "largest cutter-point motion between evaluated positions, mm (default 0.05)", {}},
         Field{"threads", Kind::Integer, false, 1, 256, "worker threads (default: the run's --threads)", {}}});
    const DrumFinishResult& r = *p.result;
    UndercutOptions so;
    so.samples_u = static_cast<int>(o.integer("samples_u", 200));
    so.samples_v = static_cast<int>(o.integer("samples_v", 1000));
    so.search_above_mm = o.number("search_above", so.search_above_mm);
    so.search_below_mm = o.number("search_below", so.search_below_mm);
    so.sweep_step_mm = o.number("sweep_step", so.sweep_step_mm);
    so.threads = threads_option(o, L);
    const auto t0 = std::chrono::steady_clock::now();
    DrumFinishSimulation sim = simulate_drum_finish(r, p.request, so, context(L).progress);
    UndercutResult& u = sim.undercut;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    lua_createtable(L, 0, 14);
    set_undercut_stats(L, u);
    // The move that cut the deepest overcut (1-based, as in plan:moves()).
    if (sim.overcut_move >= 0) {
      luax::set_integer(L, "overcut_move", sim.overcut_move + 1);
      set_string(L, "overcut_motion", sim.overcut_motion);
      luax::set_integer(L, "overcut_row", sim.overcut_row + 1);
    }
    set_undercut_counts(L, u);
    set_number(L, "u0", r.first_row_u);
    // Sample rows below this one (0-based) lie in the hub strip: overcut only.
    luax::set_integer(L, "first_machined_row", sim.first_machined_row);
    set_number(L, "seconds", seconds);
    char head[120];
    std::snprintf(head, sizeof head, "%d x %d samples of u' in [0, 1], machined from %.3f; ", u.samples_u, u.samples_v,
                  r.first_row_u);
    // 3 significant digits, no "-0.00": a footer reads at a glance.
    const auto um = [](double mm) { return significant_text(1e3 * mm) + " µm"; };
    const std::string footer = head + ("undercut max " + um(u.undercut_max_mm) + ", mean " + um(u.undercut_mean_mm) +
                                       ", median " + um(u.undercut_median_mm) + ", std " + um(u.undercut_std_mm) +
                                       "; overcut " + um(u.overcut_mm) + " (every move); untouched " +
                                       std::to_string(u.untouched));
    push_undercut_map(L, u.samples_u, u.samples_v, std::move(u.residual_mm), footer);
    lua_setfield(L, -2, "map");
    return 1;
  });
}

// The default half range of a map written without scale_um: the largest
// |value| rounded up to 1, 2, 3 or 5 times a power of ten, so the colour bar's
// labels read as round numbers (a run's maps share one scale: pass scale_um).
double undercut_map_round_scale(double m) {
  if (!(m > 0) || !std::isfinite(m)) return 1;
  const double p = std::pow(10.0, std::floor(std::log10(m)));
  for (double f : {1.0, 2.0, 3.0, 5.0, 10.0})
    if (m <= f * p * (1 + 1e-12)) return f * p;
  return 10 * p;
}

// map:write_svg / map:write_png (path [, {title=, scale_um=, width=, height=}]):
// values in µm (the map holds mm) on a symmetric scale +-scale_um.
int write_undercut_map(lua_State* L, const char* where, bool png) {
  const LuaUndercutMap& m = luax::check<LuaUndercutMap>(L, 1);
  const std::string path = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  return luax::guarded(L, [&] {
    const luax::Options o(
        L, 3, where,
        {Field{"title", Kind::String, false, std::nullopt, std::nullopt, "picture title", {}},
         Field{"scale_um", Kind::Number, false, 1e-3, 1e5,
               "colour scale +-, µm: the same on every map of a run so they compare (default: the largest |value| "
               "rounded up to 1, 2, 3 or 5 x 10^k)", {}},
         Field{"width", Kind::Integer, false, 50, 10000, "plot width, px; default 800", {}},
         Field{"height", Kind::Integer, false, 50, 10000, "plot height, px; default 320", {}}});
    HeatMap um = m.map;
    for (double& x : um.values) x *= 1e3;  // NaN and +inf stay what they are
    HeatMapOptions h;
    h.title = o.string("title", "Material left (µm): red above the design, blue below");
    h.value_label = "µm";
    h.footer = m.footer;
    if (!m.u_label.empty()) h.u_label = m.u_label;
    if (!m.v_label.empty()) h.v_label = m.v_label;
    h.fraction_ticks = m.fraction_ticks;
    h.labels = m.labels;
    h.scale_max = o.has("scale_um") ? o.number("scale_um", 0) : undercut_map_round_scale(heat_map_scale(um, h));
    h.plot_width_px = static_cast<int>(o.integer("width", h.plot_width_px));
    h.plot_height_px = static_cast<int>(o.integer("height", h.plot_height_px));
    if (png)
      write_heat_map_png(um, path, h);
    else
      write_heat_map_svg(um, path, h);
    lua_pushstring(L, path.c_str());
    return 1;
  });
}
int w_drum_map_write_svg(lua_State* L) { return write_undercut_map(L, "UndercutMap:write_svg", false); }
int w_drum_map_write_png(lua_State* L) { return write_undercut_map(L, "UndercutMap:write_png", true); }

int w_drum_plan_tostring(lua_State* L) {
  const LuaDrumPlan& p = check_drum_plan(L);
  lua_pushfstring(L, "bliskrun.DrumFinishPlan(%s%s%d rows, %d poses, %d refusals)", p.name.c_str(),
                  p.name.empty() ? "" : ": ", static_cast<int>(p.result->rows.size()), p.result->total_poses,
                  p.result->total_refusals);
  return 1;
}

}  // namespace

void open_planning(lua_State* L) {
  static const luaL_Reg plan_methods[] = {{"report", w_drum_plan_report},       {"row", w_drum_plan_row},
                                          {"moves", w_drum_plan_moves},
                                          {"write_apt", w_drum_plan_write_apt}, {"trimmed", w_drum_plan_trimmed},
                                          {"simulate", w_drum_plan_simulate},   {nullptr, nullptr}};
  luax::register_type(L, luax::TypeName<LuaDrumPlan>::name, plan_methods, &luax::gc_value<LuaDrumPlan>,
                      w_drum_plan_tostring);
  static const luaL_Reg map_methods[] = {
      {"write_svg", w_drum_map_write_svg}, {"write_png", w_drum_map_write_png}, {nullptr, nullptr}};
  luax::register_type<LuaUndercutMap>(L, map_methods);
  static const luaL_Reg functions[] = {
      {"drum_finish", w_drum_finish}, {"drum_finish_all", w_drum_finish_all}, {"trim_flank", w_trim_flank},
      {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
