// The cycle-time estimate against closed forms: a straight line with
// trapezoidal acceleration (L/v + v/a long, 2*sqrt(L/a) short), the
// jerk-limited profile (L/v + v/a + a/j), a circle of chords run through at
// the feed (the look-ahead keeps the speed over the junctions), a turn of a
// rotary axis at its speed limit, inverse-time feeds and tool changes.
#include "core/machine/cycle_time.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_machines.h"

namespace bliskrun {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A table-table A/C machine with stated limits: X, Y, Z at 30 m/min,
// 2 m/s^2, no jerk limit unless given; rotaries 3600 deg/min, 720 deg/s^2.
MachineDefinition machine(double jerk = kInf) {
  MachineDefinition m = test::table_table_ac();
  for (int i = 0; i < 3; ++i) m.dynamics.axes[i] = {30000, 2000, jerk};
  for (int i = 3; i < 5; ++i) m.dynamics.axes[i] = {deg_to_rad(3600), deg_to_rad(720), kInf};
  m.dynamics.tool_change_s = 5;
  return m;
}

ProgramMove move(MoveKind kind, Vec3 xyz, double a_deg = 0, double c_deg = 0, double feed = 0, int tool = 1) {
  ProgramMove m;
  m.kind = kind;
  m.axes.linear_mm = xyz;
  m.axes.rotary_rad = {deg_to_rad(a_deg), deg_to_rad(c_deg)};
  m.feed = feed;
  m.tool = tool;
  return m;
}

TEST(CycleTime, RestToRestClosedForms) {
  // Trapezoid: long (reaches v) and short (a triangle).
  EXPECT_NEAR(rest_to_rest_seconds(500, 500, 2000, kInf), 500.0 / 500 + 500.0 / 2000, 1e-12);
  EXPECT_NEAR(rest_to_rest_seconds(10, 500, 2000, kInf), 2 * std::sqrt(10.0 / 2000), 1e-12);
  // Jerk-limited, both limits reached: L/v + v/a + a/j.
  EXPECT_NEAR(rest_to_rest_seconds(500, 500, 2000, 50000), 1.0 + 0.25 + 0.04, 1e-12);
  // Too short for the acceleration limit: the peak acceleration sqrt(v j)
  // ... here the move peaks at p with p * 2 sqrt(p / j) = L.
  const double L = 0.001, j = 50000, p = std::cbrt(L * L * j / 4);
  EXPECT_NEAR(rest_to_rest_seconds(L, 500, 2000, j), 4 * std::sqrt(p / j), 1e-12);
  EXPECT_LT(p, 2000.0 * 2000 / j);
  // Continuous where the cases meet: the move that just reaches v (v times
  // its rise v/a + a/j: 145 mm) and the one that just reaches a (peak speed
  // a^2/j = 80 mm/s, rise 2 a/j: 6.4 mm).
  for (double d : {145.0, 6.4}) {
    EXPECT_NEAR(rest_to_rest_seconds(d * (1 - 1e-9), 500, 2000, j), rest_to_rest_seconds(d * (1 + 1e-9), 500, 2000, j),
                1e-6);
  }
}

TEST(CycleTime, RapidAlongOneAxisIsTheTrapezoidAndTheSlowestAxisDecides) {
  const MachineDefinition m = machine();
  const double v = 30000.0 / 60, a = 2000;
  // 400 mm along X: long (v^2/a = 125 mm).
  CycleTime t = estimate_cycle_time({move(MoveKind::Rapid, {400, 0, 0})}, m);
  EXPECT_NEAR(t.total_s - t.tool_change_s, 400 / v + v / a, 1e-9);
  EXPECT_NEAR(t.rapid_s, 400 / v + v / a, 1e-9);
  EXPECT_EQ(t.cut_s, 0);
  // 20 mm: short.
  t = estimate_cycle_time({move(MoveKind::Rapid, {20, 0, 0})}, m);
  EXPECT_NEAR(t.rapid_s, 2 * std::sqrt(20 / a), 1e-9);
  // Each axis on its own: 400 mm X and 20 mm Y take the X time.
  t = estimate_cycle_time({move(MoveKind::Rapid, {400, 20, 0})}, m);
  EXPECT_NEAR(t.rapid_s, 400 / v + v / a, 1e-9);
  // A half turn of C at 3600 deg/min = 60 deg/s, 720 deg/s^2: 180/60 + 60/720.
  t = estimate_cycle_time({move(MoveKind::Rapid, {0, 0, 0}, 0, 180)}, m);
  EXPECT_NEAR(t.rapid_s, 180.0 / 60 + 60.0 / 720, 1e-9);
}

TEST(CycleTime, FeedLineIsTheTrapezoidAtTheProgrammedFeed) {
  const MachineDefinition m = machine();
  const double f = 600.0 / 60, a = 2000;
  // A diagonal 100 mm line at F600: every axis in proportion, the path
  // accelerates at the tightest axis' limit over its share (X and Y each
  // carry 1/sqrt(2): a * sqrt(2)).
  const Vec3 end = Vec3(1, 1, 0).normalized() * 100;
  CycleTime t = estimate_cycle_time({move(MoveKind::Feed, end, 0, 0, 600)}, m);
  EXPECT_NEAR(t.cut_s, 100 / f + f / (a * std::sqrt(2.0)), 1e-9);
  // Short at a fast feed: never reaches it.
  t = estimate_cycle_time({move(MoveKind::Feed, {0.5, 0, 0}, 0, 0, 20000)}, m);
  EXPECT_NEAR(t.cut_s, 2 * std::sqrt(0.5 / a), 1e-9);
  // A feed above the axis' top speed runs at the top speed.
  t = estimate_cycle_time({move(MoveKind::Feed, {1000, 0, 0}, 0, 0, 60000)}, m);
  EXPECT_NEAR(t.cut_s, 1000 / 500.0 + 500.0 / a, 1e-9);
  // Inverse time (G93): F = 2 per minute is 30 s (no acceleration limit).
  MachineDefinition free = m;
  free.dynamics.axes[0] = {kInf, kInf, kInf};
  ProgramMove g93 = move(MoveKind::Feed, {10, 0, 0}, 0, 0, 2);
  g93.feed_mode = FeedMode::InverseTime;
  EXPECT_NEAR(estimate_cycle_time({g93}, free).cut_s, 30, 1e-9);
}

TEST(CycleTime, CircleOfChordsRunsAtTheFeedThroughTheJunctions) {
  const MachineDefinition m = machine();
  const double radius = 20, f = 1200.0 / 60, a = 2000;
  const int n = 720;
  std::vector<ProgramMove> moves;
  double perimeter = 0;
  Vec3 last(radius, 0, 0);
  moves.push_back(move(MoveKind::Rapid, last));
  for (int k = 1; k <= n; ++k) {
    const Vec3 p(radius * std::cos(2 * kPi * k / n), radius * std::sin(2 * kPi * k / n), 0);
    perimeter += (p - last).norm();
    moves.push_back(move(MoveKind::Feed, p, 0, 0, 1200));
    last = p;
  }
  const CycleTime t = estimate_cycle_time(moves, m);
  // Start and stop on a chord along Y (the axis that carries the motion
  // there): the trapezoid's v/a; in between at the feed.
  EXPECT_NEAR(t.cut_s, perimeter / f + f / a, 1e-3 * f / a);
  EXPECT_NEAR(t.rapid_s, 2 * std::sqrt(radius / a), 1e-9);
}

TEST(CycleTime, RotaryTurnAtItsSpeedLimit) {
  const MachineDefinition m = machine();
  // C a full turn in 36 feed blocks at F 100000 (deg/min: no linear axis
  // moves), capped by C's 3600 deg/min = 60 deg/s and 720 deg/s^2.
  std::vector<ProgramMove> moves;
  for (int k = 1; k <= 36; ++k) moves.push_back(move(MoveKind::Feed, {0, 0, 0}, 0, 10.0 * k, 100000));
  const CycleTime t = estimate_cycle_time(moves, m);
  EXPECT_NEAR(t.cut_s, 360.0 / 60 + 60.0 / 720, 1e-9);
}

TEST(CycleTime, ToolChangesAndPositioningAreSeparate) {
  const MachineDefinition m = machine();
  std::vector<ProgramMove> moves = {move(MoveKind::Rapid, {400, 0, 0}, 0, 0, 0, 5),
                                    move(MoveKind::Feed, {400, 100, 0}, 0, 0, 600, 5),
                                    move(MoveKind::Feed, {400, 0, 0}, 0, 0, 600, 5),
                                    move(MoveKind::Rapid, {0, 0, 0}, 0, 0, 0, 7),
                                    move(MoveKind::Feed, {0, 0, -10}, 0, 0, 300, 7)};
  CycleTimeOptions o;
  o.positioning = {false, false, true, false, false};  // the second feed block positions
  const CycleTime t = estimate_cycle_time(moves, m, o);
  EXPECT_EQ(t.tool_changes, 2);
  EXPECT_DOUBLE_EQ(t.tool_change_s, 10);
  EXPECT_NEAR(t.total_s, t.rapid_s + t.cut_s + t.tool_change_s, 1e-12);
  // The two feed blocks reverse: the corner stops (each block its own
  // trapezoid), then split into cutting and positioning.
  EXPECT_NEAR(t.block_s[1], 100 / 10.0 + 10.0 / 2000, 1e-9);
  EXPECT_NEAR(t.block_s[2], 100 / 10.0 + 10.0 / 2000, 1e-9);
  EXPECT_NEAR(t.rapid_s, 2 * (400 / 500.0 + 500.0 / 2000) + t.block_s[2], 1e-9);
  EXPECT_NEAR(t.cut_s, t.block_s[1] + t.block_s[4], 1e-12);
  EXPECT_NEAR(t.block_s[4], 10 / 5.0 + 5.0 / 2000, 1e-9);
}

TEST(CycleTime, DefaultsWhereTheMachineFileStatesNone) {
  MachineDefinition m = test::table_table_ac();
  const AxisLimits x = axis_limits(m, 0), c = axis_limits(m, 4);
  EXPECT_EQ(x.velocity_per_min, m.rapid.feed_mm_per_min);
  EXPECT_EQ(x.accel_per_s2, MachineDynamics::kLinearAccelMmPerS2);
  EXPECT_NEAR(rad_to_deg(c.velocity_per_min), MachineDynamics::kRotarySpeedDegPerMin, 1e-9);
  m.rotary[1].max_speed_rad_per_min = deg_to_rad(5000);  // the axis' `speed` is its top speed
  EXPECT_NEAR(rad_to_deg(axis_limits(m, 4).velocity_per_min), 5000, 1e-9);
}

}  // namespace
}  // namespace bliskrun
