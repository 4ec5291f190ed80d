#pragma once
// Blade 0 of the built-in blisk as the repair tests' design: 25 sections,
// built once per test binary. Shared by the damaged-blade, damaged-region and
// rebuild-check tests.
#include "core/parts/builtin_blisk.h"
#include "core/repair/damaged_blade.h"

namespace bliskrun::test {

inline const DesignBlade& builtin_blade_design() {
  static const DesignBlade d = builtin_design_blade(BuiltinBlisk(), 0, 25);
  return d;
}

}  // namespace bliskrun::test
