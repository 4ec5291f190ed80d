#pragma once
// plan:moves() of the finishing plans whose moves are DrumFinishMove lists
// (the drum finish and the edge finish): one writer for both wrappers.
#include <vector>

#include "core/planning/drum_finish.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

// Pushes {{kind = "feed"|"rapid", motion =, tip =, axis =, row =}, ...} in
// the form bliskrun.post.write takes (rows 1-based). A refused link (Stop)
// ends the list there: nothing unproven is implied.
inline void push_finish_moves(lua_State* L, const std::vector<DrumFinishMove>& moves) {
  lua_newtable(L);
  lua_Integer n = 0;
  for (const DrumFinishMove& m : moves) {
    if (m.kind == DrumFinishMove::Kind::Stop) break;
    lua_createtable(L, 0, 5);
    luax::set_string(L, "kind", m.kind == DrumFinishMove::Kind::Feed ? "feed" : "rapid");
    luax::set_string(L, "motion", m.motion);
    luax::set_vec3(L, "tip", m.pose.tip);
    luax::set_vec3(L, "axis", m.pose.axis);
    lua_pushinteger(L, m.row + 1);
    lua_setfield(L, -2, "row");
    lua_rawseti(L, -2, ++n);
  }
}

}  // namespace bliskrun::lua_api
