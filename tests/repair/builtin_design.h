#pragma once
// Blade 0 of the built-in blisk as the repair tests' design: 25 sections,
// built once per test binary, and a damaged blade's scan and rebuild against
// it. Shared by the damaged-blade, damaged-region and rebuild-check tests.
#include "core/parts/builtin_blisk.h"
#include "core/repair/damaged_blade.h"
#include "core/repair/damaged_rebuild.h"

namespace bliskrun::test {

inline const DesignBlade& builtin_blade_design() {
  static const DesignBlade d = builtin_design_blade(BuiltinBlisk(), 0, 25);
  return d;
}

// A damaged blade measured in `sections` sections of `points` points (the
// other MeasurementOptions as they default) and rebuilt against the built-in
// design: the tests' scan, then rebuild.
struct MeasuredRebuild {
  SectionMeasurement m;
  DamagedRebuild r;
};
inline MeasuredRebuild measure_and_rebuild(const DamagedBlade& blade, int sections, int points) {
  MeasurementOptions mo;
  mo.sections = sections;
  mo.points = points;
  SectionMeasurement m = measure_sections(blade, mo);
  DamagedRebuild r = rebuild_damaged(m, builtin_blade_design());
  return {std::move(m), std::move(r)};
}

}  // namespace bliskrun::test
