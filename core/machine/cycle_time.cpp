// The cycle-time estimate (the model and its assumptions: cycle_time.h).
#include "core/machine/cycle_time.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace bliskrun {

namespace {

double stated_or(double value, double fallback) { return std::isnan(value) ? fallback : value; }

// Time an S-curve takes to change speed by dv >= 0 beyond dv/a (what the
// trapezoid already counts): the acceleration's ramp up and down, a/j when
// the acceleration limit is reached, else the whole 2*sqrt(dv/j) less dv/a.
double jerk_extra(double dv, double a, double j) {
  if (!(dv > 0) || std::isinf(j)) return 0;
  if (std::isinf(a)) return 2 * std::sqrt(dv / j);
  return dv >= a * a / j ? a / j : 2 * std::sqrt(dv / j) - dv / a;
}

// Seconds to cover `length` entering at v0 and leaving at v1 (both reachable:
// the look-ahead passes guarantee it), cruising at most at v, accelerating
// at most at a; plus the jerk's ramps.
double block_seconds(double length, double v0, double v1, double v, double a, double j) {
  if (!(length > 0)) return 0;
  if (std::isinf(a)) return length / v;
  const double peak = std::min(v, std::sqrt(std::max(0.0, (2 * a * length + v0 * v0 + v1 * v1) / 2)));
  const double up = (peak * peak - v0 * v0) / (2 * a), down = (peak * peak - v1 * v1) / (2 * a);
  const double cruise = std::max(0.0, length - up - down);
  return (peak - v0) / a + (peak - v1) / a + (peak > 0 ? cruise / peak : 0) + jerk_extra(peak - v0, a, j) +
         jerk_extra(peak - v1, a, j);
}

// One block's motion per axis: X Y Z (mm) and the rotaries (rad).
std::array<double, 5> axis_distances(const MachineAxes& from, const MachineAxes& to) {
  return {std::abs(to.linear_mm.x() - from.linear_mm.x()), std::abs(to.linear_mm.y() - from.linear_mm.y()),
          std::abs(to.linear_mm.z() - from.linear_mm.z()), std::abs(to.rotary_rad[0] - from.rotary_rad[0]),
          std::abs(to.rotary_rad[1] - from.rotary_rad[1])};
}

// A feed block as a path of `length` with its caps (length units per s,
// per s^2, per s^3): the path is the XYZ words' change in mm, or for a block
// that moves no linear axis the rotaries' change in deg.
struct FeedBlock {
  double length = 0, v = kInf, a = kInf, j = kInf;
  Vec3 direction = Vec3::Zero();  // of the XYZ words' change; zero when they do not change
};

FeedBlock feed_block(const ProgramMove& m, const Vec3& linear_change, const std::array<double, 5>& d,
                     const std::array<AxisLimits, 5>& lim) {
  FeedBlock b;
  const double linear = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const double rotary_deg = rad_to_deg(std::sqrt(d[3] * d[3] + d[4] * d[4]));
  b.length = linear > 1e-9 ? linear : rotary_deg;
  if (!(b.length > 1e-9)) return {};
  if (linear > 1e-9) b.direction = linear_change / linear;
  if (m.feed > 0)
    b.v = m.feed_mode == FeedMode::InverseTime ? b.length * m.feed / 60 : m.feed / 60;
  for (int i = 0; i < 5; ++i) {
    if (!(d[i] > 0)) continue;
    const double share = b.length / d[i];  // path units per axis unit
    b.v = std::min(b.v, lim[i].velocity_per_min / 60 * share);
    b.a = std::min(b.a, lim[i].accel_per_s2 * share);
    b.j = std::min(b.j, lim[i].jerk_per_s3 * share);
  }
  return b;
}

// A run of feed blocks from rest to rest: the look-ahead's junction speeds
// (backward, then forward), then each block's time.
void time_feed_run(const std::vector<FeedBlock>& run, std::vector<double>& seconds) {
  const size_t n = run.size();
  std::vector<double> exit(n, 0.0);
  for (size_t k = n; k-- > 0;) {
    if (k + 1 == n) {
      exit[k] = 0;
      continue;
    }
    const FeedBlock& next = run[k + 1];
    const double reach = std::isinf(next.a) ? kInf : std::sqrt(exit[k + 1] * exit[k + 1] + 2 * next.a * next.length);
    // A corner keeps the speed's component along the new direction (full
    // speed on a chord-split curve, none at a right angle or a reversal).
    const double turn = run[k].direction.dot(next.direction);
    const double corner = run[k].direction.isZero() || next.direction.isZero() ? 1.0 : std::max(0.0, turn);
    exit[k] = std::min({run[k].v, next.v, reach}) * corner;
  }
  double entry = 0;
  seconds.assign(n, 0.0);
  for (size_t k = 0; k < n; ++k) {
    const FeedBlock& b = run[k];
    if (!std::isinf(b.a)) exit[k] = std::min(exit[k], std::sqrt(entry * entry + 2 * b.a * b.length));
    seconds[k] = block_seconds(b.length, entry, exit[k], b.v, b.a, b.j);
    entry = exit[k];
  }
}

}  // namespace

