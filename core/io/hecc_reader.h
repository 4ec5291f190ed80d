#pragma once
// NASA HECC centrifugal impeller (../shared/data/nasa_hecc_impeller/
// PROVENANCE.md): one file per blade section, hub -> shroud, each a single
// open-ended loop of rows X, R*THETA, R in inches under the header
// "X R*THETA R" (design intent: space separated) or "X,R*THETA,R" (as
// manufactured: comma separated); flow-path lines under the header "x r",
// tab separated, inches. 15 main + 15 splitter blades.
//
// The two sets wrap θ in opposite directions. The as-manufactured set follows
// the Read-Me's convention (θ positive in the direction of rotation, θ falls
// from LE to TE on a backswept blade); the design-intent set is mirrored here
// (θ -> -θ) so both come out in that one convention, and the sections say so
// (BladeSections::rotation_sign = +1: the rotor turns towards +θ).
#include <string>
#include <vector>

#include "core/io/blade_sections.h"

namespace bliskrun {

constexpr int kHeccMainBlades = 15;
constexpr int kHeccSplitterBlades = 15;

enum class HeccSet { design_intent, as_manufactured };
enum class HeccBlade { main, splitter };

// One section loop in mm, part frame. `mirror_theta` applies θ -> -θ.
// Throws DataError(file, line, ...) on malformed input.
std::vector<Vec3> parse_hecc_section(const std::string& text, const std::string& file_label, bool mirror_theta);
// A flow-path line as (z, r) in mm.
std::vector<Vec2> parse_hecc_flowpath(const std::string& text, const std::string& file_label);

// Reads the sections of one blade of one set from `impeller_dir` (the
// nasa_hecc_impeller folder), hub -> shroud, with the design-intent hub and
// shroud flow path (the only one supplied; for the cold as-manufactured set it
// is the hot path, an approximation of a few tenths of a mm).
BladeSections read_hecc_impeller(const std::string& impeller_dir, HeccSet set, HeccBlade blade);

}  // namespace bliskrun
