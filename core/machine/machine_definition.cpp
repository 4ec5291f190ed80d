#include "core/machine/machine_definition.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"

namespace bliskrun {

namespace {

bool finite(const Vec3& v) { return v.allFinite(); }

void check_unit(const Vec3& v, const std::string& field) {
  if (!finite(v) || std::abs(v.norm() - 1.0) > 1e-9)
    throw ParameterError(field, "expected a unit vector, got norm " + std::to_string(v.norm()));
}

}  // namespace

std::vector<std::string> body_frames(const MachineDefinition& m) {
  std::vector<std::string> frames{"base"};
  for (const LinearAxis& a : m.linear) frames.push_back(a.name);
  for (const RotaryAxis& a : m.rotary) frames.push_back(a.name);
  frames.push_back("spindle");
  frames.push_back("part");
  return frames;
}

void validate(const MachineDefinition& m) {
  static const char* kLinear[] = {"X", "Y", "Z"};
  if (m.linear.size() != 3)
    throw ParameterError("linear", "expected the three axes X, Y, Z, got " +
                                       std::to_string(m.linear.size()));
  for (int i = 0; i < 3; ++i) {
    const LinearAxis& a = m.linear[i];
    const std::string field = "linear[" + std::to_string(i + 1) + "]";
    if (a.name != kLinear[i])
      throw ParameterError(field + ".name", "expected '" + std::string(kLinear[i]) + "', got '" +
                                                a.name + "'");
    if (std::isnan(a.min_mm) || std::isnan(a.max_mm) || !(a.min_mm < a.max_mm))
      throw ParameterError(field, "expected min < max");
  }
  if (m.rotary.size() != 2)
    throw ParameterError("rotary", "expected two rotary axes (5-axis machine), got " +
                                       std::to_string(m.rotary.size()));
  for (int i = 0; i < 2; ++i) {
    const RotaryAxis& a = m.rotary[i];
    const std::string field = "rotary[" + std::to_string(i + 1) + "]";
    if (a.name != "A" && a.name != "B" && a.name != "C")
      throw ParameterError(field + ".name", "expected A, B or C, got '" + a.name + "'");
    check_unit(a.direction, field + ".direction");
    if (!finite(a.pivot_mm)) throw ParameterError(field + ".pivot", "expected finite numbers");
    if (std::isnan(a.min_rad) || std::isnan(a.max_rad) || !(a.min_rad < a.max_rad))
      throw ParameterError(field, "expected min < max");
  }
  for (int i = 0; i < 2; ++i) {
    const RotaryAxis& a = m.rotary[i];
    if (a.iso841_sense == 0) continue;
    const int sense = iso841_sense(m, i);
    if (sense != a.iso841_sense) {
      const char* machine_axis = a.name == "A" ? "+X" : a.name == "B" ? "+Y" : "+Z";
      throw ParameterError(
          "rotary[" + std::to_string(i + 1) + "].iso841",
          std::string("stated ") + (a.iso841_sense > 0 ? "true" : "false") + ", but as defined (" +
              (a.carrier == AxisCarrier::Part ? "a table" : "a head") + " turning " +
              (a.carrier == AxisCarrier::Part ? "the part" : "the tool") + " right-handed about its direction) a positive " +
              a.name + " turns the tool relative to the part " + (sense > 0 ? "right" : "left") +
              "-handed about " + machine_axis + ", " + (sense > 0 ? "as" : "the reverse of") +
              " ISO 841's +" + a.name);
    }
  }
  if (!(m.rapid.feed_mm_per_min > 0) || !std::isfinite(m.rapid.feed_mm_per_min))
    throw ParameterError("rapid.feed", "expected a rapid feed > 0 mm/min");
  if (m.rotary[0].name == m.rotary[1].name)
    throw ParameterError("rotary[2].name", "both rotary axes are named " + m.rotary[0].name);
  if (m.rotary[0].direction.cross(m.rotary[1].direction).norm() < 1e-6)
    throw ParameterError("rotary[2].direction",
                         "parallel to rotary[1]: the two rotary axes cannot orient the tool");
  check_unit(m.spindle, "spindle");
  // The axis whose rotation acts on the spindle first is the innermost tool
  // axis if there is one, else the outermost table axis (the chain as seen
  // from the tool). Parallel to the spindle, it would only spin the tool.
  int first = -1;
  for (int i = 1; i >= 0; --i)
    if (m.rotary[i].carrier == AxisCarrier::Tool) { first = i; break; }
  if (first < 0) first = 0;
  if (m.rotary[first].direction.cross(m.spindle).norm() < 1e-6)
    throw ParameterError("rotary[" + std::to_string(first + 1) + "].direction",
                         "parallel to the spindle: this axis cannot tilt the tool");
  if (!finite(m.part_origin_mm)) throw ParameterError("part_origin", "expected finite numbers");
  if (!(m.linear_resolution_mm > 0) || !(m.rotary_resolution_rad > 0))
    throw ParameterError("resolution", "expected positive resolutions");
  std::vector<int> slides = m.tool_slides;
  slides.insert(slides.end(), m.part_slides.begin(), m.part_slides.end());
  std::sort(slides.begin(), slides.end());
  if (slides != std::vector<int>{0, 1, 2})
    throw ParameterError("slides", "expected each of X, Y, Z once, on the tool side or the part side");
  if (std::find(m.part_slides.begin(), m.part_slides.end(), 2) != m.part_slides.end())
    throw ParameterError("slides.part", "the Z slide carries the spindle (its word sets the tool length's place): "
                                        "put Z on the tool side");
  validate_bodies(m.bodies, body_frames(m), "bodies");
}

int iso841_sense(const MachineDefinition& m, int i) {
  const RotaryAxis& a = m.rotary[i];
  const Vec3 machine_axis = a.name == "A" ? Vec3::UnitX() : a.name == "B" ? Vec3::UnitY() : Vec3::UnitZ();
  const double along = a.direction.dot(machine_axis) * (a.carrier == AxisCarrier::Part ? -1 : 1);
  return along >= 0 ? 1 : -1;
}

std::string configuration_name(const MachineDefinition& m) {
  int tool = 0;
  for (const RotaryAxis& a : m.rotary) tool += a.carrier == AxisCarrier::Tool;
  return tool == 0 ? "table-table" : tool == 1 ? "head-table" : "head-head";
}

}  // namespace bliskrun
