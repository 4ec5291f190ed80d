#pragma once
// Impeller camber data (impeller paper §2): per blade, the camber-surface
// points of the shroud and hub curves with the half thickness there,
// "x y z h" in mm, each list ordered leading edge -> trailing edge.
//
//   # comments and blank lines anywhere
//   blades 17
//   main shroud 25          <- a list header: blade, curve, point count
//   x y z h                 <- that many lines
//   ...
//   main hub 25
//   ...
//   splitter shroud 21      <- optional, with "splitter hub"
//   ...
//   splitter hub 21
//   ...
//   splitter_offset 0.5     <- optional: splitter position in pitches
//
// Every failure is a DataError at file:line saying what was expected: a
// list of fewer than 4 points, a field that is not a finite number, h <= 0,
// a point that repeats its predecessor or turns back along the list (the
// curve must advance: consecutive chords at less than 90 degrees), a missing
// or repeated list, a blade whose hub and shroud lists differ in length.
#include <string>

#include "core/io/impeller_definition.h"

namespace bliskrun {

ImpellerDefinition parse_camber_data(const std::string& text, const std::string& label);
ImpellerDefinition read_camber_data(const std::string& path);

// The text parse_camber_data reads back to the same definition (17
// significant digits); hub_extension is not part of the data.
std::string format_camber_data(const ImpellerDefinition& d);
// Written atomically (core/common/atomic_file).
void write_camber_data(const ImpellerDefinition& d, const std::string& path);

}  // namespace bliskrun
