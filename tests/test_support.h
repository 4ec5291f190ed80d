#pragma once
// Helpers shared by tests: running recipes in-process and through the
// bliskrun executable, temporary folders, and where real part data lives.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "core/common/types.h"
#include "core/tools/pose.h"
#include "core/tools/tool.h"

namespace bliskrun::test {

// A fresh empty folder under the system temp folder, removed at destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  // Writes `contents` to path()/name and returns the full path.
  std::string write(const std::string& name, const std::string& contents) const;

 private:
  std::string path_;
};

struct RecipeResult {
  int exit_code = -1;
  std::string output;  // stderr of the run (and stdout for the executable)
};

// Writes `lua` as <dir>/recipe.lua and runs it in-process with out folder
// <dir>/out and the given extra arguments (--set, --data, ... as for the CLI
// are not parsed here: use run_bliskrun for that). No time limit unless a
// test is about the limit: a limit would make the test depend on the
// machine's speed (a docs example outlasted 60 s beside a CPU hog); a hang
// is ctest's timeout's to catch.
RecipeResult run_recipe_text(const TempDir& dir, const std::string& lua, bool quiet = true,
                             double time_limit_s = 0, double memory_limit_mb = 1024);

// One bad recipe line and a substring its error message must hold.
struct RecipeErrorCase {
  const char* name;      // test name suffix
  const char* call;      // the Lua line
  const char* expected;  // substring of the message
};

// Runs `c.call` as line 2 of a recipe in `dir`: success means exit code 1 and
// a message with "recipe.lua:2:" and `c.expected` in it.
::testing::AssertionResult fails_at_line_2(const TempDir& dir, const RecipeErrorCase& c);

// Names parameterised error tests after RecipeErrorCase::name.
inline std::string error_case_name(const ::testing::TestParamInfo<RecipeErrorCase>& info) {
  return info.param.name;
}

// Runs the built executable with `args`; captures stdout+stderr.
RecipeResult run_bliskrun(const std::vector<std::string>& args);

// What every recipe run leaves for a person to look at (issue 19): a
// self-contained report.html in `out` (opening with the verdict, issue 37; tables, no external src/href) and the
// ParaView collection `pvd` whose every listed .vtp exists beside it.
::testing::AssertionResult has_run_report(const std::string& out, const std::string& pvd);

// The moves of an APT/CL file as the recipes write it: each GOTO/x,y,z,i,j,k
// line's tip and (normalised) axis, `rapid` when a RAPID line came before it.
struct AptMove {
  Vec3 tip = Vec3::Zero(), axis = Vec3::UnitZ();
  bool rapid = false;
};
std::vector<AptMove> read_apt_moves(const std::string& path);

// Folder of real part data (../shared/data beside the clone), or "" when absent.
std::string shared_data_dir();

// A flat-end (corner-radius) mill R / r with a flute of flute_mm, a shank
// 2R wide and shank_mm long, and a holder 6R wide and holder_mm long (0:
// none) — the edge finish's tool in the tests.
Tool flat_end_mill(double radius_mm, double corner_mm, double flute_mm, double shank_mm, double holder_mm = 0);

// The blisk paper's drum wheel (Table 3, wheel 2): 8 mm across, barrel
// radius 50 mm, head 4 mm, shank 6 x 96.
Tool paper_drum_wheel();

// A pose at `tip` whose axis leans tilt_rad from +z towards azimuth_rad.
ToolPose tilted_pose(const Vec3& tip, double tilt_rad, double azimuth_rad);

}  // namespace bliskrun::test
