#pragma once
// Five-axis point milling of a blade face with a ball or tapered ball end
// (issue 40): what flank milling cannot finish within tolerance (a face that
// is not ruled) is finished by the ball's tip, row by row.
//
//  - Rows along the flow (constant u, v running; the default) or across it
//    (constant v, u running), in the face's own parameters (SPEC §2: u hub ->
//    shroud, v along the chord; Impeller::face()).
//  - Row spacing: the ball's scallop closed form (ball_step_over on the
//    face's normal curvature across the rows, its largest along the row) as
//    the start; then the scallop between the new row and the last is
//    MEASURED on the surface — the material the two rows' balls leave along
//    the normal of samples between them (every 0.05 mm of the rows'
//    centres, so what the measurement misses is below 0.05^2 / 8r) — and the
//    step shrunk until it is within scallop_mm. Only the balls are measured:
//    a taper above them can only cut more, so the figure is an upper bound.
//  - Stations along a row by the chord tolerance of the ball CENTRE's path
//    (plan_row_steps with the guarantee: measured): between stations the
//    centre runs straight, so that is how far the cut leaves the row — on a
//    convex face below the design, so the tolerance is capped by the allowed
//    overcut (PointMillResult::chord_tol_mm).
//  - Hub-side boundary: the first row stops at the fillet's offset — its
//    contact lies `hub_stop_mm` along the face above the window's u0 edge
//    (default: the ball's radius; the hub finish's fillet row covers the
//    corner below it). Stated in the result (first_row_u).
//  - Tool axis: up the face's span (towards the shroud side, where the
//    spindle is) leaning away from the face by lean_rad (more than the
//    taper's half angle, so the cone stands off the face), turned about the
//    normal by the lead angle towards the feed. Where the tool is not clear
//    of the world (the neighbouring blade or splitter, the hub, the shroud
//    side) the lean grows and the axis turns sideways (tilt_until_clear,
//    which also proves the motion from the previous pose); a contact no axis
//    clears is refused, never emitted, and splits its row.
//  - Smoothness: the axis' turn per mm of contact travel is limited by
//    max_turn_rad_per_mm: where a row's leans change faster, the leans are
//    raised to the envelope max_j(lean_j - rate * |s_i - s_j|) and the row
//    planned again from them (the loop only raises a lean). What the face's
//    own twist turns cannot be smoothed away; the result reports the largest
//    turn per mm measured.
//
// Proved, not assumed: every pose and every cutting motion (swept) against
// the face and its neighbours with core/sim's GougeGuard (allowed_overcut_mm
// less what the guards' samples miss) and against the world with the whole
// tool; every step between rows, link and lead by prove_chain / plan_link /
// plan_departure (core/planning/links.h). The moves come out as the one
// toolpath type (core/toolpath/move.h).
#include <memory>
#include <string>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/collision/tilt.h"
#include "core/common/progress.h"
#include "core/geometry/surface.h"
#include "core/planning/links.h"
#include "core/planning/pass_moves.h"
#include "core/planning/row_steps.h"
#include "core/toolpath/move.h"
#include "core/tools/tool.h"

