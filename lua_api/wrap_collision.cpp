// bliskrun.collision_world{...} and its queries: check (one pose),
// check_motion (swept, between two poses) and tilt (tilt until clear along a
// path of contacts). Lengths in mm, angles in degrees. See docs/lua_api.md.
#include <cmath>
#include <limits>
#include <memory>

#include "core/collision/tilt.h"
#include "core/common/parallel.h"
#include "lua_api/lua_tool.h"
#include "lua_api/machine_host.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_collision.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {
namespace {

using luax::Field;
using luax::Kind;

// ---- reading ---------------------------------------------------------------

// {vertices = {{x,y,z}, ...}, triangles = {{i,j,k}, ...}} with 1-based indices.
TriangleMesh check_mesh(lua_State* L, int idx, const std::string& what) {
  idx = lua_absindex(L, idx);
  const luax::Options o(L, idx, what,
                        {Field{"vertices", Kind::Table, true, std::nullopt, std::nullopt, "list of {x, y, z}, mm", {}},
                         Field{"triangles", Kind::Table, true, std::nullopt, std::nullopt,
                               "list of {i, j, k}, 1-based vertex indices", {}}});
  TriangleMesh mesh;
  o.push_raw("vertices");
  const lua_Integer nv = luaL_len(L, -1);
  for (lua_Integer i = 1; i <= nv; ++i) {
    lua_rawgeti(L, -1, i);
    mesh.vertices.push_back(luax::check_vec3(L, -1, (what + ".vertices[" + std::to_string(i) + "]").c_str()));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  o.push_raw("triangles");
  const lua_Integer nt = luaL_len(L, -1);
  for (lua_Integer i = 1; i <= nt; ++i) {
    lua_rawgeti(L, -1, i);
    const std::string name = what + ".triangles[" + std::to_string(i) + "]";
    if (!lua_istable(L, -1)) luax::error(L, name + ": expected {i, j, k}");
    Eigen::Vector3i t;
    for (int k = 0; k < 3; ++k) {
      lua_rawgeti(L, -1, k + 1);
      int is_int = 0;
      const lua_Integer v = lua_tointegerx(L, -1, &is_int);
      if (!is_int) luax::error(L, name + ": expected three integer vertex indices");
      if (v < 1 || v > nv) {
        luax::error(L, name + ": vertex index " + std::to_string(v) + " outside 1.." + std::to_string(nv));
      }
      t[k] = static_cast<int>(v - 1);
      lua_pop(L, 1);
    }
    mesh.triangles.push_back(t);
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return mesh;
}

ToolPose check_pose(lua_State* L, int idx, const char* what) {
  const luax::Options o(L, idx, what,
                        {Field{"tip", Kind::Vec3, true, std::nullopt, std::nullopt, "tool reference point, mm", {}},
                         Field{"axis", Kind::Vec3, true, std::nullopt, std::nullopt,
                               "tool axis towards the shank (normalised)", {}}});
  return ToolPose{o.vec3("tip", Vec3::Zero()), o.vec3("axis", Vec3::UnitZ())};
}

Field clearance_field() {
  return Field{"clearance", Kind::Table, false, std::nullopt, std::nullopt,
               "{cutter=, shank=, holder=} required clearances, mm (default 0)", {}};
}

Clearances check_clearances(lua_State* L, const luax::Options& o, const std::string& what) {
  if (!o.has("clearance")) return {};
  o.push_raw("clearance");
  const luax::Options c(L, lua_gettop(L), what + ".clearance",
                        {Field{"cutter", Kind::Number, false, 0.0, std::nullopt, "mm", {}},
                         Field{"shank", Kind::Number, false, 0.0, std::nullopt, "mm", {}},
                         Field{"holder", Kind::Number, false, 0.0, std::nullopt, "mm", {}}});
  Clearances out{c.number("cutter", 0), c.number("shank", 0), c.number("holder", 0)};
  lua_pop(L, 1);
  return out;
}


}  // namespace

std::vector<Field> tilt_option_fields() {
  return {clearance_field(),
          Field{"lead", Kind::Number, false, -90.0, 90.0, "initial lead/pitch λ, degrees (default 0)", {}},
          Field{"tilt", Kind::Number, false, -180.0, 180.0, "initial tilt w, degrees (default 0)", {}},
          Field{"lead_step", Kind::Number, false, 1e-6, 90.0, "λ step, degrees (default 0.5)", {}},
          Field{"lead_max", Kind::Number, false, -90.0, 90.0, "largest λ tried, degrees (default 45)", {}},
          Field{"allow_tilt", Kind::Boolean, false, std::nullopt, std::nullopt, "also vary w (default false)", {}},
          Field{"tilt_step", Kind::Number, false, 1e-6, 90.0, "w step, degrees (default 1)", {}},
          Field{"tilt_range", Kind::Number, false, 0.0, 180.0, "|w - w0| at most, degrees (default 10)", {}},
          Field{"motion_tol", Kind::Number, false, 1e-6, std::nullopt, "swept check tolerance, mm (default 0.001)", {}},
          Field{"axis_limit", Kind::Table, false, std::nullopt, std::nullopt,
                "{name=, rotary_axis=, reference=, min=, max=} degrees; default none", {}},
          Field{"machine", Kind::Any, false, std::nullopt, std::nullopt,
                "a bliskrun.machine: refuse axes no rotary position within its travel gives", {}}};
}

AxisLimit read_axis_limit(lua_State* L, int idx, const std::string& what) {
  const luax::Options a(L, idx, what,
                        {Field{"name", Kind::String, false, std::nullopt, std::nullopt, "e.g. \"C\"", {}},
                         Field{"rotary_axis", Kind::Vec3, false, std::nullopt, std::nullopt,
                               "direction of the rotary axis (default {0,0,1})", {}},
                         Field{"reference", Kind::Vec3, false, std::nullopt, std::nullopt,
                               "zero direction, perpendicular to it (default {0,1,0})", {}},
                         Field{"min", Kind::Number, true, -180.0, 180.0, "degrees", {}},
                         Field{"max", Kind::Number, true, -180.0, 180.0, "degrees", {}}});
  RotaryAxisLimit limit;
  limit.name = a.string("name", "C");
  limit.rotary_axis = a.vec3("rotary_axis", Vec3::UnitZ());
  limit.reference = a.vec3("reference", Vec3::UnitY());
  limit.min_rad = deg_to_rad(a.number("min", -30));
  limit.max_rad = deg_to_rad(a.number("max", 30));
  return make_axis_limit(limit);
}

std::shared_ptr<const CollisionWorld> world_option(lua_State* L, const luax::Options& o, const std::string& what,
                                                   const std::string& hint) {
  o.push_raw("world");
  const LuaWorld* w = luax::test<LuaWorld>(L, -1);
  if (!w) luax::error(L, what + ": option 'world': expected a bliskrun.CollisionWorld" + hint);
  std::shared_ptr<const CollisionWorld> world = w->world;
  lua_pop(L, 1);
  return world;
}

TiltSettings read_tilt_settings(lua_State* L, const luax::Options& o, const std::string& what_name) {
  const char* what = what_name.c_str();
  TiltSettings s;
  s.clearances = check_clearances(L, o, what);
  s.lead0_rad = deg_to_rad(o.number("lead", 0));
  s.tilt0_rad = deg_to_rad(o.number("tilt", 0));
  s.lead_step_rad = deg_to_rad(o.number("lead_step", 0.5));
  s.lead_max_rad = deg_to_rad(o.number("lead_max", 45));
  s.allow_tilt = o.boolean("allow_tilt", false);
  s.tilt_step_rad = deg_to_rad(o.number("tilt_step", 1));
  s.tilt_range_rad = deg_to_rad(o.number("tilt_range", 10));
  s.motion_tol_mm = o.number("motion_tol", 1e-3);
  if (o.has("axis_limit")) {
    o.push_raw("axis_limit");
    s.axis_limit = read_axis_limit(L, lua_gettop(L), std::string(what) + ".axis_limit");
    lua_pop(L, 1);
  }
  if (o.has("machine")) {
    // The machine's own rotary travel limits the axis (SPEC §5: the limits
    // a machine defines are what the interference loop uses), on top of
    // any explicit axis_limit.
    o.push_raw("machine");
    const MachineValue* m = test_machine(L, lua_gettop(L));
    if (!m) luax::error(L, std::string(what) + ": option 'machine': expected a bliskrun.machine");
    auto kin = std::make_shared<const Kinematics>(m->definition, 0.0);
    const std::string name = m->definition.name;
    AxisLimit explicit_limit = s.axis_limit;
    s.axis_limit = [kin, name, explicit_limit](const Vec3& axis) -> std::string {
      if (explicit_limit) {
        std::string why = explicit_limit(axis);
        if (!why.empty()) return why;
      }
      return kin->reachable(axis) ? std::string()
                                  : "machine '" + name + "': no rotary position within travel gives this axis";
    };
    lua_pop(L, 1);
  }
  return s;
}

namespace {

// ---- pushing ---------------------------------------------------------------

using luax::set_bool;
using luax::set_number;
using luax::set_string;
using luax::set_vec3;

void push_pose_check(lua_State* L, const CollisionWorld& world, const PoseCheck& c) {
  lua_createtable(L, 0, 4);
  set_bool(L, "clear", c.clear);
  set_number(L, "min_margin", c.min_margin_mm);
  lua_createtable(L, static_cast<int>(c.parts.size()), 0);
  for (size_t i = 0; i < c.parts.size(); ++i) {
    const PartClearance& p = c.parts[i];
    lua_createtable(L, 0, 6);
    set_string(L, "part", to_string(p.part));
    set_number(L, "distance", p.distance_mm);
    set_bool(L, "resolved", p.resolved);
    set_bool(L, "collides", p.collides);
    if (p.object >= 0) {
      set_string(L, "object", world.name(p.object));
      set_vec3(L, "on_tool", p.on_tool);
      set_vec3(L, "on_object", p.on_object);
    }
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "parts");
  if (c.worst >= 0) set_string(L, "worst", to_string(c.parts[c.worst].part));
}

// ---- functions -------------------------------------------------------------

// One check surface as read from its entry: a mesh (bliskrun.Mesh, or
// {vertices=, triangles=}), or a surface to tessellate at chord_tol (on a
// worker, with the others).
struct MeshEntry {
  TriangleMesh mesh;
  std::shared_ptr<const Surface> surface;
  double chord_tol = 0;
};

MeshEntry check_surface_entry(lua_State* L, const luax::Options& s, const std::string& what) {
  if (s.has("mesh") == s.has("surface")) luax::error(L, what + ": give exactly one of 'mesh' and 'surface'");
  MeshEntry out;
  if (s.has("surface")) {
    if (!s.has("chord_tol")) luax::error(L, what + ": 'surface' needs 'chord_tol' (mm)");
    s.push_raw("surface");
    out.surface = luax::check<SurfaceHandle>(L, -1).surface;
    lua_pop(L, 1);
    out.chord_tol = s.number("chord_tol", 0);
    return out;
  }
  s.push_raw("mesh");
  if (const MeshHandle* handle = luax::test<MeshHandle>(L, -1)) {
    out.mesh = *handle->mesh;
  } else {
    out.mesh = check_mesh(L, -1, what + ".mesh");
  }
  lua_pop(L, 1);
  return out;
}

int w_collision_world(lua_State* L) {
  return luax::guarded(L, [&] {
    const luax::Options o(L, 1, "bliskrun.collision_world",
                          {Field{"surfaces", Kind::Table, true, std::nullopt, std::nullopt,
                                 "list of {name=, mesh=}, {name=, surface=, chord_tol=} or {name=, revolution=}", {}}});
    auto world = std::make_shared<CollisionWorld>();
    // Read every entry first (Lua is asked on this thread only), then
    // tessellate and build the meshes' hierarchies on the run's threads, and
    // add them in the order given (a world's objects keep their indices).
    struct Pending {
      std::string name;
      CheckSurfaceOptions options;
      std::shared_ptr<const RevolutionDistance> revolution;
      MeshEntry mesh;
      CollisionWorld::PreparedSurface prepared;
    };
    std::vector<Pending> pending;
    o.push_raw("surfaces");
    const lua_Integer n = luaL_len(L, -1);
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, -1, i);
      const std::string what = "bliskrun.collision_world surfaces[" + std::to_string(i) + "]";
      const luax::Options s(
          L, lua_gettop(L), what,
          {Field{"name", Kind::String, true, std::nullopt, std::nullopt, "name used in reports, e.g. \"blade k+1\"", {}},
           Field{"mesh", Kind::Any, false, std::nullopt, std::nullopt,
                 "bliskrun.Mesh or {vertices={{x,y,z},...}, triangles={{i,j,k},...}} (1-based)", {}},
           Field{"surface", Kind::Any, false, std::nullopt, std::nullopt, "bliskrun.Surface to tessellate", {}},
           Field{"revolution", Kind::Any, false, std::nullopt, std::nullopt,
                 "a surface of revolution measured analytically (no mesh): each tool part by spheres "
                 "covering it, against the meridian polyline within chord_tol (default 0.001)", {}},
           Field{"chord_tol", Kind::Number, false, 1e-6, std::nullopt, "tessellation tolerance, mm", {}},
           Field{"margin", Kind::Number, false, 0.0, 100.0,
                 "extra clearance against this surface, mm (default 0); give a coarse mesh its chord_tol", {}},
           Field{"parts", Kind::Table, false, std::nullopt, std::nullopt,
                 "tool parts checked against it, e.g. {\"shank\", \"holder\"} for the blade being machined "
                 "(default all)", {}},
           Field{"stock", Kind::Boolean, false, std::nullopt, std::nullopt,
                 "stock still on a face, an obstacle for `parts` only (the cutter cuts it): the cutter is never "
                 "checked against it, not even by the traverse checks of links (default false)", {}}});
      PartMask mask;
      if (s.has("parts")) {
        s.push_raw("parts");
        mask = {false, false, false};
        const lua_Integer np = luaL_len(L, -1);
        for (lua_Integer k = 1; k <= np; ++k) {
          lua_rawgeti(L, -1, k);
          const char* part = lua_tostring(L, -1);
          const std::string p = part ? part : "";
          if (p == "cutter") mask.cutter = true;
          else if (p == "shank") mask.shank = true;
          else if (p == "holder") mask.holder = true;
          else luax::error(L, what + ".parts[" + std::to_string(k) + "]: expected \"cutter\", \"shank\" or \"holder\"");
          lua_pop(L, 1);
        }
        lua_pop(L, 1);
        if (np < 1) luax::error(L, what + ".parts: expected at least one of \"cutter\", \"shank\", \"holder\"");
      }
      CheckSurfaceOptions options;
      options.parts = mask;
      options.margin_mm = s.number("margin", 0.0);
      options.stock = s.boolean("stock", false);
      if (options.stock && mask.cutter)
        luax::error(L, what + ": a stock surface is an obstacle for the shank and holder, not the cutter (parts)");
      if (s.has("revolution")) {
        if (s.has("mesh") || s.has("surface"))
          luax::error(L, what + ": give one of 'mesh', 'surface' and 'revolution'");
        s.push_raw("revolution");
        const std::shared_ptr<const Surface> surface = luax::check<SurfaceHandle>(L, -1).surface;
        lua_pop(L, 1);
        const auto* rev = dynamic_cast<const SurfaceOfRevolution*>(surface.get());
        if (!rev) luax::error(L, what + ".revolution: expected a surface of revolution (impeller:hub(), "
                                        "bliskrun.surface_of_revolution, bliskrun.offset_revolution)");
        pending.push_back({s.string("name", ""), options,
                           std::make_shared<RevolutionDistance>(*rev, s.number("chord_tol", 1e-3)), {}, {}});
      } else {
        pending.push_back({s.string("name", ""), options, nullptr, check_surface_entry(L, s, what), {}});
      }
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    Progress& progress = context(L).progress;
    run_parallel(pending.size(), context(L).options.threads, progress, "check surfaces", [&](size_t k, Progress& pg) {
      Pending& p = pending[k];
      if (p.revolution) return;
      if (p.mesh.surface) p.mesh.mesh = tessellate(*p.mesh.surface, p.mesh.chord_tol, 0, 1, 0, 1, pg);
      p.prepared = CollisionWorld::prepare(p.name, p.mesh.mesh, p.options);
      p.mesh.mesh = TriangleMesh();  // the hierarchy holds what it needs
    });
    for (Pending& p : pending) {
      if (p.revolution) world->add(p.name, p.revolution, p.options);
      else world->add(std::move(p.prepared));
    }
    luax::push_new(L, LuaWorld{std::move(world)});
    return 1;
  });
}

int w_world_names(lua_State* L) {
  return luax::guarded(L, [&] {
    const CollisionWorld& w = *luax::check<LuaWorld>(L, 1).world;
    lua_createtable(L, w.size(), 0);
    for (int i = 0; i < w.size(); ++i) {
      luax::push(L, w.name(i));
      lua_rawseti(L, -2, i + 1);
    }
    return 1;
  });
}

int w_world_check(lua_State* L) {
  return luax::guarded(L, [&] {
    const CollisionWorld& w = *luax::check<LuaWorld>(L, 1).world;
    LuaTool& tool = luax::check<LuaTool>(L, 2);
    const ToolPose pose = check_pose(L, 3, "CollisionWorld:check pose");
    const luax::Options o(L, 4, "CollisionWorld:check",
                          {clearance_field(),
                           Field{"horizon", Kind::Number, false, 0.0, std::nullopt,
                                 "resolve distances up to clearance + horizon, mm (default: all)", {}}});
    const Clearances c = check_clearances(L, o, "CollisionWorld:check");
    const double horizon = o.number("horizon", std::numeric_limits<double>::infinity());
    push_pose_check(L, w, w.check(tool.body(), pose, c, horizon));
    return 1;
  });
}

int w_world_check_motion(lua_State* L) {
  return luax::guarded(L, [&] {
    const CollisionWorld& w = *luax::check<LuaWorld>(L, 1).world;
    LuaTool& tool = luax::check<LuaTool>(L, 2);
    const ToolPose from = check_pose(L, 3, "CollisionWorld:check_motion from");
    const ToolPose to = check_pose(L, 4, "CollisionWorld:check_motion to");
    const luax::Options o(L, 5, "CollisionWorld:check_motion",
                          {clearance_field(),
                           Field{"tol", Kind::Number, false, 1e-6, std::nullopt,
                                 "clearance may dip by at most this between samples, mm (default 0.001)", {}}});
    const Clearances c = check_clearances(L, o, "CollisionWorld:check_motion");
    const MotionCheck m = w.check_motion(tool.body(), from, to, c, o.number("tol", 1e-3));
    lua_createtable(L, 0, 5);
    set_bool(L, "clear", m.clear);
    set_bool(L, "undecided", m.undecided);
    luax::set_integer(L, "samples", m.samples);
    set_number(L, "min_margin", m.min_margin_mm);
    if (!m.clear) {
      set_number(L, "t", m.t);
      push_pose_check(L, w, m.at);
      lua_setfield(L, -2, "at");
    }
    return 1;
  });
}

// The least margin over a motion (a lower bound within tol): for reports,
// where check_motion's min_margin is only the smallest margin its proof
// sampled.
int w_world_motion_min_margin(lua_State* L) {
  return luax::guarded(L, [&] {
    const CollisionWorld& w = *luax::check<LuaWorld>(L, 1).world;
    LuaTool& tool = luax::check<LuaTool>(L, 2);
    const ToolPose from = check_pose(L, 3, "CollisionWorld:motion_min_margin from");
    const ToolPose to = check_pose(L, 4, "CollisionWorld:motion_min_margin to");
    const luax::Options o(L, 5, "CollisionWorld:motion_min_margin",
                          {clearance_field(),
                           Field{"tol", Kind::Number, false, 1e-6, std::nullopt,
                                 "the bound's tolerance, mm (default 0.01)", {}}});
    const Clearances c = check_clearances(L, o, "CollisionWorld:motion_min_margin");
    lua_pushnumber(L, w.motion_min_margin(tool.body(), from, to, c, o.number("tol", 0.01)));
    return 1;
  });
}

int w_world_tilt(lua_State* L) {
  return luax::guarded(L, [&] {
    const CollisionWorld& w = *luax::check<LuaWorld>(L, 1).world;
    LuaTool& tool = luax::check<LuaTool>(L, 2);
    luaL_checktype(L, 3, LUA_TTABLE);
    std::vector<ContactFrame> contacts;
    const lua_Integer n = luaL_len(L, 3);
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, 3, i);
      const luax::Options c(L, lua_gettop(L), "CollisionWorld:tilt contacts[" + std::to_string(i) + "]",
                            {Field{"point", Kind::Vec3, true, std::nullopt, std::nullopt, "contact point, mm", {}},
                             Field{"tangent", Kind::Vec3, true, std::nullopt, std::nullopt, "path direction", {}},
                             Field{"normal", Kind::Vec3, true, std::nullopt, std::nullopt,
                                   "surface normal out of the material", {}}});
      contacts.push_back(ContactFrame{c.vec3("point", Vec3::Zero()), c.vec3("tangent", Vec3::UnitX()),
                                      c.vec3("normal", Vec3::UnitZ())});
      lua_pop(L, 1);
    }
    const char* what = "CollisionWorld:tilt";
    const luax::Options o(L, 4, what, tilt_option_fields());
    const TiltSettings s = read_tilt_settings(L, o, what);
    const TiltRun run = tilt_path(w, tool.body(), contacts, s, context(L).progress);
    lua_createtable(L, 0, 2);
    lua_createtable(L, static_cast<int>(run.poses.size()), 0);
    for (size_t i = 0; i < run.poses.size(); ++i) {
      const TiltAccepted& p = run.poses[i];
      lua_createtable(L, 0, 5);
      luax::set_integer(L, "index", p.index + 1);
      set_vec3(L, "tip", p.pose.tip);
      set_vec3(L, "axis", p.pose.axis);
      set_number(L, "lead", rad_to_deg(p.lead_rad));
      set_number(L, "tilt", rad_to_deg(p.tilt_rad));
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "poses");
    lua_createtable(L, static_cast<int>(run.refusals.size()), 0);
    for (size_t i = 0; i < run.refusals.size(); ++i) {
      const TiltRefusal& r = run.refusals[i];
      lua_createtable(L, 0, 3);
      luax::set_integer(L, "index", r.index + 1);
      set_vec3(L, "contact", r.contact);
      set_string(L, "reason", r.reason);
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "refusals");
    return 1;
  });
}

const luaL_Reg kWorldMethods[] = {{"names", w_world_names},
                                  {"check", w_world_check},
                                  {"check_motion", w_world_check_motion},
                                  {"motion_min_margin", w_world_motion_min_margin},
                                  {"tilt", w_world_tilt},
                                  {nullptr, nullptr}};

const luaL_Reg kCollisionFunctions[] = {{"collision_world", w_collision_world}, {nullptr, nullptr}};

}  // namespace

void open_collision(lua_State* L) {
  luax::register_type<LuaWorld>(L, kWorldMethods);
  luaL_setfuncs(L, kCollisionFunctions, 0);
}

}  // namespace bliskrun::lua_api
