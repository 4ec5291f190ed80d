// Belt-grinding robot cells (core/machine/robot*.h): bliskrun.robot_cell
// loads a cell file from scripts/machines (arm, joints, home, belt stations),
// cell:plan_grinding presents the blade held in the gripper to a station
// along belt paths, plan:write_program posts it with a robot post
// (scripts/posts/abb_rapid.lua, kuka_krl.lua), reads it back and replays it
// through the arm's kinematics before anything is written.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/geometry/mass_properties.h"
#include "core/machine/robot_cycle_time.h"
#include "core/machine/robot_program.h"
#include "core/machine/wheel_clearance.h"
#include "lua_api/luax.h"
#include "lua_api/machine_host.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

struct LuaRobotCell {
  RobotCell cell;
  std::string source;
};

struct LuaBladeBody {
  std::shared_ptr<const BladeBody> body;
};

struct LuaRobotPlan {
  std::shared_ptr<const RobotCell> cell;
  std::string station;
  RobotGrindingPlan plan;
  double feed_mm_s = 0;
};

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::LuaRobotCell> {
  static constexpr const char* name = "bliskrun.RobotCell";
};
template <>
struct TypeName<lua_api::LuaBladeBody> {
  static constexpr const char* name = "bliskrun.BladeBody";
};
template <>
struct TypeName<lua_api::LuaRobotPlan> {
  static constexpr const char* name = "bliskrun.RobotGrindingPlan";
};
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;

using luax::number_field;

Vec3 vec3_field(lua_State* L, int idx, const char* key, const std::string& where) {
  lua_getfield(L, idx, key);
  if (!lua_istable(L, -1)) luax::error(L, where + "." + key + ": expected {x, y, z}");
  const Vec3 v = luax::check_vec3(L, -1, (where + "." + key).c_str());
  lua_pop(L, 1);
  return v;
}

// A frame given as {origin = {x,y,z}, x = {..}, z = {..}} (y = z × x); x and z
// must be at right angles.
Frame frame_field(lua_State* L, int idx, const std::string& where) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) luax::error(L, where + ": expected {origin = {x,y,z}, x = {..}, z = {..}}");
  const Vec3 o = vec3_field(L, idx, "origin", where), x = vec3_field(L, idx, "x", where),
             z = vec3_field(L, idx, "z", where);
  if (x.norm() < 1e-12 || z.norm() < 1e-12 || std::abs(x.normalized().dot(z.normalized())) > 1e-6)
    luax::error(L, where + ": expected x and z of non-zero length at right angles");
  Frame f = Frame::Identity();
  f.linear().col(0) = x.normalized();
  f.linear().col(2) = z.normalized();
  f.linear().col(1) = f.linear().col(2).cross(f.linear().col(0));
  f.translation() = o;
  return f;
}

void push_frame(lua_State* L, const Frame& f) {
  lua_createtable(L, 0, 4);
  luax::set_vec3(L, "origin", f.translation());
  luax::set_vec3(L, "x", f.linear().col(0));
  luax::set_vec3(L, "y", f.linear().col(1));
  luax::set_vec3(L, "z", f.linear().col(2));
}

JointAngles joints_arg(lua_State* L, int idx, const char* name) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx) || luaL_len(L, idx) != 6)
    luax::error(L, std::string(name) + ": expected 6 joint values in degrees");
  JointAngles q;
  for (int i = 0; i < 6; ++i) {
    lua_rawgeti(L, idx, i + 1);
    if (!lua_isnumber(L, -1)) luax::error(L, std::string(name) + "[" + std::to_string(i + 1) + "]: expected a number");
    q[i] = deg_to_rad(lua_tonumber(L, -1));
    lua_pop(L, 1);
  }
  return q;
}

void push_joints(lua_State* L, const JointAngles& q) {
  lua_createtable(L, 6, 0);
  for (int i = 0; i < 6; ++i) {
    lua_pushnumber(L, rad_to_deg(q[i]));
    lua_rawseti(L, -2, i + 1);
  }
}

