// bliskrun.drum_wheel{...}, conical_drum_wheel, flat_end_mill, ball_end_mill,
// tapered_ball_end_mill, contact_wheel, and the Tool methods. Lengths in mm,
// angles in degrees (converted here). See docs/lua_api.md.
#include <cmath>
#include <limits>

#include "lua_api/lua_tool.h"
#include "lua_api/modules.h"

namespace bliskrun::lua_api {
namespace {

using luax::Field;
using luax::Kind;

Field length(const char* name, const char* doc, bool required = true) {
  return Field{name, Kind::Number, required, 0.0, std::nullopt, doc, {}};
}

// Fields every tool takes besides its own.
void add_common(std::vector<Field>& fields) {
  fields.push_back(Field{"shank", Kind::Table, false, std::nullopt, std::nullopt,
                         "{diameter=, length=} above the cutting part, mm", {}});
  fields.push_back(Field{"holder", Kind::Table, false, std::nullopt, std::nullopt,
                         "{diameter=, length=} above the shank, mm", {}});
  fields.push_back(Field{"collision_tol", Kind::Number, false, 1e-6, 1.0,
                         "tessellation tolerance of the collision body, mm (default 0.001)", {}});
}

CylinderSpec cylinder(lua_State* L, const luax::Options& o, const char* key, const std::string& what) {
  if (!o.has(key)) return {};
  o.push_raw(key);
  const luax::Options c(L, lua_gettop(L), what + "." + key,
                        {length("diameter", "diameter, mm"), length("length", "length along the axis, mm")});
  CylinderSpec spec{c.number("diameter", 0), c.number("length", 0)};
  lua_pop(L, 1);
  return spec;
}

// Validates the options at index 1 against the tool's fields plus the common
// ones, builds the tool with `make`, pushes the userdata.
template <class Make>
int construct(lua_State* L, const char* what, std::vector<Field> fields, Make make) {
  return luax::guarded(L, [&] {
    add_common(fields);
    const luax::Options o(L, 1, what, fields);
    const CylinderSpec shank = cylinder(L, o, "shank", what);
    const CylinderSpec holder = cylinder(L, o, "holder", what);
    LuaTool t{make(o, shank, holder), o.number("collision_tol", 1e-3), nullptr};
    luax::push_new(L, std::move(t));
    return 1;
  });
}

int w_drum_wheel(lua_State* L) {
  return construct(L, "bliskrun.drum_wheel",
                   {length("max_diameter", "D_t, largest diameter (mid-height), mm"),
                    length("barrel_radius", "R_c, barrel arc radius, mm, >= D_t/2"),
                    length("head_length", "L_c, height of the wheel head, mm")},
                   [](const luax::Options& o, const CylinderSpec& s, const CylinderSpec& h) {
                     return Tool::drum_wheel({o.number("max_diameter", 0), o.number("barrel_radius", 0),
                                              o.number("head_length", 0), s, h});
                   });
}

int w_conical_drum_wheel(lua_State* L) {
  return construct(L, "bliskrun.conical_drum_wheel",
                   {length("bottom_diameter", "diameter at the tip end, mm"),
                    length("top_diameter", "diameter at the shank end, mm"),
                    length("barrel_radius", "R_c, barrel arc radius, mm"),
                    length("head_length", "L_c, height of the wheel head, mm")},
                   [](const luax::Options& o, const CylinderSpec& s, const CylinderSpec& h) {
                     return Tool::conical_drum_wheel({o.number("bottom_diameter", 0), o.number("top_diameter", 0),
                                                      o.number("barrel_radius", 0), o.number("head_length", 0), s,
                                                      h});
                   });
}

int w_flat_end_mill(lua_State* L) {
  return construct(L, "bliskrun.flat_end_mill",
                   {length("radius", "R, tool radius, mm"),
                    length("corner_radius", "r, corner radius, mm, 0 (sharp) to R", false),
                    length("flute_length", "height of the cutting part, mm")},
                   [](const luax::Options& o, const CylinderSpec& s, const CylinderSpec& h) {
                     return Tool::flat_end_mill(
                         {o.number("radius", 0), o.number("corner_radius", 0), o.number("flute_length", 0), s, h});
                   });
}

int w_ball_end_mill(lua_State* L) {
  return construct(L, "bliskrun.ball_end_mill",
                   {length("radius", "ball radius, mm"), length("flute_length", "height of the cutting part, mm")},
                   [](const luax::Options& o, const CylinderSpec& s, const CylinderSpec& h) {
                     return Tool::ball_end_mill({o.number("radius", 0), o.number("flute_length", 0), s, h});
                   });
}

int w_tapered_ball_end_mill(lua_State* L) {
  return construct(L, "bliskrun.tapered_ball_end_mill",
                   {length("tip_radius", "radius of the ball at the tip, mm"),
                    Field{"half_angle", Kind::Number, true, 0.0, 89.999, "taper half angle, degrees", {}},
                    length("flute_length", "height of the cutting part, mm")},
                   [](const luax::Options& o, const CylinderSpec& s, const CylinderSpec& h) {
                     return Tool::tapered_ball_end_mill({o.number("tip_radius", 0),
                                                         deg_to_rad(o.number("half_angle", 0)),
                                                         o.number("flute_length", 0), s, h});
                   });
}

int w_contact_wheel(lua_State* L) {
  return construct(L, "bliskrun.contact_wheel",
                   {length("radius", "wheel radius, mm"), length("width", "wheel width along its axis, mm")},
                   [](const luax::Options& o, const CylinderSpec& s, const CylinderSpec& h) {
                     return Tool::contact_wheel({o.number("radius", 0), o.number("width", 0), s, h});
                   });
}

ToolPartId check_part(lua_State* L, int idx) {
  const std::string name = luax::check_string(L, idx, "part");
  for (int i = 0; i < kToolPartCount; ++i) {
    if (name == to_string(static_cast<ToolPartId>(i))) return static_cast<ToolPartId>(i);
  }
  luax::error(L, "part: expected \"cutter\", \"shank\" or \"holder\", got \"" + name + "\"");
}

void push_rz(lua_State* L, const Vec2& p) { luax::push(L, std::vector<double>{p.x(), p.y()}); }

int w_tool_description(lua_State* L) {
  luax::push(L, luax::check<LuaTool>(L, 1).tool.description());
  return 1;
}

int w_tool_kind(lua_State* L) {
  return luax::guarded(L, [&] {
    luax::push(L, std::string(to_string(luax::check<LuaTool>(L, 1).tool.kind())));
    return 1;
  });
}

int w_tool_tostring(lua_State* L) {
  return luax::guarded(L, [&] {
    luax::push(L, luax::check<LuaTool>(L, 1).tool.description());
    return 1;
  });
}

int w_tool_radius_at(lua_State* L) {
  return luax::guarded(L, [&] {
    const Tool& t = luax::check<LuaTool>(L, 1).tool;
    luax::push(L, t.radius_at(luax::check_number(L, 2, "z")));
    return 1;
  });
}

int w_tool_signed_distance(lua_State* L) {
  return luax::guarded(L, [&] {
    const Tool& t = luax::check<LuaTool>(L, 1).tool;
    const Vec3 p = luax::check_vec3(L, 2, "point");
    luax::push(L, lua_isnoneornil(L, 3) ? t.signed_distance(p) : t.signed_distance(p, check_part(L, 3)));
    return 1;
  });
}

int w_tool_effective_radius(lua_State* L) {
  return luax::guarded(L, [&] {
    const Tool& t = luax::check<LuaTool>(L, 1).tool;
    const double z = luax::check_number(L, 2, "z");
    const double angle = deg_to_rad(luax::check_number(L, 3, "angle"));
    luax::push(L, t.effective_radius(z, angle));
    return 1;
  });
}

int w_tool_cut_width(lua_State* L) {
  return luax::guarded(L, [&] {
    const Tool& t = luax::check<LuaTool>(L, 1).tool;
    const luax::Options o(L, 2, "Tool:cut_width",
                          {Field{"residual", Kind::Number, true, 0.0, std::nullopt, "allowed residual height, mm", {}},
                           Field{"curvature", Kind::Number, false, std::nullopt, std::nullopt,
                                 "surface normal curvature along the tool axis, 1/mm (> 0 concave)", {}},
                           Field{"z", Kind::Number, false, std::nullopt, std::nullopt,
                                 "contact height on the profile, mm (default: the flank contact height)", {}}});
    const CutWidth w = t.cut_width(o.number("z", t.flank_contact_height()), o.number("curvature", 0),
                                   o.number("residual", 0));
    lua_createtable(L, 0, 3);
    luax::push(L, w.width_mm);
    lua_setfield(L, -2, "width");
    push_rz(L, w.a);
    lua_setfield(L, -2, "a");
    push_rz(L, w.b);
    lua_setfield(L, -2, "b");
    return 1;
  });
}

int w_tool_flank_contact_height(lua_State* L) {
  return luax::guarded(L, [&] {
    luax::push(L, luax::check<LuaTool>(L, 1).tool.flank_contact_height());
    return 1;
  });
}

int w_tool_reach(lua_State* L) {
  return luax::guarded(L, [&] {
    luax::push(L, luax::check<LuaTool>(L, 1).tool.reach());
    return 1;
  });
}

int w_tool_profile(lua_State* L) {
  return luax::guarded(L, [&] {
    const Tool& t = luax::check<LuaTool>(L, 1).tool;
    const ToolPartId part = lua_isnoneornil(L, 2) ? ToolPartId::Cutter : check_part(L, 2);
    const std::vector<ProfileElement>& elements = t.profile(part).elements();
    lua_createtable(L, static_cast<int>(elements.size()), 0);
    for (size_t i = 0; i < elements.size(); ++i) {
      const ProfileElement& e = elements[i];
      lua_createtable(L, 0, 5);
      luax::push(L, std::string(e.kind == ProfileElement::Kind::Arc ? "arc" : "segment"));
      lua_setfield(L, -2, "kind");
      push_rz(L, e.start);
      lua_setfield(L, -2, "from");
      push_rz(L, e.end);
      lua_setfield(L, -2, "to");
      if (e.kind == ProfileElement::Kind::Arc) {
        push_rz(L, e.centre);
        lua_setfield(L, -2, "centre");
        luax::push(L, e.radius);
        lua_setfield(L, -2, "radius");
      }
      lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    return 1;
  });
}

const luaL_Reg kToolMethods[] = {{"kind", w_tool_kind},
                                 {"description", w_tool_description},
                                 {"radius_at", w_tool_radius_at},
                                 {"signed_distance", w_tool_signed_distance},
                                 {"effective_radius", w_tool_effective_radius},
                                 {"cut_width", w_tool_cut_width},
                                 {"flank_contact_height", w_tool_flank_contact_height},
                                 {"reach", w_tool_reach},
                                 {"profile", w_tool_profile},
                                 {nullptr, nullptr}};

const luaL_Reg kToolFunctions[] = {{"drum_wheel", w_drum_wheel},
                                   {"conical_drum_wheel", w_conical_drum_wheel},
                                   {"flat_end_mill", w_flat_end_mill},
                                   {"ball_end_mill", w_ball_end_mill},
                                   {"tapered_ball_end_mill", w_tapered_ball_end_mill},
                                   {"contact_wheel", w_contact_wheel},
                                   {nullptr, nullptr}};

}  // namespace

void open_tools(lua_State* L) {
  luax::register_type(L, luax::TypeName<LuaTool>::name, kToolMethods, &luax::gc_value<LuaTool>, w_tool_tostring);
  luaL_setfuncs(L, kToolFunctions, 0);
}

}  // namespace bliskrun::lua_api
