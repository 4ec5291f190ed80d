// Impellers in Lua (impeller paper §2–3): bliskrun.impeller{...} -> Impeller,
// built in (parametric) or from a camber-data file; faces and hub as
// surfaces, the camber data writable in the paper's format.
#include <memory>
#include <sstream>
#include <string>

#include "core/common/error.h"
#include "core/io/camber_data.h"
#include "core/parts/impeller.h"
#include "core/parts/ruled_fit.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {
struct ImpellerHandle {
  std::shared_ptr<const Impeller> impeller;
  std::string source;  // "built-in" or the camber file
};
}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <> struct TypeName<lua_api::ImpellerHandle> { static constexpr const char* name = "bliskrun.Impeller"; };
}  // namespace bliskrun::luax

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;

const ImpellerHandle& check_impeller(lua_State* L) { return luax::check<ImpellerHandle>(L, 1); }

Field number_field(const char* name, double fallback, const char* doc) {
  std::ostringstream s;
  s << doc << "; default " << fallback;
  return Field{name, Kind::Number, false, std::nullopt, std::nullopt, s.str(), {}};
}

// The built-in parameters: recipe key, core field, and whether it is an
// angle (degrees in Lua). One table serves the declaration and the reading.
struct BuiltinKey {
  const char* name;
  double BuiltinImpellerParams::*field;
  bool angle;
  const char* doc;
};
const BuiltinKey kBuiltinKeys[] = {
    {"splitter_start", &BuiltinImpellerParams::splitter_start, false,
     "built-in: fraction of the meridional length where splitters start"},
    {"outlet_radius", &BuiltinImpellerParams::outlet_radius_mm, false, "built-in: outlet radius, mm"},
    {"outlet_width", &BuiltinImpellerParams::outlet_width_mm, false, "built-in: blade height at the outlet, mm"},
    {"inlet_z", &BuiltinImpellerParams::inlet_z_mm, false, "built-in: axial position of the inlet plane, mm"},
    {"hub_inlet_radius", &BuiltinImpellerParams::hub_inlet_radius_mm, false, "built-in: hub radius at the inlet, mm"},
    {"shroud_inlet_radius", &BuiltinImpellerParams::shroud_inlet_radius_mm, false,
     "built-in: shroud radius at the inlet, mm"},
    {"beta_inlet", &BuiltinImpellerParams::beta_inlet_rad, true,
     "built-in: blade angle from the meridional direction at the shroud inlet, degrees"},
    {"beta_outlet", &BuiltinImpellerParams::beta_outlet_rad, true, "built-in: backsweep at the outlet, degrees"},
    {"half_thickness_le", &BuiltinImpellerParams::half_thickness_le_mm, false,
     "built-in: half thickness at the leading edge, mm"},
    {"half_thickness_te", &BuiltinImpellerParams::half_thickness_te_mm, false,
     "built-in: half thickness at the trailing edge, mm"},
    {"half_thickness_max_hub", &BuiltinImpellerParams::half_thickness_max_hub_mm, false,
     "built-in: largest half thickness along the hub, mm"},
    {"half_thickness_max_shroud", &BuiltinImpellerParams::half_thickness_max_shroud_mm, false,
     "built-in: largest half thickness along the shroud, mm"},
};

// bliskrun.impeller{camber = "file" | built-in keys, hub_extension =}
int w_impeller(lua_State* L) {
  const BuiltinImpellerParams d;
  std::vector<Field> fields = {
      Field{"camber", Kind::String, false, std::nullopt, std::nullopt,
            "camber-data file (x y z h lists); without it the built-in impeller", {}},
      Field{"blades", Kind::Integer, false, 2, 200, "built-in: number of main blades; default 17", {}},
      Field{"splitters", Kind::Boolean, false, std::nullopt, std::nullopt,
            "built-in: with splitter blades; default true", {}},
      Field{"camber_points", Kind::Integer, false, 6, 1000, "built-in: camber points per curve; default 25", {}},
      number_field("hub_extension", ImpellerDefinition{}.hub_extension_mm,
                   "hub of revolution past the blades' LE and TE, mm")};
  for (const BuiltinKey& k : kBuiltinKeys)
    fields.push_back(number_field(k.name, k.angle ? rad_to_deg(d.*k.field) : d.*k.field, k.doc));
  const luax::Options o(L, 1, "bliskrun.impeller", fields);

  ImpellerHandle h;
  ImpellerDefinition def;
  if (o.has("camber")) {
    for (const Field& f : fields)
      if (f.name != "camber" && f.name != "hub_extension" && o.has(f.name))
        luax::error(L, "bliskrun.impeller: option '" + f.name +
                           "' is for the built-in impeller; with 'camber' the data file gives the blades");
    h.source = context(L).resolve_read(L, o.string("camber", ""));
    luax::guarded(L, [&] {
      def = read_camber_data(h.source);
      return 0;
    });
  } else {
    BuiltinImpellerParams p;
    p.blade_count = static_cast<int>(o.integer("blades", d.blade_count));
    p.splitters = o.boolean("splitters", d.splitters);
    p.camber_points = static_cast<int>(o.integer("camber_points", d.camber_points));
    for (const BuiltinKey& k : kBuiltinKeys) {
      const double fallback = k.angle ? rad_to_deg(d.*k.field) : d.*k.field;
      const double v = o.number(k.name, fallback);
      p.*k.field = k.angle ? deg_to_rad(v) : v;
    }
    h.source = "built-in";
    luax::guarded(L, [&] {
      def = builtin_impeller_definition(p);
      return 0;
    });
  }
  def.hub_extension_mm = o.number("hub_extension", def.hub_extension_mm);
  return luax::guarded(L, [&] {
    try {
      h.impeller = std::make_shared<const Impeller>(std::move(def));
    } catch (const ParameterError& e) {
      // Data that read well but make no impeller (lists of different
      // lengths): name the file as well as the list.
      if (h.source == "built-in") throw;
      throw Error(h.source + ": " + e.what());
    }
    luax::push_new(L, std::move(h));
    return 1;
  });
}

