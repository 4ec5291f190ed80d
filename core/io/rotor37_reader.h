#pragma once
// NASA Rotor 37 in the AGARD table layout (../shared/data/nasa_rotor37/
// PROVENANCE.md, section 1): rotor37geometry.dat ("Table IV", 13 surfaces of
// 100 points J Z R THETA1 THETA2; Z, R in cm, θ in radians) and
// rotor37hub-shroud.dat ("Table V", arrays Zhub, Rhub, Zshroud, Rshroud in
// cm, 8 values a line). 36 blades (stated in pyturbo's Info.txt; the table
// does not state it).
//
// Each loop runs LE -> TE along THETA1 (the suction side) and back along
// THETA2 (the pressure side); J = 1 and J = 100, where THETA1 = THETA2, appear
// once, so a loop has 198 points.
#include <string>

#include "core/io/blade_sections.h"

namespace bliskrun {

constexpr int kRotor37BladeCount = 36;
constexpr int kRotor37Surfaces = 13;
constexpr int kRotor37PointsPerSurface = 100;

// Throws DataError(file, line, what was expected) on malformed input.
BladeSections read_rotor37(const std::string& geometry_path, const std::string& hub_shroud_path);
BladeSections parse_rotor37(const std::string& geometry_text, const std::string& geometry_label,
                            const std::string& hub_shroud_text, const std::string& hub_shroud_label);

}  // namespace bliskrun
