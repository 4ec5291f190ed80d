#pragma once
// Each lua_api/wrap_<subsystem>.cpp defines one open function that adds its
// functions and types to the `bliskrun` table at the top of the stack.
// modules.cpp calls them all, in this order; adding a subsystem = one line
// here and one in modules.cpp.
#include <lua.hpp>

namespace bliskrun::lua_api {

void open_units(lua_State* L);      // wrap_units.cpp: mm, um, deg globals
void open_files(lua_State* L);      // wrap_files.cpp: write_json, write_text, read paths
void open_geometry(lua_State* L);   // wrap_geometry.cpp
void open_io(lua_State* L);         // wrap_io.cpp: point-grid reader
void open_cad(lua_State* L);        // wrap_cad.cpp: read_cad (IGES, STEP through OpenCASCADE)
void open_parts(lua_State* L);      // wrap_parts.cpp: built-in blisk
void open_impeller(lua_State* L);   // wrap_impeller.cpp: impellers from camber data (built-in or file)
void open_analysis(lua_State* L);   // wrap_analysis.cpp: curvature stats, wheel design
void open_tools(lua_State* L);      // wrap_tools.cpp: drum wheels, mills, contact wheel
void open_collision(lua_State* L);  // wrap_collision.cpp: collision world, pose/motion checks, tilt
void open_planning(lua_State* L);   // wrap_planning.cpp: drum_finish, drum_finish_all, plan report/APT/simulation
void open_machine(lua_State* L);    // wrap_machine.cpp: machines, kinematics
void open_post(lua_State* L);       // wrap_post.cpp: posts, read-back and sweep, cycle time
void open_report(lua_State* L);     // wrap_report.cpp: report (one HTML page per run)
void open_vtk(lua_State* L);        // wrap_vtk.cpp: write_vtk (ParaView collection)
void open_flank(lua_State* L);      // wrap_flank.cpp: flank_mill (ruled faces: impeller flank finishing)
void open_belt(lua_State* L);       // wrap_belt.cpp: belt_paths (contact-wheel paths for robotic belt grinding)
void open_robot(lua_State* L);      // wrap_robot.cpp: robot_cell, plan_grinding, robot programs (RAPID, KRL)
void open_edges(lua_State* L);      // wrap_edges.cpp: edge_region, edge_finish (blade LE/TE with a flat-end bottom)
void open_channel(lua_State* L);    // wrap_channel.cpp: channel_rough (impeller notching and widening)
void open_sim(lua_State* L);        // wrap_sim.cpp: simulate (undercut of any surface, passes with their tools)
void open_repair(lua_State* L);     // wrap_repair.cpp: rebuild_sections (a blade lofted through measured sections)
void open_repair_paths(lua_State* L);  // wrap_repair_paths.cpp: close_blade, repair_paths (repair zigzag / spiral, offset layers)
void open_hub_finish(lua_State* L);  // wrap_hub_finish.cpp: hub_finish (blade root strip and channel floor, (tapered) ball end)
void open_point_mill(lua_State* L);  // wrap_point_mill.cpp: point_mill (five-axis point milling of a face, (tapered) ball end)
void open_stock(lua_State* L);      // wrap_stock.cpp: stock (the material-removal model: a blank of revolution cut by moves)

// Registers everything into a new global table `bliskrun`.
void open_all(lua_State* L);

}  // namespace bliskrun::lua_api