BladeKind check_kind(lua_State* L, int idx, const Impeller& imp) {
  if (lua_isnoneornil(L, idx)) return BladeKind::kMain;
  const std::string s = luax::check_string(L, idx, "blade kind");
  if (s == "main") return BladeKind::kMain;
  if (s == "splitter") {
    if (!imp.has_splitter()) luax::error(L, "argument 'blade kind': this impeller has no splitter blades");
    return BladeKind::kSplitter;
  }
  luax::error(L, "argument 'blade kind': expected \"main\" or \"splitter\", got \"" + s + "\"");
}

// imp:face(blade 1..N, "plus"|"minus" [, "main"|"splitter"]) -> Surface
int w_face(lua_State* L) {
  const Impeller& imp = *check_impeller(L).impeller;
  const long long k = luax::check_integer(L, 2, "blade");
  if (k < 1 || k > imp.blade_count())
    luax::error(L, "argument 'blade': " + std::to_string(k) + " is outside 1.." +
                       std::to_string(imp.blade_count()));
  const std::string s = luax::check_string(L, 3, "side");
  if (s != "plus" && s != "minus")
    luax::error(L, "argument 'side': expected \"plus\" or \"minus\", got \"" + s + "\"");
  const BladeKind kind = check_kind(L, 4, imp);
  return luax::guarded(L, [&] {
    push_surface(L, imp.face(kind, static_cast<int>(k - 1), s == "plus" ? CamberSide::kPlus : CamberSide::kMinus));
    return 1;
  });
}

int w_hub(lua_State* L) {
  const ImpellerHandle& h = check_impeller(L);
  // Shares the impeller's hub (aliasing constructor: no copy).
  push_surface(L, std::shared_ptr<const Surface>(h.impeller, &h.impeller->hub()));
  return 1;
}

int w_hub_meridian(lua_State* L) {
  push_meridian(L, check_impeller(L).impeller->hub_meridian());
  return 1;
}

int w_blade_count(lua_State* L) {
  lua_pushinteger(L, check_impeller(L).impeller->blade_count());
  return 1;
}

int w_has_splitter(lua_State* L) {
  lua_pushboolean(L, check_impeller(L).impeller->has_splitter());
  return 1;
}

int w_outer_radius(lua_State* L) {
  lua_pushnumber(L, check_impeller(L).impeller->outer_radius_mm());
  return 1;
}

// imp:write_camber(path) -> full path (in the out folder)
int w_write_camber(lua_State* L) {
  const ImpellerHandle& h = check_impeller(L);
  const std::string target = context(L).resolve_write(L, luax::check_string(L, 2, "path"));
  return luax::guarded(L, [&] {
    write_camber_data(h.impeller->definition(), target);
    lua_pushstring(L, target.c_str());
    return 1;
  });
}

// bliskrun.fit_ruled(grid [, {first_row =, last_row =}]) -> {max, rms, worst_row, worst_col, surface}
// (rows 1-based, default all)
int w_fit_ruled(lua_State* L) {
  const std::shared_ptr<const PointGrid> grid = luax::check<GridHandle>(L, 1).grid;
  const luax::Options o(L, 2, "bliskrun.fit_ruled",
                        {Field{"first_row", Kind::Integer, false, 1, 1e7, "first grid row fitted (hub end); default 1", {}},
                         Field{"last_row", Kind::Integer, false, 1, 1e7, "last grid row fitted (tip end); default the last", {}}});
  const int r0 = static_cast<int>(o.integer("first_row", 1)) - 1;
  const int r1 = static_cast<int>(o.integer("last_row", grid->rows)) - 1;
  return luax::guarded(L, [&] {
    const RuledFit f = fit_ruled(*grid, r0, r1);
    lua_createtable(L, 0, 5);
    luax::set_number(L, "max", f.max_mm);
    luax::set_number(L, "rms", f.rms_mm);
    luax::set_number(L, "worst_row", f.worst_row + 1);
    luax::set_number(L, "worst_col", f.worst_col + 1);
    push_surface(L, f.surface);
    lua_setfield(L, -2, "surface");
    return 1;
  });
}

int w_tostring(lua_State* L) {
  const ImpellerHandle& h = check_impeller(L);
  std::ostringstream s;
  s << "bliskrun.Impeller(" << h.impeller->blade_count() << " blades"
    << (h.impeller->has_splitter() ? " + splitters" : "") << ", outer r "
    << h.impeller->outer_radius_mm() << " mm, " << h.source << ")";
  lua_pushstring(L, s.str().c_str());
  return 1;
}

}  // namespace

void open_impeller(lua_State* L) {
  static const luaL_Reg methods[] = {{"blade_count", w_blade_count}, {"has_splitter", w_has_splitter},
                                     {"face", w_face},               {"hub", w_hub},
                                     {"hub_meridian", w_hub_meridian}, {"outer_radius", w_outer_radius},
                                     {"write_camber", w_write_camber}, {nullptr, nullptr}};
  luax::register_type(L, luax::TypeName<ImpellerHandle>::name, methods, &luax::gc_value<ImpellerHandle>,
                      w_tostring);
  static const luaL_Reg functions[] = {{"impeller", w_impeller}, {"fit_ruled", w_fit_ruled}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
