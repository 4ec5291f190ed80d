// bliskrun.stock: the material-removal model (core/stock) — a blank of
// revolution that a job's moves cut, reporting what each cut removed, the
// air it cut, its engagement, and what is left.
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/stock/stock.h"
#include "lua_api/lua_tool.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;
using luax::number_field;

struct StockHandle {
  Stock stock;
};

}  // namespace
}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <>
struct TypeName<lua_api::StockHandle> {
  static constexpr const char* name = "bliskrun.Stock";
};
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {

namespace {

// {{r, z}, ...} -> points.
std::vector<Vec2> stock_read_profile(lua_State* L, int idx, const std::string& what) {
  idx = lua_absindex(L, idx);
  std::vector<Vec2> out;
  const lua_Integer n = luaL_len(L, idx);
  if (n > BlankProfile::kMaxPoints) {
    luax::error(L, what + ": expected at most " + std::to_string(BlankProfile::kMaxPoints) + " points");
  }
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, i);
    const std::string name = what + "[" + std::to_string(i) + "]";
    if (!lua_istable(L, -1)) luax::error(L, name + ": expected {r, z}");
    lua_rawgeti(L, -1, 1);
    lua_rawgeti(L, -2, 2);
    if (!lua_isnumber(L, -2) || !lua_isnumber(L, -1)) luax::error(L, name + ": expected {r, z} (mm)");
    out.emplace_back(lua_tonumber(L, -2), lua_tonumber(L, -1));
    lua_pop(L, 3);
  }
  return out;
}

// bliskrun.stock{profile = {{r, z}, ...}, resolution = 0.5}
int w_stock(lua_State* L) {
  static const char* what = "bliskrun.stock";
  const luax::Options o(L, 1, what,
                        {Field{"profile", Kind::Table, true, std::nullopt, std::nullopt,
                               "the blank's meridian: a closed polygon {{r, z}, ...} about the part's Z axis, mm", {}},
                         number_field("resolution", "ray spacing of the three grids, mm (default 0.5)", 0.01, 100)});
  o.push_raw("profile");
  const std::vector<Vec2> profile = stock_read_profile(L, -1, std::string(what) + ": profile");
  lua_pop(L, 1);
  StockOptions so;
  so.resolution_mm = o.number("resolution", so.resolution_mm);
  return luax::guarded(L, [&] {
    luax::push_new(L, StockHandle{Stock(BlankProfile(profile), so)});
    return 1;
  });
}

// The moves of arg idx: a list of {kind =, tip =, axis =} or a plan (any
// value with a :moves() method).
Toolpath stock_read_moves(lua_State* L, int idx, const std::string& what) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) {
    if (lua_getfield(L, idx, "moves") != LUA_TFUNCTION) {
      luax::error(L, what + ": expected a list of moves {kind =, tip =, axis =} or a plan with :moves()");
    }
    lua_pushvalue(L, idx);
    lua_call(L, 1, 1);
    lua_replace(L, idx);
    if (!lua_istable(L, idx)) luax::error(L, what + ": the plan's :moves() did not return a list");
  }
  Toolpath moves;
  const lua_Integer n = luaL_len(L, idx);
  moves.reserve(static_cast<size_t>(n));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, i);
    const std::string name = what + "[" + std::to_string(i) + "]";
    if (!lua_istable(L, -1)) luax::error(L, name + ": expected {kind =, tip =, axis =}");
    Move m;
    lua_getfield(L, -1, "kind");
    const std::string kind = lua_isstring(L, -1) ? lua_tostring(L, -1) : "feed";
    lua_pop(L, 1);
    if (kind == "stop") {
      m.kind = Move::Kind::Stop;
    } else if (kind == "feed" || kind == "rapid") {
      m.kind = kind == "feed" ? Move::Kind::Feed : Move::Kind::Rapid;
      m.pose = pose_from_table(L, -1, name.c_str());
    } else {
      luax::error(L, name + ".kind: expected \"feed\", \"rapid\" or \"stop\", got \"" + kind + "\"");
    }
    moves.push_back(std::move(m));
    lua_pop(L, 1);
  }
  return moves;
}

void push_stock_result(lua_State* L, const CutResult& r, const Stock& s, bool per_move, double seconds) {
  lua_createtable(L, 0, 16);
  luax::set_number(L, "removed_mm3", r.removed_mm3);
  luax::set_number(L, "cut_mm", r.cut_mm);
  luax::set_number(L, "air_cut_mm", r.air_cut_mm);
  luax::set_number(L, "air_share", r.cut_mm > 0 ? r.air_cut_mm / r.cut_mm : 0);
  luax::set_number(L, "rapid_mm", r.rapid_mm);
  luax::set_number(L, "rapid_removed_mm3", r.rapid_removed_mm3);
  luax::set_integer(L, "rapid_cut_moves", r.rapid_cut_moves);
  luax::set_integer(L, "body_contact_moves", r.body_contact_moves);
  luax::set_number(L, "body_contact_max_mm3", r.body_contact_max_mm3);
  luax::set_integer(L, "samples", r.samples);
  luax::set_number(L, "volume_left_mm3", s.volume());
  luax::set_number(L, "seconds", seconds);
  lua_createtable(L, 0, 5);
  luax::set_number(L, "rate_max_mm2", r.rate_max_mm2);
  const double engaged = r.cut_mm - r.air_cut_mm;
  luax::set_number(L, "rate_mean_mm2", engaged > 0 ? r.removed_mm3 / engaged : 0);
  luax::set_number(L, "axial_max_mm", r.axial_max_mm);
  luax::set_number(L, "radial_max_mm", r.radial_max_mm);
  lua_setfield(L, -2, "engagement");
  if (per_move) {
    lua_createtable(L, static_cast<int>(r.moves.size()), 0);
    for (size_t i = 0; i < r.moves.size(); ++i) {
      const MoveCut& m = r.moves[i];
      lua_createtable(L, 0, 7);
      luax::set_number(L, "removed_mm3", m.removed_mm3);
      luax::set_number(L, "length_mm", m.length_mm);
      luax::set_number(L, "air_mm", m.air_mm);
      luax::set_number(L, "rate_max_mm2", m.rate_max_mm2);
      luax::set_number(L, "axial_mm", m.axial_mm);
      luax::set_number(L, "radial_mm", m.radial_mm);
      luax::set_number(L, "body_mm3", m.body_mm3);
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "moves");
  }
}