AxisLimits axis_limits(const MachineDefinition& machine, int axis) {
  const AxisDynamics& d = machine.dynamics.axes.at(static_cast<size_t>(axis));
  if (axis < 3)
    return {stated_or(d.velocity_per_min, machine.rapid.feed_mm_per_min),
            stated_or(d.accel_per_s2, MachineDynamics::kLinearAccelMmPerS2),
            stated_or(d.jerk_per_s3, MachineDynamics::kLinearJerkMmPerS3)};
  const double speed = machine.rotary.at(static_cast<size_t>(axis - 3)).max_speed_rad_per_min;
  return {stated_or(d.velocity_per_min,
                    std::isfinite(speed) ? speed : deg_to_rad(MachineDynamics::kRotarySpeedDegPerMin)),
          stated_or(d.accel_per_s2, deg_to_rad(MachineDynamics::kRotaryAccelDegPerS2)),
          stated_or(d.jerk_per_s3, deg_to_rad(MachineDynamics::kRotaryJerkDegPerS3))};
}

// The 7-phase profile's closed form. Reaching speed v from rest takes
// v/a + a/j when the acceleration limit is reached (v >= a^2/j), else
// 2*sqrt(v/j); by symmetry it covers v times half that time. A move too
// short to reach v peaks at the speed whose rise and fall cover it exactly.
double rest_to_rest_seconds(double distance, double v, double a, double j) {
  if (!(distance > 0)) return 0;
  const auto rise = [&](double speed) {
    if (std::isinf(a)) return std::isinf(j) ? 0.0 : 2 * std::sqrt(speed / j);
    return std::isinf(j) || speed >= a * a / j ? speed / a + (std::isinf(j) ? 0.0 : a / j) : 2 * std::sqrt(speed / j);
  };
  if (std::isinf(v)) v = std::numeric_limits<double>::max();
  if (distance >= v * rise(v)) return 2 * rise(v) + (distance - v * rise(v)) / v;
  // The peak speed p with p * rise(p) = distance.
  double p;
  if (std::isinf(a)) {
    p = std::cbrt(distance * distance * j / 4);
  } else {
    const double c = std::isinf(j) ? 0.0 : a / j;  // p^2/a + p*c = distance
    p = a * (-c + std::sqrt(c * c + 4 * distance / a)) / 2;
    if (!std::isinf(j) && p < a * a / j) p = std::cbrt(distance * distance * j / 4);
  }
  return 2 * rise(p);
}

CycleTime estimate_cycle_time(const std::vector<ProgramMove>& moves, const MachineDefinition& machine,
                              const CycleTimeOptions& options) {
  std::array<AxisLimits, 5> lim;
  for (int i = 0; i < 5; ++i) lim[static_cast<size_t>(i)] = axis_limits(machine, i);
  const double change_s = stated_or(machine.dynamics.tool_change_s, MachineDynamics::kToolChangeS);

  CycleTime out;
  out.block_s.assign(moves.size(), 0.0);
  out.block_tool_change_s.assign(moves.size(), 0.0);
  std::vector<FeedBlock> run;
  size_t run_first = 0;
  const auto close_run = [&] {
    std::vector<double> seconds;
    time_feed_run(run, seconds);
    for (size_t k = 0; k < run.size(); ++k) out.block_s[run_first + k] = seconds[k];
    run.clear();
  };
  MachineAxes at = options.start;
  int tool = 0;
  for (size_t i = 0; i < moves.size(); ++i) {
    const ProgramMove& m = moves[i];
    for (int r = 0; r < 2; ++r) at.rotary_rad[static_cast<size_t>(r)] -= 2 * kPi * m.rotary_reset[static_cast<size_t>(r)];
    const bool change = m.tool != 0 && m.tool != tool;
    const std::array<double, 5> d = axis_distances(at, m.axes);
    if (change || m.kind == MoveKind::Rapid) {
      if (!run.empty()) close_run();
    }
    if (change) {
      out.block_tool_change_s[i] = change_s;
      ++out.tool_changes;
      tool = m.tool;
    }
    if (m.kind == MoveKind::Rapid) {
      double slowest = 0;
      for (int k = 0; k < 5; ++k) {
        const AxisLimits& l = lim[static_cast<size_t>(k)];
        slowest = std::max(slowest, rest_to_rest_seconds(d[static_cast<size_t>(k)], l.velocity_per_min / 60,
                                                         l.accel_per_s2, l.jerk_per_s3));
      }
      out.block_s[i] = slowest;
    } else {
      if (run.empty()) run_first = i;
      run.push_back(feed_block(m, m.axes.linear_mm - at.linear_mm, d, lim));
    }
    at = m.axes;
  }
  if (!run.empty()) close_run();
  out.block_positioning.assign(moves.size(), false);
  for (size_t i = 0; i < moves.size(); ++i) {
    const bool positioning = moves[i].kind == MoveKind::Rapid ||
                             (i < options.positioning.size() && options.positioning[i]);
    out.block_positioning[i] = positioning;
    (positioning ? out.rapid_s : out.cut_s) += out.block_s[i];
    out.tool_change_s += out.block_tool_change_s[i];
  }
  out.total_s = out.rapid_s + out.cut_s + out.tool_change_s;
  return out;
}

}  // namespace bliskrun
