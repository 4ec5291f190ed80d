#pragma once
// Blade models in Lua, shared by the part readers (wrap_io.cpp) and
// bliskrun.loft_sections (wrap_parts.cpp): the loft options every reader
// takes, and the one result table they all return.
#include <vector>

#include "core/io/blade_sections.h"
#include "core/parts/blade_model.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

// cols, edge_margin, span_extension.
std::vector<luax::Field> loft_fields();
LoftOptions loft_options(const luax::Options& o);

// Lofts `blade` and pushes {blades, sections, pressure, suction,
// hub_meridian, casing_meridian, hub, casing, hub_row, tip_row, rotation,
// rotation_from, camber_agrees, edges, fit} (docs/lua_api.md, "Blade models").
void push_blade_model(lua_State* L, const BladeSections& blade, const LoftOptions& options);

}  // namespace bliskrun::lua_api