namespace bliskrun {

enum class PointMillRows { AlongFlow, AcrossFlow };

// A design surface the tool must not cut (a neighbouring face, the hub's
// sector), with its outward normal's sense.
struct PointMillSurface {
  std::string name;
  std::shared_ptr<const Surface> surface;
  bool flip_normal = false;  // out of the material is -(pu x pv)
};

struct PointMillRequest {
  PointMillSurface face;                    // the face milled
  std::vector<PointMillSurface> neighbours; // guarded (the cutter may not cut them) and in the world
  const Tool* tool = nullptr;               // ball or tapered ball end
  // Check surfaces; null: point_mill_world(*this).
  const CollisionWorld* world = nullptr;
  PointMillRows rows = PointMillRows::AlongFlow;
  double u0 = 0, u1 = 1, v0 = 0, v1 = 1;    // the face's window milled
  double hub_stop_mm = -1;                  // < 0: the ball's radius
  double scallop_mm = 0.005;
  StepOptions steps{ChordMethod::Variable, 0.002, true, 2.0, 1e-4};
  double lead_rad = 0;                      // along-flow rows: turn about the normal towards the feed
  double lean_rad = 10.0 * kPi / 180.0;
  double lean_step_rad = 1.0 * kPi / 180.0;
  double lean_max_rad = 45.0 * kPi / 180.0;
  double side_tilt_rad = 20.0 * kPi / 180.0;  // sideways turns while clearing (0: none)
  double side_step_rad = 5.0 * kPi / 180.0;
  double max_turn_rad_per_mm = 2.0 * kPi / 180.0;
  AxisLimit axis_limit;                     // the machine's reach (empty: none)
  Clearances clearances{0, 0.2, 1.0};
  double motion_tol_mm = 1e-3;
  LinkOptions links{RetractDirection::ToolAxis, 5.0, 0.1, 0, 0.002};
  double allowed_overcut_mm = 0.002;
  double guard_spacing_mm = 0.1;
  double mesh_tol_mm = 0.01;   // point_mill_world's meshes
  double tool_tol_mm = 1e-3;   // ToolBody meshing tolerance
  int threads = 1;             // rows on this many workers; the plan does not depend on it
};

// The world a request with world = null uses: the face for the shank and
// holder only (the cutter touches it by design and is proved by its guard;
// 0.05 mm mesh, that as margin), every neighbour for the whole tool
// (mesh_tol_mm).
CollisionWorld point_mill_world(const PointMillRequest& request);

struct PointMillPose {
  ToolPose pose;
  Vec3 contact = Vec3::Zero(), normal = Vec3::UnitZ(), centre = Vec3::Zero();
  double u = 0, v = 0;
  double lean_rad = 0;
  bool tilted = false;  // the operation's axis was not clear
};

struct PointMillPass {
  int row = 0;
  double level = 0;       // the row's constant parameter (u along the flow, v across)
  bool reversed = false;  // runs towards decreasing parameter
  std::vector<PointMillPose> poses;
};

struct PointMillRow {
  double level = 0;
  double closed_form_step_mm = 0;  // from the previous row, ball_step_over
  double step_mm = 0;              // taken, after the measurement
  double scallop_mm = 0;           // measured between it and the previous row
  double max_deviation_mm = 0;     // measured chord deviation of the centre path
  int stations = 0;
};

struct PointMillRefusal {
  int row = 0;
  Vec3 contact = Vec3::Zero();
  std::string reason;
};

using PointMillConnection = PassConnection;  // core/planning/pass_moves.h

struct PointMillResult {
  std::vector<PointMillRow> rows;
  std::vector<PointMillPass> passes;
  std::vector<PointMillConnection> connections;  // lead-in, between passes, lead-out
  std::vector<PointMillRefusal> refusals;
  double ball_radius_mm = 0, taper_rad = 0;
  double first_row_u = 0;          // the hub-side boundary taken (u of the first row)
  double scallop_max_mm = 0;       // measured, over every pair of rows
  double scallop_closed_form_mm = 0;  // the closed form's prediction at the steps taken (largest)
  double max_deviation_mm = 0;
  // The chord tolerance the stations were stepped by: the request's, or
  // less where a chord that deep would cut more than allowed_overcut_mm
  // (less what the guards miss) below a convex face.
  double chord_tol_mm = 0;
  double max_turn_rad_per_mm = 0;  // measured along the passes
  int poses = 0, tilted = 0, smoothed_rows = 0, gouge_splits = 0;
  int steps = 0, links = 0, refused_connections = 0;
  double seconds = 0;
  bool complete() const { return refusals.empty() && refused_connections == 0; }
};

// Throws ParameterError naming the option for a missing face or tool, a
// tool that is not a ball or tapered ball end, a lean not above the taper's
// half angle, non-positive scallop or chord, or an empty window.
PointMillResult plan_point_milling(const PointMillRequest& request, Progress& progress = Progress::none());

// The program: lead-in (Rapid "start"), each pass (Feed: "approach" or
// "step", then "cut"), steps (Feed) and links (Rapid) between passes, the
// lead-out; a Stop with the reason where a connection was refused.
Toolpath point_mill_moves(const PointMillResult& result);

// The root strip (issue 40): the band of the face between the window's
// hub-side edge (u0: the hub or the fillet's offset) and the first row
// (first_row_u), which the rows stop above (hub_stop_mm) and so do not
// finish. Measured, to be reported apart from the face's residual: at
// samples_u x samples_v points of the strip, the distance from the design
// point to the nearest ball of the program's moves (every move, rows and
// connections: the ball centre's motion taken as the straight segment
// between consecutive poses, which it leaves by far less than a micron at
// the planner's stations). Only the ball is measured: the taper and shank
// stand up the span, away from the hub, so the figure is what the ball end
// leaves — the material there is at least that thick (more where the
// previous operation left more), and nothing of this operation finishes it.
struct PointMillStrip {
  double u0 = 0, u1 = 0;          // the strip's parameters: window edge to the first row
  double height_mm = 0;           // largest along-face distance from u0 to u1 over v (the strip's height)
  double height_min_mm = 0;       // smallest (>= hub_stop_mm: the stop is taken at the narrowest v)
  double material_max_mm = 0;     // largest distance to the nearest ball, over the strip's samples
  double material_mean_mm = 0;
  double max_u = 0, max_v = 0;    // where the largest is
  int samples = 0;
};
PointMillStrip measure_root_strip(const PointMillRequest& request, const PointMillResult& result, int samples_u = 12,
                                  int samples_v = 200);

// Measurement (for the planner and the tests): the scallop height between
// two rows of ball centres (polylines, each centre a ball of radius r), at
// the surface points `samples` with unit normals `normals`: the largest
// over the samples of the lowest point the balls reach on the sample's
// normal line (mm above the surface; a sample no ball reaches reads as
// +infinity). The centres' polylines are swept (sub-sampled every
// step_mm).
double measured_scallop_mm(const std::vector<Vec3>& row_a, const std::vector<Vec3>& row_b, double r,
                           const std::vector<Vec3>& samples, const std::vector<Vec3>& normals,
                           double step_mm = 0.05);

}  // namespace bliskrun
