#pragma once
// How long a program runs: an estimate from the read-back blocks
// (program_reader.h) and the machine's axis limits (MachineDynamics).
//
// The model, block by block (every assumption is one a controller can beat
// or miss; the estimate is for planning the shop's day, not a promise):
//   - Rapids (G0, FMAX) stop at their end. Each axis moves its own distance
//     from rest to rest at its own limits — velocity, acceleration, jerk — as
//     a jerk-limited ("S-curve", 7-phase) profile; the block takes as long as
//     its slowest axis (the controllers' non-interpolated rapid).
//   - Feed moves (G1, L ... F) are interpolated: every axis moves in
//     proportion. A run of consecutive feed blocks is one motion with look-
//     ahead: the path speed is capped per block by F (mm/min along the XYZ
//     words' change; for a block that moves no linear axis, F in deg/min of
//     the rotaries' change, as Fanuc and Heidenhain read it; 1/F minutes with
//     G93) and by every axis' velocity limit; it changes at most at the
//     block's acceleration limit (the tightest axis' limit over its share of
//     the motion), forward and backward over the run (the junction speed
//     between two blocks is the lower of their caps, times the cosine of the
//     corner between their XYZ directions, never below zero: a chord-split
//     curve runs through, a right angle or a reversal stops). Jerk adds to each change of speed the time its acceleration
//     takes to build up and fall (a/j per change, or the S-curve's
//     2*sqrt(dv/j) when the acceleration limit is not reached). A run starts
//     and ends at rest (after a rapid, a tool change, a stop).
//   - A tool change (a T word or TOOL CALL of another tool than the one in
//     the spindle, the first one included) takes `tool_change_s`.
// Dwell, spindle run-up and M-code times are not modelled.
#include <string>
#include <vector>

#include "core/machine/machine_definition.h"
#include "core/machine/program_reader.h"

namespace bliskrun {

// One axis' limits, in its own units: mm (linear) or rad (rotary) per
// minute, per s^2, per s^3. Infinite: no limit from this axis.
struct AxisLimits {
  double velocity_per_min;
  double accel_per_s2;
  double jerk_per_s3;
};

// The limits the estimate uses for axis i (0-2 X Y Z, 3-4 the rotaries in
// chain order): the machine file's `dynamics`, else the documented defaults
// (MachineDynamics in machine_definition.h).
AxisLimits axis_limits(const MachineDefinition& machine, int axis);

// Seconds to move `distance` (> 0) from rest to rest at the limits: the
// jerk-limited profile's closed form (trapezoidal when jerk is infinite:
// L/v + v/a for a long move, 2*sqrt(L/a) for a short one).
double rest_to_rest_seconds(double distance, double velocity_per_s, double accel, double jerk);

struct BlockTime {
  double seconds = 0;
  enum class Kind { Rapid, Feed, ToolChange } kind = Kind::Feed;
};

struct CycleTime {
  double total_s = 0;
  double rapid_s = 0;        // positioning: G0 / FMAX blocks
  double cut_s = 0;          // feed blocks (cutting, and planned rapids posted as feeds)
  double tool_change_s = 0;  // tool changes
  int tool_changes = 0;
  // Per block of the program (same order as read_program's moves): its
  // time; a tool change is charged to the block that calls the new tool.
  std::vector<double> block_s;
  std::vector<double> block_tool_change_s;
  std::vector<bool> block_positioning;  // the block's time counts as positioning
};

struct CycleTimeOptions {
  MachineAxes start;  // the axes before the first block (ProgramReadOptions::start)
  // Per block: a feed block that positions (a planned rapid posted as a feed
  // move, MachineMove::positioning) — its time counts as positioning, not
  // cutting. Empty: none.
  std::vector<bool> positioning;
};

// The estimate for the moves read back from a program.
CycleTime estimate_cycle_time(const std::vector<ProgramMove>& moves, const MachineDefinition& machine,
                              const CycleTimeOptions& options = {});

}  // namespace bliskrun
