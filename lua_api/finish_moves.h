#pragma once
// plan:moves() of the plans whose program is a Toolpath with Stops
// (core/toolpath/move.h: the drum, edge and hub finishes): one writer for
// their wrappers.
#include <vector>

#include "core/toolpath/move.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

// Pushes {{kind = "feed"|"rapid", motion =, tip =, axis =, row =}, ...} in
// the form bliskrun.post.write takes (rows 1-based). A refused link (Stop)
// ends the list there: nothing unproven is implied.
inline void push_finish_moves(lua_State* L, const Toolpath& moves) {
  lua_newtable(L);
  lua_Integer n = 0;
  for (const Move& m : moves) {
    if (m.kind == Move::Kind::Stop) break;
    lua_createtable(L, 0, 5);
    luax::set_string(L, "kind", to_string(m.kind));
    luax::set_string(L, "motion", m.motion);
    luax::set_vec3(L, "tip", m.pose.tip);
    luax::set_vec3(L, "axis", m.pose.axis);
    luax::set_integer(L, "row", m.row + 1);
    lua_rawseti(L, -2, ++n);
  }
}

}  // namespace bliskrun::lua_api
