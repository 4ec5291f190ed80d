#pragma once
// An impeller's design data (impeller paper §2): per blade, the camber-
// surface points of the shroud and hub curves, each with the blade's half
// thickness there, and how the blades repeat. Data only: the camber-data
// reader produces it (core/io/camber_data.h), the impeller builder makes the
// part from it and checks it (Impeller, validate: core/parts/impeller.h).
// Millimetres, Z the impeller axis.
#include <optional>
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

struct CamberPoint {
  Vec3 p = Vec3::Zero();
  double half_thickness_mm = 0;  // h of the paper: half the blade thickness there
};

// One blade's design data. Both lists LE -> TE, at least 4 points each and
// as many points in both: hub point i and shroud point i lie on one ruling.
struct BladeCamber {
  std::vector<CamberPoint> shroud, hub;
};

struct ImpellerDefinition {
  BladeCamber main;
  std::optional<BladeCamber> splitter;
  int blade_count = 17;
  double splitter_offset_pitch = 0.5;  // splitter k sits at (k + this) pitches, (0, 1)
  // The hub of revolution runs this far past the main blade's LE and TE
  // along the hub curve's end tangents (a hub face reaches past the blades).
  double hub_extension_mm = 10.0;
};

}  // namespace bliskrun
