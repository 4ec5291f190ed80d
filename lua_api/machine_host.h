#pragma once
// Machine definition files and post-processors: the Lua side of
// core/machine, on the plain Lua API (wrap_machine.cpp binds it to the
// `bliskrun.machine` / `bliskrun.post` tables).
//
// Machine files (scripts/machines/*.lua, or a recipe's own) run with four
// extra globals:
//   machine { ... }        validates a definition (degrees, mm) and returns it;
//   parametric { parameters = {name = {default=, doc=}, ...}, build = f }
//                          a generic definition: call it with a table of
//                          parameters (unknown names are errors) to build;
//   generic "name"         the parametric definition in scripts/machines/name.lua;
//   machine_lib "name"     what machine files share, scripts/machines/lib/name.lua
//                          (five_axis: the generic files' common parameters,
//                          machine fields and bodies).
// Every error names the machine file and line.
//
// Post files (scripts/posts/*.lua) run with `extend "name"`, which returns a
// copy of another post's table to override steps in (see scripts/posts/base.lua),
// and `fixed(value, decimals)`, string.format("%.<decimals>f") exactly but
// several times cheaper and never "-0.000" (core/common/fixed_text.h).
#include <lua.hpp>

#include <limits>
#include <string>
#include <vector>

#include "core/machine/kinematics.h"
#include "core/machine/motion.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

// The userdata every machine value is: a validated definition.
struct MachineValue {
  MachineDefinition definition;
  std::string source;  // file it was loaded from
};
inline constexpr const char* kMachineType = "bliskrun.Machine";

// Creates (once) the metatable of MachineValue with __gc; wrap_machine adds
// the methods.
void ensure_machine_type(lua_State* L);
MachineValue& push_machine(lua_State* L, MachineValue value);
MachineValue* test_machine(lua_State* L, int idx);
// The machine at idx (a Lua error naming the type otherwise), and a table of
// axis values {X=, Y=, Z=, <rotaries in deg>=} read for that machine, the
// argument `name` in messages. (wrap_machine.cpp)
MachineValue& check_machine(lua_State* L, int idx);
MachineAxes check_axes(lua_State* L, int idx, const MachineDefinition& m, const char* name);

// Runs a machine file; if it returns a parametric definition, builds it with
// the parameter table at `params_idx` (0: none, defaults). Pushes the
// MachineValue. Raises a Lua error at file:line on any problem.
void load_machine_file(lua_State* L, const std::string& path, int params_idx,
                       const std::string& machines_dir);

// Reads the definition table at `idx` (the argument of machine{}): raises a
// Lua error at the caller's line naming the key and what was expected.
MachineDefinition check_machine_table(lua_State* L, int idx);

// Reads a list of bodies { {name=, frame=, box=|cylinder=|cone=, radius=}, ... }
// (machine_bodies.h; frame defaults to `default_frame`): a Lua error naming
// "<what>[i].<key>" and what was expected.
std::vector<MachineBody> check_bodies(lua_State* L, int idx, const std::string& what, const std::string& default_frame);

// Loads a post file and pushes its module table.
void load_post_file(lua_State* L, const std::string& path, const std::string& posts_dir);

// The scripts folder (machines/, posts/, lib/): $BLISKRUN_SCRIPTS or the
// source tree's. "name" -> scripts/<kind>/name.lua (an error naming the kind
// if absent); anything with a '/' or ".lua" is a recipe path, resolved and
// confined by the runner. (wrap_machine.cpp)
std::string scripts_folder();
std::string resolve_script(lua_State* L, const std::string& what, const std::string& kind);

// Pushes the post an option table names: a post name (scripts/posts/<name>.lua,
// loaded) or a post table (bliskrun.post.load, edited) left as it is.
// Returns its stack index; raises a Lua error naming `what` otherwise.
int push_post_option(lua_State* L, const luax::Options& o, const std::string& what);

// Runs a Lua file with `env_idx` as its environment; leaves its one result.
void run_script_file(lua_State* L, const std::string& path, int env_idx);

struct PostTool {
  int number = 1;
  double length_mm = 0;
  long spindle_rpm = 0;     // 0: no spindle word
};

// How the part sits in the program's setup, for the header. The path is
// already in the part frame; this says how the model was turned into it.
struct PostSetup {
  std::string name;         // which setup ("inlet down"); empty: not named
  bool flip = false;        // turned over: 180 deg about X
  double clocking_deg = 0;  // then turned about the part frame's +Z
};

struct PostJob {
  std::string name;             // program name
  std::vector<PostTool> tools;  // in the order MachineMove::tool indexes them; at least one
  int work_offset = 1;          // G54 = 1, G55 = 2, ...; the TNC's preset row
  std::string coolant;          // "flood", "mist", "through", "off"; empty: none written (the post's default)
  long program_number = 0;      // Fanuc O-number, the TNC's PGM name; 0: the post's default
  PostSetup setup;
  std::vector<std::string> notes;  // header lines of the recipe's own
};

// Runs post:write(job, out) for the post table at `post_idx` over `program`
// and returns the program text. `kin` gives the machine (and, for one tool,
// its kinematics). Lua errors propagate.
std::string run_post(lua_State* L, int post_idx, const Kinematics& kin,
                     const MachineProgram& program, const PostJob& job);

// The output mode a post asks for: its `tcp` field, overridden by `tcp_always`.
bool post_wants_tcp(lua_State* L, int post_idx);
bool post_tcp_always(lua_State* L, int post_idx);

// What a post says of its controller (fields of the post table):
//   orientation = "axis" | "vector"   how TCP moves the tool axis between
//                                     blocks (rotaries linear, e.g. PATHCTRL
//                                     AXIS; or the great circle, PATHCTRL
//                                     VECTOR); default "axis"
//   resets_rotary_display = true      the post writes a display reset of a
//                                     continuous rotary axis (step
//                                     rotary_reset, e.g. Heidenhain M94)
//   rotary_input_limit = deg          the largest rotary value the
//                                     controller takes (default: none)
struct PostTraits {
  bool tcp = false, tcp_always = false, vector = false, rotary_reset = false;
  double rotary_input_limit_deg = std::numeric_limits<double>::infinity();
};
PostTraits post_traits(lua_State* L, int post_idx);

// "X","Y","Z" then the rotary names; decimals from the resolution.
int decimals_for(double resolution);

}  // namespace bliskrun::lua_api
