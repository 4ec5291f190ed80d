// Units at the Lua boundary (SPEC §2): lengths in millimetres, angles in
// degrees. `mm`, `um` and `deg` are globals so a recipe reads
// `chord_tol = 2*um`, `c_range = {-30*deg, 30*deg}`.
#include "core/common/types.h"
#include "lua_api/modules.h"

namespace bliskrun::lua_api {

void open_units(lua_State* L) {
  const struct {
    const char* name;
    double value;
  } units[] = {{"mm", 1.0}, {"um", 1e-3}, {"cm", 10.0}, {"m", 1000.0}, {"inch", 25.4},
               {"deg", 1.0}, {"rad", 180.0 / kPi}};
  for (const auto& u : units) {
    lua_pushnumber(L, u.value);
    lua_setglobal(L, u.name);
  }
  lua_pushstring(L, "0.1.0");
  lua_setfield(L, -2, "version");
}

}  // namespace bliskrun::lua_api
