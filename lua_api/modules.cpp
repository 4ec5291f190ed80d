#include "lua_api/modules.h"

namespace bliskrun::lua_api {

void open_all(lua_State* L) {
  lua_newtable(L);  // the `bliskrun` table
  open_units(L);
  open_files(L);
  open_vtk(L);
  open_report(L);
  open_geometry(L);
  open_io(L);
  open_cad(L);
  open_parts(L);
  open_impeller(L);
  open_analysis(L);
  open_tools(L);
  open_collision(L);
  open_planning(L);
  open_machine(L);
  open_post(L);
  open_edges(L);
  open_channel(L);
  open_sim(L);
  open_repair(L);
  open_repair_paths(L);
  open_hub_finish(L);
  open_point_mill(L);
  open_stock(L);
  open_flank(L);
  open_belt(L);
  open_robot(L);
  lua_setglobal(L, "bliskrun");
}

}  // namespace bliskrun::lua_api
