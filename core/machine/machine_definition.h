#pragma once
// A 5-axis machine as a value: three linear axes, two rotary axes, where each
// rotary axis sits in the kinematic chain, and the conventions a program for
// it follows.
//
// Frames. The machine frame has its origin at the program zero (the work
// offset the program runs in, G54) and its axes along the linear axes X, Y, Z.
// Everything below is given with all axes at zero ("home"): rotary directions,
// pivots, the spindle direction.
//
// Chain. A rotary axis is carried either by the part side (a table: it turns
// the part) or by the tool side (a head: it turns the spindle). The list
// `rotary` is in chain order from the machine base outwards on each side: on
// an A/C trunnion the A cradle carries the C table, so A comes first; on a
// head-head gantry the C fork carries the B head, so C comes first. The linear
// axes always express the motion of the tool relative to the machine frame
// (ISO convention: a positive X move takes the tool towards +X of the part,
// whichever slide moves).
//
// Tool length. XYZ with all rotaries at zero denote either the tool tip (the
// controller applies the length along the spindle, G43 H / TOOL CALL) or the
// spindle gauge point (the program carries the length itself). Head pivots are
// given relative to the gauge point, because that is where the head is
// measured; the tool length then decides how far the tip swings.
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/common/types.h"
#include "core/machine/machine_bodies.h"