// robot_cell{...} inside a cell file: validates and returns the cell.
int l_robot_cell(lua_State* L) {
  const luax::Options o(
      L, 1, "robot_cell",
      {Field{"name", Kind::String, true, std::nullopt, std::nullopt, "the cell's name", {}},
       Field{"controller", Kind::String, false, std::nullopt, std::nullopt, "\"abb\" or \"kuka\"", {"abb", "kuka"}},
       Field{"opw", Kind::Table, true, std::nullopt, std::nullopt,
             "arm lengths {a1, a2, b, c1, c2, c3, c4}, mm (core/machine/robot.h)", {}},
       Field{"joints", Kind::Table, true, std::nullopt, std::nullopt,
             "6 x {zero = deg, sign = 1|-1, min = deg, max = deg, speed = deg/s}", {}},
       Field{"home", Kind::Table, true, std::nullopt, std::nullopt, "6 joint values, deg", {}},
       Field{"stations", Kind::Table, true, std::nullopt, std::nullopt,
             "name = {contact = {x,y,z}, normal = {..}, axis = {..}, wheel = {radius, width}, belt, speed}", {}}});
  LuaRobotCell c;
  c.cell.name = o.string("name", "");
  o.push_raw("opw");
  {
    const luax::Options g(L, lua_gettop(L), "robot_cell: opw",
                          {number_field("a1", "mm"), number_field("a2", "mm"), number_field("b", "mm"), number_field("c1", "mm"), number_field("c2", "mm"),
                           number_field("c3", "mm"), number_field("c4", "mm")});
    OpwGeometry& a = c.cell.arm.geometry;
    a = {g.number("a1", 0), g.number("a2", 0), g.number("b", 0), g.number("c1", 0),
         g.number("c2", 0), g.number("c3", 0), g.number("c4", 0)};
  }
  lua_pop(L, 1);
  o.push_raw("joints");
  if (luaL_len(L, -1) != 6) luax::error(L, "robot_cell: joints: expected 6 joints");
  for (int i = 0; i < 6; ++i) {
    lua_rawgeti(L, -1, i + 1);
    const std::string what = "robot_cell: joints[" + std::to_string(i + 1) + "]";
    const luax::Options j(L, lua_gettop(L), what,
                          {number_field("zero", "OPW angle at the controller's zero, deg"),
                           Field{"sign", Kind::Integer, false, -1, 1, "1 or -1", {}},
                           number_field("min", "deg"), number_field("max", "deg"), number_field("speed", "deg/s", 1e-6)});
    if (!j.has("min") || !j.has("max") || !j.has("speed")) luax::error(L, what + ": expected min, max and speed");
    RobotJoint& rj = c.cell.arm.joints[i];
    rj.zero_rad = deg_to_rad(j.number("zero", 0));
    rj.sign = static_cast<int>(j.integer("sign", 1));
    rj.min_rad = deg_to_rad(j.number("min", 0));
    rj.max_rad = deg_to_rad(j.number("max", 0));
    rj.max_speed_rad_s = deg_to_rad(j.number("speed", 0));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  o.push_raw("home");
  c.cell.home = joints_arg(L, -1, "robot_cell: home");
  lua_pop(L, 1);
  o.push_raw("stations");
  const int st = lua_gettop(L);
  lua_pushnil(L);
  while (lua_next(L, st) != 0) {
    if (lua_type(L, -2) != LUA_TSTRING) luax::error(L, "robot_cell: stations: expected name = {...} entries");
    BeltStation s;
    s.name = lua_tostring(L, -2);
    const std::string what = "robot_cell: stations." + s.name;
    const luax::Options so(L, lua_gettop(L), what,
                           {Field{"contact", Kind::Vec3, true, std::nullopt, std::nullopt,
                                  "where the wheel touches the part, base frame, mm", {}},
                            Field{"normal", Kind::Vec3, true, std::nullopt, std::nullopt,
                                  "the wheel's outward normal there (towards the part)", {}},
                            Field{"axis", Kind::Vec3, true, std::nullopt, std::nullopt, "the wheel's axis", {}},
                            Field{"wheel", Kind::Table, true, std::nullopt, std::nullopt,
                                  "{radius = mm, width = mm, compliance = mm}", {}},
                            Field{"belt", Kind::String, false, std::nullopt, std::nullopt, "belt, e.g. \"ceramic, 120 grit\"", {}},
                            number_field("speed", "belt speed, m/s", 0),
                            number_field("belt_run", "the belt's strands behind the wheel's centre, mm; default 150", 0, 1e4)});
    const Vec3 n = so.vec3("normal", Vec3::Zero()), a = so.vec3("axis", Vec3::Zero());
    if (n.norm() < 1e-12 || a.norm() < 1e-12 || std::abs(n.normalized().dot(a.normalized())) > 1e-6)
      luax::error(L, what + ": expected normal and axis of non-zero length at right angles");
    s.contact.linear().col(0) = a.normalized();
    s.contact.linear().col(2) = n.normalized();
    s.contact.linear().col(1) = s.contact.linear().col(2).cross(s.contact.linear().col(0));
    s.contact.translation() = so.vec3("contact", Vec3::Zero());
    so.push_raw("wheel");
    const luax::Options w(L, lua_gettop(L), what + ".wheel",
                          {number_field("radius", "mm", 1e-3), number_field("width", "mm", 1e-3),
                           number_field("compliance", "how far the rubber and belt give under the grinding force, mm; default 0.5", 0, 100)});
    if (!w.has("radius") || !w.has("width")) luax::error(L, what + ".wheel: expected {radius = mm, width = mm}");
    s.wheel_radius_mm = w.number("radius", 0);
    s.wheel_width_mm = w.number("width", 0);
    s.compliance_mm = w.number("compliance", s.compliance_mm);
    lua_pop(L, 1);
    s.belt_run_mm = so.number("belt_run", s.belt_run_mm);
    s.belt = so.string("belt", "");
    s.belt_speed_m_s = so.number("speed", 0);
    c.cell.stations.push_back(s);
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  std::sort(c.cell.stations.begin(), c.cell.stations.end(),
            [](const BeltStation& x, const BeltStation& y) { return x.name < y.name; });
  try {
    c.cell.validate();
  } catch (const ParameterError& e) {
    luax::error(L, std::string("robot_cell: ") + e.what());
  }
  luax::push_new(L, std::move(c));
  return 1;
}

// bliskrun.robot_cell(name_or_file) -> RobotCell
int w_robot_cell(lua_State* L) {
  const std::string what = luax::check_string(L, 1, "cell");
  const std::string path = resolve_script(L, what, "machines");
  lua_newtable(L);  // the file's environment: robot_cell and the safe libraries
  lua_pushcfunction(L, l_robot_cell);
  lua_setfield(L, -2, "robot_cell");
  for (const char* lib : {"math", "string", "table"}) {
    lua_getglobal(L, lib);
    lua_setfield(L, -2, lib);
  }
  run_script_file(L, path, -1);
  LuaRobotCell* c = luax::test<LuaRobotCell>(L, -1);
  if (!c) luax::error(L, path + ": expected the file to return robot_cell { ... }");
  c->source = path;
  return 1;
}

LuaRobotCell& check_cell(lua_State* L) { return luax::check<LuaRobotCell>(L, 1); }

int w_cell_name(lua_State* L) {
  lua_pushstring(L, check_cell(L).cell.name.c_str());
  return 1;
}

int w_cell_stations(lua_State* L) {
  const RobotCell& cell = check_cell(L).cell;
  lua_createtable(L, static_cast<int>(cell.stations.size()), 0);
  for (size_t i = 0; i < cell.stations.size(); ++i) {
    const BeltStation& s = cell.stations[i];
    lua_createtable(L, 0, 6);
    luax::set_string(L, "name", s.name);
    luax::set_number(L, "radius", s.wheel_radius_mm);
    luax::set_number(L, "width", s.wheel_width_mm);
    luax::set_string(L, "belt", s.belt);
    luax::set_number(L, "speed", s.belt_speed_m_s);
    luax::set_number(L, "compliance", s.compliance_mm);
    luax::set_number(L, "belt_run", s.belt_run_mm);
    push_frame(L, s.contact);
    lua_setfield(L, -2, "frame");
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  return 1;
}

// cell:forward(joints_deg) -> flange frame {origin, x, y, z}
int w_cell_forward(lua_State* L) {
  const RobotCell& cell = check_cell(L).cell;
  push_frame(L, robot_forward(cell.arm, joints_arg(L, 2, "joints")));
  return 1;
}

// cell:inverse(frame [, previous_joints_deg]) -> {{joints, branch, singular, within_limits}, ...}
int w_cell_inverse(lua_State* L) {
  const RobotCell& cell = check_cell(L).cell;
  const Frame f = frame_field(L, 2, "frame");
  RobotIkOptions ik;
  if (!lua_isnoneornil(L, 3)) ik.previous = joints_arg(L, 3, "previous");
  const auto solutions = robot_inverse(cell.arm, f, ik);
  lua_createtable(L, static_cast<int>(solutions.size()), 0);
  for (size_t i = 0; i < solutions.size(); ++i) {
    lua_createtable(L, 0, 4);
    push_joints(L, solutions[i].joints);
    lua_setfield(L, -2, "joints");
    luax::set_number(L, "branch", solutions[i].branch);
    luax::set_bool(L, "singular", solutions[i].wrist_singular);
    luax::set_bool(L, "within_limits", solutions[i].within_limits);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  return 1;
}

// cell:plan_grinding{station=, grip=, paths=, feed=, link_feed=, retract=} -> RobotGrindingPlan
int w_cell_plan_grinding(lua_State* L) {
  const LuaRobotCell& lc = check_cell(L);
  const luax::Options o(
      L, 2, "cell:plan_grinding",
      {Field{"station", Kind::String, true, std::nullopt, std::nullopt, "station name (cell:stations())", {}},
       Field{"grip", Kind::Table, true, std::nullopt, std::nullopt,
             "the blade frame in the flange frame {origin, x, z}", {}},
       Field{"paths", Kind::Table, true, std::nullopt, std::nullopt,
             "belt paths (bliskrun.belt_paths(...).paths): points, normals, tangents", {}},
       number_field("feed", "contact speed along the path, mm/s; default 20", 1e-3, 1e4),
       number_field("link_feed", "speed off the wheel between paths, mm/s; default 200", 1e-3, 1e5),
       number_field("retract", "lift-off along the normal between paths, mm; default 10", 1e-3, 1000),
       Field{"blade", Kind::Any, true, std::nullopt, std::nullopt,
             "the whole blade (bliskrun.blade_body{...}) the wheel and belt are checked against", {}}});
  auto cell = std::make_shared<RobotCell>(lc.cell);
  o.push_raw("blade");
  const LuaBladeBody* blade = luax::test<LuaBladeBody>(L, -1);
  if (!blade) luax::error(L, "cell:plan_grinding: blade: expected bliskrun.blade_body{...}");
  const std::shared_ptr<const BladeBody> body = blade->body;
  lua_pop(L, 1);
  o.push_raw("grip");
  cell->grip = frame_field(L, -1, "cell:plan_grinding: grip");
  lua_pop(L, 1);
  const std::string station = o.string("station", "");
  std::vector<std::vector<BladeContact>> paths;
  o.push_raw("paths");
  const int pi = lua_gettop(L);
  const lua_Integer np = luaL_len(L, pi);
  for (lua_Integer j = 1; j <= np; ++j) {
    lua_rawgeti(L, pi, j);
    const int p = lua_gettop(L);
    const std::string where = "cell:plan_grinding: paths[" + std::to_string(j) + "]";
    std::vector<BladeContact> path;
    lua_getfield(L, p, "points");
    lua_getfield(L, p, "normals");
    lua_getfield(L, p, "tangents");
    if (!lua_istable(L, -3) || !lua_istable(L, -2) || !lua_istable(L, -1))
      luax::error(L, where + ": expected points, normals and tangents");
    const lua_Integer n = luaL_len(L, -3);
    if (luaL_len(L, -2) != n || luaL_len(L, -1) != n) luax::error(L, where + ": points, normals and tangents differ in length");
    for (lua_Integer i = 1; i <= n; ++i) {
      BladeContact c;
      lua_rawgeti(L, -3, i);
      c.point = luax::check_vec3(L, -1, (where + ".points").c_str());
      lua_pop(L, 1);
      lua_rawgeti(L, -2, i);
      c.normal = luax::check_vec3(L, -1, (where + ".normals").c_str());
      lua_pop(L, 1);
      lua_rawgeti(L, -1, i);
      c.tangent = luax::check_vec3(L, -1, (where + ".tangents").c_str());
      lua_pop(L, 1);
      path.push_back(c);
    }
    lua_pop(L, 4);
    paths.push_back(std::move(path));
  }
  lua_pop(L, 1);
  RobotGrindingOptions go;
  go.feed_mm_s = o.number("feed", go.feed_mm_s);
  go.link_feed_mm_s = o.number("link_feed", go.link_feed_mm_s);
  go.retract_mm = o.number("retract", go.retract_mm);
  go.start = cell->home;
  go.blade = body.get();
  return luax::guarded(L, [&] {
    LuaRobotPlan lp;
    lp.plan = plan_robot_grinding(*cell, cell->station(station), paths, go);
    lp.cell = cell;
    lp.station = station;
    lp.feed_mm_s = go.feed_mm_s;
    luax::push_new(L, std::move(lp));
    return 1;
  });
}

LuaRobotPlan& check_robot_plan(lua_State* L) { return luax::check<LuaRobotPlan>(L, 1); }

int w_robot_plan_report(lua_State* L) {
  const RobotGrindingPlan& p = check_robot_plan(L).plan;
  lua_createtable(L, 0, 8);
  luax::set_number(L, "moves", static_cast<double>(p.moves.size()));
  luax::set_number(L, "paths", p.paths);
  luax::set_number(L, "turned_paths", p.turned_paths);
  luax::set_number(L, "branch_changes", p.branch_changes);
  luax::set_number(L, "singular_moves", p.singular_moves);
  luax::set_number(L, "turn_changes", p.turn_changes);
  luax::set_number(L, "max_joint_speed_ratio", p.max_joint_speed_ratio);
  luax::set_number(L, "max_link_joint_speed_ratio", p.max_link_joint_speed_ratio);
  luax::set_strings(L, "refusals", p.refusals);
  lua_createtable(L, 0, 5);
  luax::set_number(L, "poses", static_cast<double>(p.wheel.poses));
  luax::set_number(L, "max_conformity", p.wheel.max_conformity_mm);
  luax::set_number(L, "rejected", static_cast<double>(p.wheel.collisions));
  luax::set_number(L, "max_collision_depth", p.wheel.max_collision_depth_mm);
  luax::set_string(L, "first_collision", p.wheel.first_collision);
  lua_setfield(L, -2, "wheel");
  return 1;
}

// plan:cycle_time{tcp_accel = 1000, joint_accel = 2, from_home = true,
// to_home = true} -> {total_s, grinding_s, link_s, home_s, grinding_mm,
// link_mm, paths, joint_limited_steps} (core/machine/robot_cycle_time.h)
int w_robot_plan_cycle_time(lua_State* L) {
  const LuaRobotPlan& lp = check_robot_plan(L);
  const luax::Options o(
      L, 2, "plan:cycle_time",
      {number_field("tcp_accel", "path acceleration of the TCP, mm/s^2; default 1000", 1, 1e6),
       number_field("joint_accel", "joint acceleration for the home moves, rad/s^2; default 2", 1e-3, 1e3),
       Field{"from_home", Kind::Boolean, false, std::nullopt, std::nullopt, "add home -> first target", {}},
       Field{"to_home", Kind::Boolean, false, std::nullopt, std::nullopt, "add last target -> home", {}}});
  RobotCycleTimeOptions co;
  co.tcp_accel_mm_s2 = o.number("tcp_accel", co.tcp_accel_mm_s2);
  co.joint_accel_rad_s2 = o.number("joint_accel", co.joint_accel_rad_s2);
  co.from_home = o.boolean("from_home", true);
  co.to_home = o.boolean("to_home", true);
  return luax::guarded(L, [&] {
    const RobotCycleTime c = estimate_robot_cycle_time(*lp.cell, lp.plan, co);
    lua_createtable(L, 0, 8);
    luax::set_number(L, "total_s", c.total_s);
    luax::set_number(L, "grinding_s", c.grinding_s);
    luax::set_number(L, "link_s", c.link_s);
    luax::set_number(L, "home_s", c.home_s);
    luax::set_number(L, "grinding_mm", c.grinding_mm);
    luax::set_number(L, "link_mm", c.link_mm);
    luax::set_number(L, "paths", c.paths);
    luax::set_number(L, "joint_limited_steps", c.joint_limited_steps);
    return 1;
  });
}

// bliskrun.blade_body{faces = {{name =, surface =}, ...}, spacing = 1} -> BladeBody
int w_blade_body(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.blade_body",
      {Field{"faces", Kind::Table, true, std::nullopt, std::nullopt,
             "every face of the blade, blade frame: {{name = \"pressure\", surface = s}, ...}", {}},
       number_field("spacing", "largest distance between samples, mm; default 1", 1e-3, 100)});
  std::vector<std::pair<std::string, std::shared_ptr<const Surface>>> faces;
  o.push_raw("faces");
  const int ft = lua_gettop(L);
  for (lua_Integer i = 1; i <= luaL_len(L, ft); ++i) {
    lua_rawgeti(L, ft, i);
    const std::string where = "bliskrun.blade_body: faces[" + std::to_string(i) + "]";
    if (!lua_istable(L, -1)) luax::error(L, where + ": expected {name = \"...\", surface = s}");
    const luax::Options f(L, lua_gettop(L), where,
                          {Field{"name", Kind::String, true, std::nullopt, std::nullopt, "the face's name in reports", {}},
                           Field{"surface", Kind::Any, true, std::nullopt, std::nullopt, "a Surface", {}}});
    f.push_raw("surface");
    const SurfaceHandle* h = luax::test<SurfaceHandle>(L, -1);
    if (!h) luax::error(L, where + ".surface: expected a Surface");
    faces.emplace_back(f.string("name", ""), h->surface);
    lua_pop(L, 2);
  }
  lua_pop(L, 1);
  const double spacing = o.number("spacing", 1.0);
  return luax::guarded(L, [&] {
    LuaBladeBody b;
    b.body = std::make_shared<const BladeBody>(BladeBody::sample(faces, spacing));
    luax::push_new(L, std::move(b));
    return 1;
  });
}

int w_blade_body_points(lua_State* L) {
  lua_pushinteger(L, static_cast<lua_Integer>(luax::check<LuaBladeBody>(L, 1).body->points.size()));
  return 1;
}

int w_robot_plan_moves(lua_State* L) {
  const RobotGrindingPlan& p = check_robot_plan(L).plan;
  lua_createtable(L, static_cast<int>(p.moves.size()), 0);
  for (size_t i = 0; i < p.moves.size(); ++i) {
    const RobotMove& m = p.moves[i];
    lua_createtable(L, 0, 8);
    push_joints(L, m.joints);
    lua_setfield(L, -2, "joints");
    luax::set_number(L, "branch", m.branch);
    luax::set_bool(L, "link", m.link);
    luax::set_bool(L, "turned", m.turned);
    luax::set_number(L, "path", m.path + 1);
    luax::set_vec3(L, "point", m.contact.point);
    luax::set_number(L, "offset", m.offset_mm);
    luax::set_number(L, "joint_speed_ratio", m.joint_speed_ratio);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  return 1;
}

// What a robot program states besides its targets: the speeds and zone
// that hold the plan on the controller, and the payload.
struct ProgramSettings {
  double ori_speed_deg_s = 0;   // the orientation speed that lets every grinding move keep its feed
  double zone_mm = 0;           // blend radius within the chord tolerance; 0: exact stops
  MassProperties gripper;       // flange frame
  MassProperties blade;         // blade frame
};

// A mass description for a post: mass (kg), centre of gravity (mm), the
// principal axes as a quaternion {w, x, y, z} (ABB aom) and as Z-Y-X angles
// (KUKA A, B, C, deg), the principal moments (kg·m²) and the whole tensor.
void push_mass(lua_State* L, const MassProperties& m) {
  const PrincipalInertia p = principal_inertia(m.inertia_kg_mm2);
  lua_createtable(L, 0, 8);
  luax::set_number(L, "mass", m.mass_kg);
  luax::set_vec3(L, "cog", m.cog_mm);
  const Eigen::Quaterniond q(p.axes);
  lua_createtable(L, 4, 0);
  const double qv[4] = {q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 4; ++i) {
    lua_pushnumber(L, qv[i]);
    lua_rawseti(L, -2, i + 1);
  }
  lua_setfield(L, -2, "aom");
  // Z-Y-X angles with B in [-90°, 90°] (R = Rz(A) Ry(B) Rx(C)).
  const Mat3& R = p.axes;
  luax::set_number(L, "a", rad_to_deg(std::atan2(R(1, 0), R(0, 0))));
  luax::set_number(L, "b", rad_to_deg(std::asin(std::clamp(-R(2, 0), -1.0, 1.0))));
  luax::set_number(L, "c", rad_to_deg(std::atan2(R(2, 1), R(2, 2))));
  luax::set_vec3(L, "moments", 1e-6 * p.moments_kg_mm2);
}

// The job a robot post writes from: cell, station and grip frames, and per
// move the target (station in blade frame) with its configuration fields,
// for moves [from, to); `calls` instead of moves when the program only calls
// its parts, `part` for a part called from another program.
void push_robot_job(lua_State* L, const LuaRobotPlan& lp, const std::string& title, const std::string& program,
                    size_t from, size_t to, const std::vector<std::string>& calls, bool part,
                    const ProgramSettings& ps) {
  const RobotCell& cell = *lp.cell;
  const BeltStation& st = cell.station(lp.station);
  auto set_pose = [&](const Frame& f) {
    luax::set_vec3(L, "origin", f.translation());
    const Eigen::Quaterniond q(f.linear());
    lua_createtable(L, 4, 0);
    const double qv[4] = {q.w(), q.x(), q.y(), q.z()};
    for (int i = 0; i < 4; ++i) {
      lua_pushnumber(L, qv[i]);
      lua_rawseti(L, -2, i + 1);
    }
    lua_setfield(L, -2, "quaternion");
    // Z-Y-X angles (KUKA's A, B, C), deg.
    const Vec3 e = f.linear().eulerAngles(2, 1, 0);
    luax::set_number(L, "a", rad_to_deg(e[0]));
    luax::set_number(L, "b", rad_to_deg(e[1]));
    luax::set_number(L, "c", rad_to_deg(e[2]));
  };
  lua_createtable(L, 0, 12);
  luax::set_string(L, "name", title);
  luax::set_string(L, "program", program);
  luax::set_bool(L, "part", part);
  luax::set_number(L, "ori_speed", ps.ori_speed_deg_s);
  luax::set_number(L, "zone", ps.zone_mm);
  // The load: the whole of it on the flange (gripper and blade, flange
  // frame), the gripper alone (flange frame) and the blade alone in its own
  // frame — the frame of the work object the robot holds.
  push_mass(L, combined(ps.gripper, transformed(ps.blade, cell.grip)));
  push_mass(L, ps.gripper);
  lua_setfield(L, -2, "gripper");
  push_mass(L, ps.blade);
  lua_setfield(L, -2, "blade");
  lua_setfield(L, -2, "payload");
  luax::set_strings(L, "calls", calls);
  lua_createtable(L, 0, 2);
  luax::set_string(L, "name", cell.name);
  push_joints(L, cell.home);
  lua_setfield(L, -2, "home");
  lua_setfield(L, -2, "cell");
  lua_createtable(L, 0, 8);
  luax::set_string(L, "name", st.name);
  luax::set_string(L, "belt", st.belt);
  luax::set_number(L, "speed", st.belt_speed_m_s);
  set_pose(st.contact);
  lua_setfield(L, -2, "station");
  lua_createtable(L, 0, 6);
  set_pose(cell.grip);
  lua_setfield(L, -2, "grip");
  lua_createtable(L, static_cast<int>(to - from), 0);
  for (size_t i = from; i < to; ++i) {
    const RobotMove& m = lp.plan.moves[i];
    lua_createtable(L, 0, 16);
    set_pose(robot_target_frame(cell, st, m));
    const auto quadrants = abb_quadrants(m.joints);
    luax::set_number(L, "cf1", quadrants[0]);
    luax::set_number(L, "cf4", quadrants[1]);
    luax::set_number(L, "cf6", quadrants[2]);
    luax::set_number(L, "cfx", abb_cfx(cell.arm, m.joints));
    luax::set_number(L, "s", kuka_status(cell.arm, m.joints));
    luax::set_number(L, "t", kuka_turn_bits(m.joints));
    luax::set_bool(L, "link", m.link);
    luax::set_bool(L, "first", i == 0);
    luax::set_number(L, "path", m.path + 1);
    luax::set_number(L, "feed", m.feed_mm_s);
    push_joints(L, m.joints);
    lua_setfield(L, -2, "joints");
    lua_rawseti(L, -2, static_cast<lua_Integer>(i - from + 1));
  }
  lua_setfield(L, -2, "moves");
}

// The `out` a post writes lines to; its text by out.text().
const char* kOutChunk =
    "local lines = {}\n"
    "return {line = function(_, t) lines[#lines + 1] = t end,\n"
    "        text = function() return table.concat(lines, '\\n') .. '\\n' end}\n";

// Runs the post (at `post`) on one job; returns the program's text.
std::string run_post(lua_State* L, int post, const LuaRobotPlan& lp, const std::string& title,
                     const std::string& program, size_t from, size_t to, const std::vector<std::string>& calls,
                     bool part, const ProgramSettings& ps) {
  if (luaL_loadstring(L, kOutChunk) != LUA_OK) lua_error(L);
  lua_call(L, 0, 1);
  const int out = lua_gettop(L);
  lua_getfield(L, post, "write");
  lua_pushvalue(L, post);
  push_robot_job(L, lp, title, program, from, to, calls, part, ps);
  lua_pushvalue(L, out);
  lua_call(L, 3, 0);
  lua_getfield(L, out, "text");
  lua_call(L, 0, 1);
  std::string text = lua_tostring(L, -1);
  lua_pop(L, 2);
  return text;
}

// The orientation speed every grinding move needs to keep its feed (the
// controller takes the longer of path length / v_tcp and turn / v_ori), and
// the blend radius whose corner cut stays within the chord tolerance: a
// parabolic blend over r each side of a corner turning by α leaves the
// corner by ≈ r·α/4, so r ≤ 4ε/α at the sharpest corner (capped at 1 mm).
void plan_settings(const LuaRobotPlan& lp, double chord_tol_mm, ProgramSettings& ps) {
  const RobotCell& cell = *lp.cell;
  const BeltStation& st = cell.station(lp.station);
  double need = 0, zone = chord_tol_mm > 0 ? 1.0 : 0.0;
  std::optional<Frame> prev, prev2;
  for (const RobotMove& m : lp.plan.moves) {
    const Frame t = robot_target_frame(cell, st, m);
    if (prev && !m.link) {
      const double length = (t.translation() - prev->translation()).norm();
      const double turn = rad_to_deg(Eigen::AngleAxisd(prev->linear().transpose() * t.linear()).angle());
      if (length > 1e-9) need = std::max(need, turn * m.feed_mm_s / length);
      if (prev2 && chord_tol_mm > 0) {
        const Vec3 a = prev->translation() - prev2->translation(), b = t.translation() - prev->translation();
        if (a.norm() > 1e-9 && b.norm() > 1e-9) {
          const double alpha = std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
          if (alpha > 1e-12) zone = std::min(zone, 4 * chord_tol_mm / alpha);
        }
      }
    }
    prev2 = m.link ? std::optional<Frame>() : prev;
    prev = t;
  }
  // 10 % above the need, in whole deg/s, and never below 30 deg/s.
  ps.ori_speed_deg_s = std::max(30.0, std::ceil(need * 1.1));
  ps.zone_mm = std::floor(zone * 1000) / 1000;
}

// A mass table {mass (kg), cog = {x, y, z} (mm), inertia = 3 rows (kg·mm²,
// about cog)} as bliskrun.mass_properties returns it; inertia optional.
MassProperties mass_table(lua_State* L, int idx, const std::string& where) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) luax::error(L, where + ": expected {mass =, cog =, inertia =}");
  MassProperties m;
  lua_getfield(L, idx, "mass");
  if (!lua_isnumber(L, -1) || !(lua_tonumber(L, -1) >= 0)) luax::error(L, where + ".mass: expected kg >= 0");
  m.mass_kg = lua_tonumber(L, -1);
  lua_pop(L, 1);
  lua_getfield(L, idx, "cog");
  if (!lua_isnil(L, -1)) m.cog_mm = luax::check_vec3(L, -1, (where + ".cog").c_str());
  lua_pop(L, 1);
  lua_getfield(L, idx, "inertia");
  if (!lua_isnil(L, -1)) {
    if (!lua_istable(L, -1) || luaL_len(L, -1) != 3) luax::error(L, where + ".inertia: expected 3 rows, kg mm2");
    for (int r = 0; r < 3; ++r) {
      lua_rawgeti(L, -1, r + 1);
      m.inertia_kg_mm2.row(r) = luax::check_vec3(L, -1, (where + ".inertia[" + std::to_string(r + 1) + "]").c_str());
      lua_pop(L, 1);
    }
    if (!m.inertia_kg_mm2.isApprox(m.inertia_kg_mm2.transpose(), 1e-9))
      luax::error(L, where + ".inertia: not symmetric");
  }
  lua_pop(L, 1);
  return m;
}

void push_mass_table(lua_State* L, const MassProperties& m) {
  lua_createtable(L, 0, 5);
  luax::set_number(L, "mass", m.mass_kg);
  luax::set_number(L, "volume", m.volume_mm3);
  luax::set_vec3(L, "cog", m.cog_mm);
  lua_createtable(L, 3, 0);
  for (int r = 0; r < 3; ++r) {
    luax::push(L, Vec3(m.inertia_kg_mm2.row(r).transpose()));
    lua_rawseti(L, -2, r + 1);
  }
  lua_setfield(L, -2, "inertia");
  const PrincipalInertia p = principal_inertia(m.inertia_kg_mm2);
  lua_createtable(L, 0, 2);
  luax::set_vec3(L, "moments", p.moments_kg_mm2);
  push_frame(L, [&] {
    Frame f = Frame::Identity();
    f.linear() = p.axes;
    f.translation() = m.cog_mm;
    return f;
  }());
  lua_setfield(L, -2, "axes");
  lua_setfield(L, -2, "principal");
}

// bliskrun.mass_properties{loops= | vertices=, triangles= | box= | cylinder=,
// density= | mass=, frame=} -> {mass, volume, cog, inertia, principal}
int w_mass_properties(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.mass_properties",
      {Field{"loops", Kind::Table, false, std::nullopt, std::nullopt,
             "closed section loops of a solid, each a list of {x, y, z} (mm), the same count each; ends capped", {}},
       Field{"vertices", Kind::Table, false, std::nullopt, std::nullopt, "a closed mesh's vertices {x, y, z}, mm", {}},
       Field{"triangles", Kind::Table, false, std::nullopt, std::nullopt, "its triangles {i, j, k} (1-based)", {}},
       Field{"box", Kind::Vec3, false, std::nullopt, std::nullopt, "a box's edges along the frame's x, y, z, mm", {}},
       Field{"cylinder", Kind::Table, false, std::nullopt, std::nullopt,
             "{radius =, length =}: a solid cylinder about the frame's z, mm", {}},
       number_field("density", "g/cm3 (the mesh and loops need it; a box or cylinder takes density or mass)", 1e-6, 1e3),
       number_field("mass", "kg, for a box or cylinder", 0, 1e5),
       Field{"frame", Kind::Table, false, std::nullopt, std::nullopt,
             "{origin, x, z}: where a box or cylinder is centred and turned; default the identity", {}}});
  const int kinds = int(o.has("loops")) + int(o.has("vertices")) + int(o.has("box")) + int(o.has("cylinder"));
  if (kinds != 1) luax::error(L, "bliskrun.mass_properties: give one of loops, vertices (with triangles), box, cylinder");
  auto points = [&](int idx, const std::string& where) {
    idx = lua_absindex(L, idx);
    if (!lua_istable(L, idx)) luax::error(L, where + ": expected a list of {x, y, z}");
    std::vector<Vec3> out;
    const lua_Integer n = luaL_len(L, idx);
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, idx, i);
      out.push_back(luax::check_vec3(L, -1, (where + "[" + std::to_string(i) + "]").c_str()));
      lua_pop(L, 1);
    }
    return out;
  };
  if (o.has("loops") || o.has("vertices")) {
    if (!o.has("density")) luax::error(L, "bliskrun.mass_properties: a mesh or loops need 'density' (g/cm3)");
    const double density = 1e-6 * o.number("density", 0);
    std::vector<Vec3> vertices;
    std::vector<std::array<int, 3>> triangles;
    if (o.has("loops")) {
      o.push_raw("loops");
      std::vector<std::vector<Vec3>> loops;
      for (lua_Integer k = 1; k <= luaL_len(L, -1); ++k) {
        lua_rawgeti(L, -1, k);
        loops.push_back(points(-1, "bliskrun.mass_properties: loops[" + std::to_string(k) + "]"));
        lua_pop(L, 1);
      }
      lua_pop(L, 1);
      return luax::guarded(L, [&] {
        closed_loft_mesh(loops, vertices, triangles);
        push_mass_table(L, solid_mass_properties(vertices, triangles, density));
        return 1;
      });
    }
    if (!o.has("triangles")) luax::error(L, "bliskrun.mass_properties: vertices need triangles");
    o.push_raw("vertices");
    vertices = points(-1, "bliskrun.mass_properties: vertices");
    lua_pop(L, 1);
    o.push_raw("triangles");
    for (lua_Integer k = 1; k <= luaL_len(L, -1); ++k) {
      lua_rawgeti(L, -1, k);
      const Vec3 t = luax::check_vec3(L, -1, ("bliskrun.mass_properties: triangles[" + std::to_string(k) + "]").c_str());
      lua_pop(L, 1);
      triangles.push_back({static_cast<int>(t.x()) - 1, static_cast<int>(t.y()) - 1, static_cast<int>(t.z()) - 1});
    }
    lua_pop(L, 1);
    return luax::guarded(L, [&] {
      push_mass_table(L, solid_mass_properties(vertices, triangles, density));
      return 1;
    });
  }
  Frame where = Frame::Identity();
  if (o.has("frame")) {
    o.push_raw("frame");
    where = frame_field(L, -1, "bliskrun.mass_properties: option 'frame'");
    lua_pop(L, 1);
  }
  if (o.has("mass") == o.has("density"))
    luax::error(L, "bliskrun.mass_properties: a box or cylinder takes 'mass' (kg) or 'density' (g/cm3)");
  return luax::guarded(L, [&] {
    if (o.has("box")) {
      const Vec3 size = o.vec3("box", Vec3::Zero());
      const double mass = o.has("mass") ? o.number("mass", 0) : 1e-6 * o.number("density", 0) * size.prod();
      push_mass_table(L, box_mass_properties(mass, size, where));
    } else {
      o.push_raw("cylinder");
      lua_getfield(L, -1, "radius");
      lua_getfield(L, -2, "length");
      if (!lua_isnumber(L, -2) || !lua_isnumber(L, -1))
        throw Error("bliskrun.mass_properties: option 'cylinder': expected {radius =, length =} in mm");
      const double r = lua_tonumber(L, -2), length = lua_tonumber(L, -1);
      lua_pop(L, 3);
      const double mass = o.has("mass") ? o.number("mass", 0) : 1e-6 * o.number("density", 0) * kPi * r * r * length;
      push_mass_table(L, cylinder_mass_properties(mass, r, length, where));
    }
    return 1;
  });
}

