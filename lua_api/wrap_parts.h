#pragma once
// Blade models in Lua, shared by the part readers (wrap_io.cpp) and
// bliskrun.loft_sections (wrap_parts.cpp): the loft options every reader
// takes, and the one result table they all return; and the Blisk type,
// shared with bliskrun.cad_blisk (wrap_cad.cpp).
#include <memory>
#include <string>
#include <vector>

#include "core/io/blade_sections.h"
#include "core/parts/blisk_part.h"
#include "core/parts/blade_model.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

// cols, edge_margin, span_extension.
// The list of point lists at stack index t ({{{x, y, z}, ...}, ...}), each
// point checked finite; errors "<prefix>option '<option>': <item> K, point
// I: ..." (bliskrun.loft_sections' sections, damaged_blade's loops).
std::vector<std::vector<Vec3>> check_point_loops(lua_State* L, int t, const std::string& prefix, const char* option,
                                                 const char* item);
std::vector<luax::Field> loft_fields();
LoftOptions loft_options(const luax::Options& o);

// Lofts `blade` and pushes {blades, sections, pressure, suction,
// hub_meridian, casing_meridian, hub, casing, hub_row, tip_row, rotation,
// rotation_from, camber_agrees, edges, fit} (docs/lua_api.md, "Blade models").
void push_blade_model(lua_State* L, const BladeSections& blade, const LoftOptions& options);

// Pushes a Blisk (bliskrun.blisk{}'s type: blade_count, flank, flank_grid,
// hub, casing, hub_meridian, ..., narrowest_passage) for any BliskPart.
void push_blisk(lua_State* L, std::shared_ptr<const BliskPart> blisk);

}  // namespace bliskrun::lua_api
