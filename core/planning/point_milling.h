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
//  - Hub-side boundary, two ways (stated in the result: follows_fillet,
//    first_row_u):
//    * with the hub (PointMillRequest::hub, follow_fillet): the rows are
//      carried down to the fillet line — the first row's ball touches the
//      face and the hub at once (its centre r from both), and the rows are
//      the iso-lines of the face trimmed between that line and the window's
//      top (p(u_f(v) + a (u1 - u_f(v)), v)), spaced by the measured scallop
//      as everywhere. Below the fillet line lies the root corner: the
//      fillet of the ball's radius no ball of that radius can enter,
//      reported apart (measure_root_strip's corner). The hub is then a
//      guarded surface too (its window along the fillet line, sampled as
//      the face is): no pose or cutting motion cuts it more than
//      allowed_overcut_mm, and the axis is tilted clear of it per pose.
//    * without: the first row stops at a fixed offset — its contact lies
//      `hub_stop_mm` along the face above the window's u0 edge (default:
//      the ball's radius); the strip below is left to another operation.
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
#include "core/geometry/revolution.h"
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
  double hub_stop_mm = -1;                  // < 0: the ball's radius (with the hub: the root band measured)
  // The hub the face stands on (a surface of revolution about Z): with
  // follow_fillet the rows are carried down to the fillet line; without,
  // measure_root_strip still measures from the fillet line (main's stop
  // measured the same way).
  std::shared_ptr<const SurfaceOfRevolution> hub;
  bool follow_fillet = true;
  // The fillet line found at this many v of the window (cubic through them).
  int fillet_samples = 41;
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
  double level = 0;       // the row's constant parameter (u along the flow, v across; of milled_surface)
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
  double first_row_u = 0;          // the hub-side boundary taken (u of the first row; following the fillet, its lowest)
  // Following the fillet: the first row lies on the fillet line, u from
  // fillet_u_min to fillet_u_max over the window; the rows were planned on
  // the face trimmed there (milled_surface, window u [0, 1], the face's v),
  // and each pose's u, v are the face's own.
  bool follows_fillet = false;
  double fillet_u_min = 0, fillet_u_max = 0;
  std::shared_ptr<const Surface> milled_surface;  // the face or, following the fillet, the face trimmed at it
  double milled_u0 = 0, milled_u1 = 1;            // the rows' window on milled_surface (u; v is the request's)
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

// The root strip (issue 40): the band of the face from the hub up to the
// hub stop (u0 + hub_stop_mm along the face; the first row of a plan that
// stops there), which a plan that stops does not finish and a plan that
// follows the fillet mills. Its lower edge is the fillet line where the
// request has the hub (below it the root corner, the fillet of the ball's
// radius, is measured apart: corner_*), else the window's u0 edge.
// Measured, to be reported apart from the face's residual: at samples_u x
// samples_v points of the band (every v, u from the lower edge up to, not
// on, the top), the distance from the design point to the nearest ball of
// the program's moves (every move, rows and connections: the ball centre's
// motion taken as the straight segment between consecutive poses, which
// it leaves by far less than a micron at the planner's stations). Only the
// ball is measured: the taper and shank stand up the span, away from the
// hub, so the figure is what the ball end leaves — the material there is at
// least that thick (more where the previous operation left more). The
// nearest segment is found through a PointIndex of the segments cut into
// pieces (near-linear in samples + moves), exactly: every piece that could
// be nearer than the nearest piece's midpoint is measured.
struct PointMillStrip {
  double u0 = 0, u1 = 0;          // the band's parameters: lower edge (lowest over v) to the top
  bool from_fillet = false;       // the lower edge is the fillet line (else the window's u0)
  double height_mm = 0;           // largest along-face distance from the lower edge to the top over v
  double height_min_mm = 0;       // smallest
  double material_max_mm = 0;     // largest distance to the nearest ball, over the band's samples
  double material_mean_mm = 0;
  double max_u = 0, max_v = 0;    // where the largest is
  int samples = 0;
  // The root corner below the fillet line (from_fillet only): the ball's
  // fillet, (sqrt(2) - 1) r at a square corner; its largest and where.
  double corner_max_mm = 0, corner_u = 0, corner_v = 0;
  int corner_samples = 0;
  std::vector<double> v, lower_u;  // the band's columns: v and its lower edge's u (the fillet line or u0)
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
