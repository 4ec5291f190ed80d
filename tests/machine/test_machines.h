#pragma once
// Machines the machine tests share: one per configuration, with pivots off
// the origin so that every offset term of the kinematics is exercised.
#include <random>
#include <string>
#include <vector>

#include "core/machine/kinematics.h"

namespace bliskrun::test {

inline RotaryAxis rotary(const std::string& name, AxisCarrier carrier, Vec3 direction, Vec3 pivot,
                         double min_deg, double max_deg) {
  RotaryAxis a;
  a.name = name;
  a.carrier = carrier;
  a.direction = direction.normalized();
  a.pivot_mm = pivot;
  a.min_rad = deg_to_rad(min_deg);
  a.max_rad = deg_to_rad(max_deg);
  return a;
}

inline RotaryAxis continuous(const std::string& name, AxisCarrier carrier, Vec3 direction, Vec3 pivot) {
  RotaryAxis a = rotary(name, carrier, direction, pivot, 0, 1);
  a.min_rad = -std::numeric_limits<double>::infinity();
  a.max_rad = std::numeric_limits<double>::infinity();
  return a;
}

inline MachineDefinition base(const std::string& name) {
  MachineDefinition m;
  m.name = name;
  m.linear = {{"X", -1e4, 1e4}, {"Y", -1e4, 1e4}, {"Z", -1e4, 1e4}};
  return m;
}

// A/C trunnion: the A cradle (about X) carries the C table (about Z).
inline MachineDefinition table_table_ac() {
  MachineDefinition m = base("test A/C trunnion");
  m.rotary = {rotary("A", AxisCarrier::Part, Vec3::UnitX(), {0, 0, -80}, -120, 30),
              continuous("C", AxisCarrier::Part, Vec3::UnitZ(), {0, 3, 0})};
  m.part_origin_mm = {2, -1, 40};
  return m;
}

// B/C trunnion: the B cradle (about Y) carries the C table.
inline MachineDefinition table_table_bc() {
  MachineDefinition m = base("test B/C trunnion");
  m.rotary = {rotary("B", AxisCarrier::Part, Vec3::UnitY(), {0, 0, -60}, -5, 110),
              continuous("C", AxisCarrier::Part, Vec3::UnitZ(), {1.5, 0, 0})};
  m.part_origin_mm = {0, 0, 25};
  return m;
}

// Head-table: C table, B head pivoting 180 mm above the gauge point.
inline MachineDefinition head_table_bc() {
  MachineDefinition m = base("test B head / C table");
  m.rotary = {continuous("C", AxisCarrier::Part, Vec3::UnitZ(), {0, 0, 0}),
              rotary("B", AxisCarrier::Tool, Vec3::UnitY(), {0, 0, 180}, -110, 110)};
  m.part_origin_mm = {0, 0, 15};
  return m;
}

// Head-head gantry: a C fork carrying an A head, fork offset 5 mm in X.
inline MachineDefinition head_head_ca() {
  MachineDefinition m = base("test C/A head");
  m.rotary = {rotary("C", AxisCarrier::Tool, Vec3::UnitZ(), {5, 0, 0}, -360, 360),
              rotary("A", AxisCarrier::Tool, Vec3::UnitX(), {0, 0, 250}, -100, 100)};
  m.tool_length = ToolLengthMode::Gauge;
  return m;
}

inline std::vector<MachineDefinition> all_machines() {
  return {table_table_ac(), table_table_bc(), head_table_bc(), head_head_ca()};
}

// Rotary angles drawn within travel (continuous axes: one turn either way).
inline std::array<double, 2> random_rotary(const MachineDefinition& m, std::mt19937& rng) {
  std::array<double, 2> r{};
  for (int i = 0; i < 2; ++i) {
    const RotaryAxis& a = m.rotary[i];
    const double lo = a.continuous() ? -2 * kPi : a.min_rad, hi = a.continuous() ? 2 * kPi : a.max_rad;
    r[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return r;
}

inline double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace bliskrun::test