namespace bliskrun {

enum class AxisCarrier { Part, Tool };
enum class ToolLengthMode { Tip, Gauge };
enum class FeedMode { PerMinute, InverseTime };  // G94 / G93

// Travel of a linear axis is that of the slide: the spindle gauge point at
// home orientation, machine frame — the same for any tool length.
struct LinearAxis {
  std::string name;  // "X", "Y", "Z" (machine direction +x, +y, +z)
  double min_mm = -std::numeric_limits<double>::infinity();
  double max_mm = std::numeric_limits<double>::infinity();
};

struct RotaryAxis {
  std::string name;                  // "A", "B" or "C"
  AxisCarrier carrier = AxisCarrier::Part;
  Vec3 direction = Vec3::UnitZ();    // unit, machine frame at home; positive = right-handed
  // A point on the axis line at home. Part-side axes: machine frame. Tool-side
  // axes: relative to the spindle gauge point at home.
  Vec3 pivot_mm = Vec3::Zero();
  // Travel. An infinite range is a continuous axis (any number of turns).
  double min_rad = -std::numeric_limits<double>::infinity();
  double max_rad = std::numeric_limits<double>::infinity();
  bool continuous() const { return std::isinf(max_rad - min_rad); }
  // What the machine file states about this axis against ISO 841: +1 "a
  // positive angle turns the tool relative to the part right-handed about the
  // machine's +X, +Y or +Z (for A, B, C)", -1 the reverse, 0 not stated.
  // validate() checks a statement against the geometry above.
  int iso841_sense = 0;
  // Fastest the axis turns (machine file `speed`, deg/min there); infinite
  // when not stated. Feed words keep every block within it (motion.h).
  double max_speed_rad_per_min = std::numeric_limits<double>::infinity();
};

// How the controller moves on a rapid (G0, FMAX). Each axis then runs at its
// own rate, so the tool follows the straight line the collision checks proved
// only where one linear axis moves, or where the controller is set to
// interpolate rapids linearly (`linear`: Fanuc parameter 1401#1 LRP, Siemens
// RTLION; Heidenhain L blocks and LinuxCNC always) and no rotary axis turns —
// a joint-linear rotary move still swings the tip off the line. Every other
// rapid is posted as a feed move at `feed_mm_per_min`, split to the chord
// tolerance like a cutting move (see motion.h).
struct RapidMotion {
  double feed_mm_per_min = 10000;
  bool linear = false;
};

// What the cycle-time estimate (cycle_time.h) takes of an axis: the machine
// file's `dynamics = {X = {max_velocity=, max_accel=, max_jerk=}, ...}`, in
// mm or rad per minute, per s^2, per s^3. NaN: not stated; then the
// defaults below apply (docs/lua_api/machines_and_posts.md).
struct AxisDynamics {
  double velocity_per_min = std::numeric_limits<double>::quiet_NaN();
  double accel_per_s2 = std::numeric_limits<double>::quiet_NaN();
  double jerk_per_s3 = std::numeric_limits<double>::quiet_NaN();
};

// Defaults for what a machine file does not state: moderate figures of a
// 5-axis machining centre, so an estimate errs on the slow side rather than
// promise a time no machine keeps. Linear: the rapid feed as top speed,
// 2 m/s^2, 50 m/s^3. Rotary: the axis' `speed` if stated, else 25 rpm;
// 1000 deg/s^2, 10000 deg/s^3. A tool change 8 s (chip to chip).
struct MachineDynamics {
  std::array<AxisDynamics, 5> axes;  // X, Y, Z, then the rotaries in chain order
  double tool_change_s = std::numeric_limits<double>::quiet_NaN();
  static constexpr double kLinearAccelMmPerS2 = 2000;
  static constexpr double kLinearJerkMmPerS3 = 50000;
  static constexpr double kRotarySpeedDegPerMin = 9000;
  static constexpr double kRotaryAccelDegPerS2 = 1000;
  static constexpr double kRotaryJerkDegPerS3 = 10000;
  static constexpr double kToolChangeS = 8;
};

struct MachineDefinition {
  std::string name;
  std::vector<LinearAxis> linear;    // X, Y, Z in this order
  std::vector<RotaryAxis> rotary;    // exactly two, chain order (see above)
  Vec3 spindle = Vec3::UnitZ();      // tool axis at home, from tip towards shank
  // Where the part frame's origin sits in the machine frame at home; the part
  // frame's axes are parallel to the machine's at home.
  Vec3 part_origin_mm = Vec3::Zero();
  ToolLengthMode tool_length = ToolLengthMode::Tip;
  FeedMode feed = FeedMode::PerMinute;
  RapidMotion rapid;
  // What the controller can represent; read-back adds it to the tolerance.
  double linear_resolution_mm = 0.001;
  double rotary_resolution_rad = deg_to_rad(0.001);
  // The safe height for retracts and tool changes, as the Z word (program
  // zero frame) with the tool axis along the spindle's home direction; NaN:
  // the top of the Z slide's travel (Kinematics::safe_z_mm). Everything on
  // the table (part, fixture) must lie below it.
  double safe_z_mm = std::numeric_limits<double>::quiet_NaN();
  // Axis limits for the cycle-time estimate only (no effect on the motion).
  MachineDynamics dynamics;
  // Which side each linear slide carries, base outwards (indices into
  // `linear`): the tool side (a column, a ram) or the part side (a table
  // slide). Together each of X, Y, Z once. Only the machine simulation
  // (machine_sim.h) asks: the kinematics see the tool move relative to the
  // part either way.
  std::vector<int> tool_slides{0, 1, 2};
  std::vector<int> part_slides;
  // The machine's own solids (machine_bodies.h); empty: not modelled.
  std::vector<MachineBody> bodies;
};

// The frames bodies of this machine can be fixed to (machine_bodies.h).
std::vector<std::string> body_frames(const MachineDefinition& machine);

// Checks the definition: three linear axes named X, Y, Z; two rotary axes with
// distinct names from A/B/C, unit directions, min < max; rotary axes not
// parallel to each other; the spindle not parallel to the axis that turns it
// first (else that axis cannot change the tool orientation). Throws
// ParameterError naming the offending field ("rotary[2].direction", ...).
void validate(const MachineDefinition& machine);

// The sense of rotary axis i against ISO 841, from the geometry: +1 when a
// positive angle turns the tool relative to the part right-handed about the
// machine axis the name denotes (A: +X, B: +Y, C: +Z), -1 when left-handed.
// A table axis turns the part, so the tool turns the other way relative to it.
int iso841_sense(const MachineDefinition& machine, int i);

// "table-table", "head-table" or "head-head", from the carriers.
std::string configuration_name(const MachineDefinition& machine);

}  // namespace bliskrun