std::string file_stem(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  return name.substr(0, name.find('.'));
}

std::string file_ext(const std::string& path) {
  const size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
  return dot == std::string::npos || (slash != std::string::npos && dot < slash) ? "" : path.substr(dot);
}

// plan:write_program{post = "abb_rapid"|"kuka_krl"|post table, file=, name=, ...} -> report
int w_robot_plan_write_program(lua_State* L) {
  const LuaRobotPlan& lp = check_robot_plan(L);
  const luax::Options o(
      L, 2, "plan:write_program",
      {Field{"post", Kind::Any, true, std::nullopt, std::nullopt, "\"abb_rapid\", \"kuka_krl\" or a post table", {}},
       Field{"file", Kind::String, true, std::nullopt, std::nullopt,
             "program file in the out folder; its name (without extension) is the program's name", {}},
       Field{"name", Kind::String, false, std::nullopt, std::nullopt, "a title written as a comment", {}},
       number_field("position_tol", "read-back tolerance of the contact, mm; default 0.002", 1e-9, 10),
       number_field("angle_tol", "read-back tolerance of the orientation, deg; default 0.001", 1e-9, 10),
       number_field("chord_tol", "the paths' chord tolerance, mm: sets the blend zone; default 0 (exact stops)", 0, 10),
       number_field("max_bytes", "largest program file; longer programs are split into parts; default 500000",
                    2000, 1e9),
       number_field("blade_mass", "the blade's mass, kg; default 0", 0, 1e4),
       Field{"blade_cog", Kind::Table, false, std::nullopt, std::nullopt, "the blade's centre of gravity, blade frame, mm", {}},
       number_field("gripper_mass", "the gripper's mass, kg; default 0", 0, 1e4),
       Field{"gripper_cog", Kind::Table, false, std::nullopt, std::nullopt,
             "the gripper's centre of gravity, flange frame, mm", {}},
       Field{"blade", Kind::Table, false, std::nullopt, std::nullopt,
             "the blade's mass properties in the blade frame (bliskrun.mass_properties)", {}},
       Field{"gripper", Kind::Table, false, std::nullopt, std::nullopt,
             "the gripper's mass properties in the flange frame (bliskrun.mass_properties)", {}},
       Field{"registration", Kind::Table, false, std::nullopt, std::nullopt,
             "the scan registration the grip was corrected with (bliskrun.register_scan): refused unless trusted", {}}});
  if (!lp.plan.refusals.empty())
    luax::error(L, "plan:write_program: the plan refused " + std::to_string(lp.plan.refusals.size()) +
                       " path(s) (first: " + lp.plan.refusals.front() + "); nothing written");
  const std::string path = context(L).resolve_write(L, o.string("file", ""));
  const std::string stem = file_stem(o.string("file", "")), ext = file_ext(path);
  const std::string dir = path.substr(0, path.size() - file_stem(path).size() - ext.size());
  const int post = push_post_option(L, o, "plan:write_program: option 'post'");
  lua_getfield(L, post, "dialect");
  const std::string dialect_name = lua_isstring(L, -1) ? lua_tostring(L, -1) : "";
  lua_pop(L, 1);
  if (dialect_name != "abb_rapid" && dialect_name != "kuka_krl")
    luax::error(L, "plan:write_program: the post is not a robot post (dialect \"abb_rapid\" or \"kuka_krl\")");
  const RobotDialect dialect = dialect_name == "abb_rapid" ? RobotDialect::AbbRapid : RobotDialect::KukaKrl;
  // KRL names are at most 24 characters, RAPID's 32; a part adds "_p" and up to 2 digits.
  const size_t longest = dialect == RobotDialect::KukaKrl ? 24 : 32;
  if (stem.empty() || !std::isalpha(static_cast<unsigned char>(stem[0])) ||
      stem.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") != std::string::npos ||
      stem.size() + 4 > longest)
    luax::error(L, "plan:write_program: option 'file': the program is named after its file, so '" + stem +
                       "' must start with a letter, hold only letters, digits and _ and be at most " +
                       std::to_string(longest - 4) + " characters");
  // A registration that is not trusted stops the post here too, whatever
  // the recipe does with it (issue 39 item 5): its problems say what to scan.
  if (o.has("registration")) {
    o.push_raw("registration");
    lua_getfield(L, -1, "trusted");
    const bool trusted = lua_toboolean(L, -1);
    lua_pop(L, 1);
    if (!trusted) {
      std::string why;
      lua_getfield(L, -1, "problems");
      if (lua_istable(L, -1))
        for (lua_Integer i = 1; i <= luaL_len(L, -1); ++i) {
          lua_rawgeti(L, -1, i);
          if (lua_isstring(L, -1)) why += std::string(why.empty() ? "" : "; ") + lua_tostring(L, -1);
          lua_pop(L, 1);
        }
      luax::error(L, "plan:write_program: the scan registration is not trusted" + (why.empty() ? "" : ": " + why) +
                         "; nothing written");
    }
    lua_pop(L, 1);
  }
  ProgramSettings ps;
  plan_settings(lp, o.number("chord_tol", 0), ps);
  auto vec_opt = [&](const char* key, Vec3& v) {
    if (!o.has(key)) return;
    o.push_raw(key);
    v = luax::check_vec3(L, -1, (std::string("plan:write_program: option '") + key + "'").c_str());
    lua_pop(L, 1);
  };
  for (const char* whole : {"blade", "gripper"}) {
    const std::string part = whole;
    if (o.has(whole) && (o.has(part + "_mass") || o.has(part + "_cog")))
      luax::error(L, "plan:write_program: give '" + part + "' or '" + part + "_mass'/'" + part + "_cog', not both");
    MassProperties& m = part == "blade" ? ps.blade : ps.gripper;
    if (o.has(whole)) {
      o.push_raw(whole);
      m = mass_table(L, -1, "plan:write_program: option '" + part + "'");
      lua_pop(L, 1);
    } else {
      // A point mass: no inertia of its own.
      m.mass_kg = o.number(part + "_mass", 0);
      vec_opt((part + "_cog").c_str(), m.cog_mm);
    }
  }
  const size_t max_bytes = static_cast<size_t>(o.number("max_bytes", 500000));
  const std::string title = o.string("name", stem);
  const size_t n_moves = lp.plan.moves.size();
  // Whole program first; when too long, parts split where a path starts, as
  // even as the paths allow, one more part until each fits.
  std::map<std::string, std::string> programs;
  std::vector<std::string> order;
  std::string text = run_post(L, post, lp, title, stem, 0, n_moves, {}, false, ps);
  if (text.size() <= max_bytes) {
    programs[stem] = text;
    order.push_back(stem);
  } else {
    std::vector<size_t> starts;  // where a path's moves begin
    for (size_t i = 1; i < n_moves; ++i)
      if (lp.plan.moves[i].path != lp.plan.moves[i - 1].path) starts.push_back(i);
    bool fits = false;
    for (size_t parts = (text.size() + max_bytes - 1) / max_bytes; !fits && parts <= 99; ++parts) {
      std::vector<size_t> cut{0};
      for (size_t k = 1; k < parts; ++k) {
        const size_t want = n_moves * k / parts;
        size_t best = 0;
        for (size_t s : starts)
          if (s > cut.back() && (best == 0 || std::abs(double(s) - double(want)) < std::abs(double(best) - double(want))))
            best = s;
        if (best > cut.back()) cut.push_back(best);
      }
      cut.push_back(n_moves);
      programs.clear();
      order.clear();
      std::vector<std::string> calls;
      fits = true;
      for (size_t k = 0; k + 1 < cut.size() && fits; ++k) {
        const std::string name = stem + "_p" + std::to_string(k + 1);
        const std::string part = run_post(L, post, lp, title, name, cut[k], cut[k + 1], {}, true, ps);
        if (part.size() > max_bytes) {
          if (cut[k + 1] - cut[k] > 0 && starts.empty())
            luax::error(L, "plan:write_program: one path's program is longer than max_bytes");
          fits = false;
        }
        programs[name] = part;
        calls.push_back(name);
      }
      if (!fits) continue;
      programs[stem] = run_post(L, post, lp, title, stem, 0, 0, calls, false, ps);
      order.push_back(stem);
      order.insert(order.end(), calls.begin(), calls.end());
    }
    if (!fits) luax::error(L, "plan:write_program: could not split the program within max_bytes");
  }
  const double position_tol = o.number("position_tol", 0.002), angle_tol = o.number("angle_tol", 0.001);
  return luax::guarded(L, [&] {
    const BeltStation& st = lp.cell->station(lp.station);
    const auto targets = read_robot_program(programs, stem, dialect);
    const MassProperties payload = combined(ps.gripper, transformed(ps.blade, lp.cell->grip));
    const RobotVerifyReport r =
        verify_robot_program(*lp.cell, st, lp.plan, targets, dialect, position_tol, angle_tol, &payload);
    if (!r.problems.empty()) {
      std::string msg = "plan:write_program: the program read back does not replay the plan (" +
                        std::to_string(r.problems.size()) + " problem(s)); nothing written";
      for (size_t i = 0; i < r.problems.size() && i < 5; ++i) msg += "\n  " + r.problems[i];
      throw Error(msg);
    }
    size_t largest = 0, total = 0;
    for (const std::string& name : order) {
      write_file_atomic(dir + name + ext, programs[name]);
      largest = std::max(largest, programs[name].size());
      total += programs[name].size();
    }
    {
      // --verify prints this line after the run.
      const WheelContactReport& w = lp.plan.wheel;
      std::ostringstream line;
      line << path << ": " << r.moves << " moves in " << order.size() << " file(s) (largest " << largest
           << " bytes) replayed through the arm as the controller reads them, max contact deviation "
           << r.max_position_mm << " mm, max orientation deviation " << r.max_angle_deg << " deg, max joint deviation "
           << r.max_joint_deg << " deg, " << r.configuration_flips << " configuration flips; wheel and belt clear of "
           << "the blade over " << w.poses << " poses (rubber conformity " << w.max_conformity_mm << " mm)";
      context(L).verified_programs.push_back(line.str());
    }
    lua_createtable(L, 0, 12);
    luax::set_string(L, "file", path);
    luax::set_string(L, "program", stem);
    lua_createtable(L, static_cast<int>(order.size()), 0);
    for (size_t i = 0; i < order.size(); ++i) {
      lua_pushstring(L, (order[i] + ext).c_str());
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "files");
    luax::set_number(L, "moves", r.moves);
    luax::set_number(L, "max_position", r.max_position_mm);
    luax::set_number(L, "max_angle", r.max_angle_deg);
    luax::set_number(L, "max_joint", r.max_joint_deg);
    luax::set_number(L, "configuration_flips", r.configuration_flips);
    luax::set_number(L, "bytes", static_cast<double>(largest));
    luax::set_number(L, "total_bytes", static_cast<double>(total));
    luax::set_number(L, "ori_speed", ps.ori_speed_deg_s);
    luax::set_number(L, "zone", ps.zone_mm);
    push_mass(L, payload);
    lua_setfield(L, -2, "payload");
    return 1;
  });
}

}  // namespace

void open_robot(lua_State* L) {
  static const luaL_Reg cell_methods[] = {{"name", w_cell_name},
                                          {"stations", w_cell_stations},
                                          {"forward", w_cell_forward},
                                          {"inverse", w_cell_inverse},
                                          {"plan_grinding", w_cell_plan_grinding},
                                          {nullptr, nullptr}};
  luax::register_type<LuaRobotCell>(L, cell_methods);
  static const luaL_Reg plan_methods[] = {{"report", w_robot_plan_report},
                                          {"moves", w_robot_plan_moves},
                                          {"write_program", w_robot_plan_write_program},
                                          {"cycle_time", w_robot_plan_cycle_time},
                                          {nullptr, nullptr}};
  luax::register_type<LuaRobotPlan>(L, plan_methods);
  static const luaL_Reg body_methods[] = {{"points", w_blade_body_points}, {nullptr, nullptr}};
  luax::register_type<LuaBladeBody>(L, body_methods);
  static const luaL_Reg functions[] = {{"robot_cell", w_robot_cell},
                                       {"blade_body", w_blade_body},
                                       {"mass_properties", w_mass_properties},
                                       {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