// stock:cut(moves | plan, tool [, {step=, air=, torus_tol=, check_body=, from=, per_move=}])
int w_stock_cut(lua_State* L) {
  static const char* what = "stock:cut";
  StockHandle& h = luax::check<StockHandle>(L, 1);
  const Toolpath moves = stock_read_moves(L, 2, std::string(what) + ": moves");
  const LuaTool* tool = luax::test<LuaTool>(L, 3);
  if (!tool) luax::error(L, std::string(what) + ": argument 2: expected a bliskrun.Tool");
  const luax::Options o(
      L, 4, what,
      {number_field("step", "largest cutter-point motion between samples, mm (default: the resolution); the material "
                            "sampling can leave is at most half of it thick", 0.001, 100),
       number_field("air", "a sample step removing less than this per mm of path cuts air, mm² (default 0.001)", 0, 1e6),
       number_field("torus_tol", "tangent-polygon tolerance of a bull-nose corner or barrel, mm (default 0.002)", 1e-5, 1),
       Field{"check_body", Kind::Boolean, false, std::nullopt, std::nullopt,
             "measure the shank and holder against the stock (default true)", {}},
       Field{"from", Kind::Table, false, std::nullopt, std::nullopt,
             "{tip =, axis =}: the pose the first move starts from (default: the first pose is placed)", {}},
       Field{"per_move", Kind::Boolean, false, std::nullopt, std::nullopt,
             "return each move's figures in .moves (default false)", {}},
       Field{"threads", Kind::Integer, false, 1, 256, "the grids cut side by side (default: the run's --threads)", {}}});
  CutOptions co;
  co.step_mm = o.number("step", 0);
  co.air_mm2 = o.number("air", co.air_mm2);
  co.torus_tol_mm = o.number("torus_tol", co.torus_tol_mm);
  co.check_body = o.boolean("check_body", true);
  co.threads = static_cast<int>(o.integer("threads", context(L).options.threads));
  const bool per_move = o.boolean("per_move", false);
  std::optional<ToolPose> from;
  if (o.has("from")) {
    o.push_raw("from");
    from = pose_from_table(L, -1, "stock:cut: option 'from'");
    lua_pop(L, 1);
  }
  return luax::guarded(L, [&] {
    const auto t0 = std::chrono::steady_clock::now();
    const CutResult r = h.stock.cut(moves, tool->tool, co, from ? &*from : nullptr, context(L).progress);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    push_stock_result(L, r, h.stock, per_move, seconds);
    return 1;
  });
}

int w_stock_volume(lua_State* L) {
  lua_pushnumber(L, luax::check<StockHandle>(L, 1).stock.volume());
  return 1;
}

// stock:info() -> {volume_mm3, blank_mm3, blank_exact_mm3, removed_mm3, resolution, rays, spans, memory_mb}
int w_stock_info(lua_State* L) {
  const Stock& s = luax::check<StockHandle>(L, 1).stock;
  lua_createtable(L, 0, 8);
  luax::set_number(L, "volume_mm3", s.volume());
  luax::set_number(L, "blank_mm3", s.blank_volume());
  luax::set_number(L, "blank_exact_mm3", s.blank_exact_volume());
  luax::set_number(L, "removed_mm3", s.blank_volume() - s.volume());
  luax::set_number(L, "resolution", s.resolution());
  luax::set_integer(L, "rays", s.ray_count());
  luax::set_integer(L, "spans", s.span_count());
  luax::set_number(L, "memory_mb", static_cast<double>(s.memory_bytes()) / (1 << 20));
  return 1;
}

// stock:material_above(point, normal [, max_mm]) -> mm, or nil where no ray has material near
int w_stock_material_above(lua_State* L) {
  const Stock& s = luax::check<StockHandle>(L, 1).stock;
  const Vec3 p = luax::check_vec3(L, 2, "point");
  const Vec3 n = luax::check_vec3(L, 3, "normal");
  const double max_mm = lua_isnoneornil(L, 4) ? 10.0 : luax::check_number(L, 4, "max_mm");
  return luax::guarded(L, [&] {
    const double d = s.material_above(p, n, max_mm);
    if (std::isnan(d)) {
      lua_pushnil(L);
    } else {
      lua_pushnumber(L, d);
    }
    return 1;
  });
}

// stock:copy() -> an independent stock in the same state
int w_stock_copy(lua_State* L) {
  const Stock& s = luax::check<StockHandle>(L, 1).stock;
  return luax::guarded(L, [&] {
    luax::push_new(L, StockHandle{s});
    return 1;
  });
}

}  // namespace

void open_stock(lua_State* L) {
  static const luaL_Reg methods[] = {{"cut", w_stock_cut},
                                     {"volume", w_stock_volume},
                                     {"info", w_stock_info},
                                     {"material_above", w_stock_material_above},
                                     {"copy", w_stock_copy},
                                     {nullptr, nullptr}};
  luax::register_type<StockHandle>(L, methods);
  static const luaL_Reg functions[] = {{"stock", w_stock}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
