#pragma once
// Hub and blade-root finishing of a blisk with a (tapered) ball-end mill
// (issue 18 item 2): what the flank finish (drum wheel, first row raised
// off the hub: DrumFinishResult::hub_strip_mm) and the edge finish (flat
// end, EdgeFinishResult::hub_strip_mm) leave next to the hub, and the hub
// floor of one channel.
//
//  - Root strip around blade k: closed rows on the blade's side surface
//    closed around its section (close_blade, core/parts/closed_blade.h),
//    pressure flank -> TE round -> suction flank -> LE round. Row 0 is the
//    fillet row: at every v the ball touches the hub and the blade at once
//    (its centre on the hub offset by r, r from the blade). The design's
//    corner is sharp and no rotating tool cuts a sharp corner: the ball
//    leaves a fillet of its radius there, reported as such (root_fillet_mm).
//    The rows above lie at constant height above the hub (the hub's
//    radial_offset of the contact point: a distance in the meridian plane)
//    up to `root_top_mm` (default 4 mm: above both the drum finish's and the
//    edge finish's strips, overlapping what they finished). Rows are spaced
//    by the ball's scallop closed form (ball_step_over: a ball of radius r
//    on a surface of normal curvature k across the rows), the height step
//    shrunk by the blade's slope to the hub (a height step dh is
//    dh / sqrt(1 - (n_blade . n_hub)^2) along the blade).
//  - Channel floor between blade k and k+1: rows across the channel at
//    constant z (circles of the hub), from where the ball touches blade k's
//    root to where it touches blade k+1's (outside the blades' axial
//    extent: between the blades' mid-lines extended), z from the inlet to
//    the outlet plane, ball centre on the hub offset by r. Across rather
//    than along the flow because a plane z = const cuts each blade's root
//    once: every row is one piece whose ends lie on the fillet (or the cell
//    boundary), so consecutive rows are joined by a short step along it and
//    the whole floor is one zigzag pass with no retract. Rows along the
//    flow are fewer but the ones that meet a blade split in two, and the
//    link between the pieces has to climb over the blade.
//    Spacing: ball_step_over on the hub's curvature along the meridian
//    (a cone's: 0), the z step shrunk by the meridian's slope.
//
// Tool axis (the operation's rule, then the interference loop): on the root
// rows up the blade's span leaning away from the blade by lean_rad (more
// than the taper's half angle, so the cone above the ball stands off the
// blade); on the floor the hub normal leaned towards the channel's middle
// by lean_rad at either end, radial in the middle. Where the shank or
// holder is not clear of the world the lean grows (tilt_until_clear, which
// also proves the motion from the previous pose); a contact no axis clears
// is refused, never emitted, and splits its row.
//
// Proved, not assumed: every pose and every cutting motion (swept) against
// the design surfaces themselves with core/sim's GougeGuard — blade k and
// blade k+1 closed around their sections (the whole span, so the flute too)
// and the hub around both — with `allowed_overcut_mm` less what the
// guards' samples miss; every step between rows, every link and lead by
// prove_chain / plan_link (core/planning/links.h, up the tool axis) against
// the world (whole tool) and the guards. The moves come out as the one
// toolpath type (core/toolpath/move.h), so posts and core/sim take them.
#include <memory>
#include <string>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/collision/tilt.h"
#include "core/common/progress.h"
#include "core/geometry/revolution.h"
#include "core/geometry/surface.h"
#include "core/toolpath/move.h"
#include "core/planning/links.h"
#include "core/planning/pass_moves.h"
#include "core/planning/row_steps.h"
#include "core/sim/undercut.h"
#include "core/tools/tool.h"

namespace bliskrun {

// A blade's two flank faces as a CAD user extracts them (u span hub -> tip,
// pressure v LE -> TE, suction v TE -> LE, pu x pv out of the material;
// core/parts/builtin_blisk.h), and optionally its leading and trailing edge
// rounds (check surfaces of the world only, hub_finish_world). The built-in
// blisk's flanks end where its rounds begin, and a round stands up to its
// radius (0.3-0.4 mm) in front of the line between the flanks' ends: a
// world of flanks alone checks nothing there.
struct BladeFaces {
  std::shared_ptr<const Surface> pressure, suction;
  std::shared_ptr<const Surface> leading, trailing;  // optional
};

struct HubFinishRequest {
  BladeFaces blade;     // k: its root is finished, the channel starts at its suction side
  BladeFaces next;      // k + 1: the channel's other side
  BladeFaces previous;  // k - 1: faces blade k's pressure flank (world only; optional)
  std::shared_ptr<const SurfaceOfRevolution> hub;
  const Tool* tool = nullptr;  // ball or tapered ball end
  // Check surfaces; null: hub_finish_world(*this). A caller's own world must
  // hold what hub_finish_world puts in (the cutter meets blades k, k+1 and
  // the hub only through the gouge guards).
  const CollisionWorld* world = nullptr;
  bool root = true, channel = true;
  double root_top_mm = 4.0;       // height above the hub of the last root row
  // Scallop height. 5 um: the drum finish leaves 14 um on the flanks; the
  // root and the floor are finished to the edge finish's band (20 um) with
  // room, at ~0.24 mm steps for r 1.5 (16 root rows, ~180 floor rows).
  double scallop_mm = 0.005;
  // Chord tolerance of the ball centre's path (measured, guaranteed). On a
  // convex round the chord runs inside the centre's path: the ball cuts up
  // to this much below the design between poses, so it stays under the
  // allowed overcut.
  StepOptions steps{ChordMethod::Constant, 0.001, true, 2.0, 1e-4};
  double allowed_overcut_mm = 0.002;
  double z_inlet_mm = 0, z_outlet_mm = 0;  // channel floor; equal: the hub's meridian ends
  // Initial axis lean (see above). Next to the ball the cone stands off the
  // blade by r (1 - cos(lean - taper)): 21 um at 12 deg with a 2.5 deg taper.
  double lean_rad = 12.0 * kPi / 180.0;
  double lean_step_rad = 1.0 * kPi / 180.0;
  double lean_max_rad = 40.0 * kPi / 180.0;
  double side_tilt_rad = 20.0 * kPi / 180.0;  // sideways turns of the axis while clearing (0: none)
  double side_step_rad = 10.0 * kPi / 180.0;
  Clearances clearances{0, 0.2, 1.0};
  double motion_tol_mm = 1e-3;
  LinkOptions links{RetractDirection::ToolAxis, 5.0, 0.1, 0, 0.002};
  double guard_spacing_mm = 0.1;   // design samples of the gouge guards
  int closed_sections = 41;        // close_blade over each blade's whole span
  int row_samples = 1500;          // points a row's centre path is interpolated through
  double tool_tol_mm = 1e-3;       // ToolBody meshing tolerance
  double mesh_tol_mm = 0.01;       // hub_finish_world: neighbours' meshes
  int threads = 1;                 // rows planned on this many workers; the plan does not depend on it
};

// The check surfaces of a hub finish (what a request with world = null
// uses): blade k - 1's faces (and edge rounds, where given) for every tool
// part (mesh_tol_mm), blade k's and k + 1's for the shank and holder only
// (0.05 mm mesh, that as margin: the cutter touches them by design — the
// root rows run round blade k's rounds, the floor's rows end on both
// blades' fillets — and is proved by the gouge guards on the closed blades,
// whose half circles are the rounds; core/parts/closed_blade.h),
// the hub for the shank and holder as it is and for the cutter
// allowed_overcut_mm inside it (analytic, core/geometry/revolution_distance.h:
// a ball is one sphere, measured exactly), plus `extra` meshes for every
// part (fixtures, or a test's obstacle).
struct NamedMesh {
  std::string name;
  TriangleMesh mesh;
};
CollisionWorld hub_finish_world(const HubFinishRequest& request, const std::vector<NamedMesh>& extra = {});

enum class HubFinishOp { Root, Channel };
const char* hub_finish_op_name(HubFinishOp op);

struct HubFinishPose {
  ToolPose pose;
  Vec3 contact = Vec3::Zero(), normal = Vec3::UnitZ();  // on the design surface the row is planned on
  Vec3 centre = Vec3::Zero();                           // ball centre
  double t = 0;           // along the row (root: v around; channel: fraction across)
  bool tilted = false;    // the operation's axis was not clear
};

struct HubFinishRefusal {
  HubFinishOp op = HubFinishOp::Root;
  int row = 0;
  Vec3 contact = Vec3::Zero();
  std::string reason;
};

// A stretch of cutting: a row, or a piece of one between refusals.
struct HubFinishPass {
  HubFinishOp op = HubFinishOp::Root;
  int row = 0;
  double level = 0;      // root: contact height above the hub (-1: the fillet row); channel: centre z
  bool reversed = false;
  std::vector<HubFinishPose> poses;
  double max_deviation_mm = 0;  // measured chord deviation of the centre path
};

using HubFinishConnection = PassConnection;  // core/planning/pass_moves.h

struct HubFinishPart {
  HubFinishOp op = HubFinishOp::Root;
  std::vector<HubFinishPass> passes;
  // Departure (in), then one between consecutive passes, then Departure (out).
  std::vector<HubFinishConnection> connections;
  int rows = 0, poses = 0, tilted = 0, refusals = 0, steps = 0, links = 0, refused_connections = 0;
  int gouge_splits = 0;          // cutting motions the guards found dipping below: the row split there
  int entered_rows = 0;          // root rows planned again entered from the previous row's last pose
  double step_min_mm = 0, step_max_mm = 0;  // across rows, mm on the design
  double max_deviation_mm = 0;
  double seconds = 0;
};

struct HubFinishResult {
  HubFinishPart root, channel;
  std::vector<HubFinishRefusal> refusals;
  // Root: the fillet row's contact heights above the hub (min, max), the
  // fillet the ball leaves (its radius: the design's corner is sharp), the
  // first and last constant-height rows. The strips of the drum and edge
  // finishes below root_top_mm are covered.
  double fillet_min_mm = 0, fillet_max_mm = 0, root_fillet_mm = 0;
  double first_height_mm = 0, top_height_mm = 0;
  // Channel: the z range and the angular cell [theta_k(z), theta_k(z) + pitch].
  double z_inlet_mm = 0, z_outlet_mm = 0, pitch_rad = 0;
  double guard_spacing_mm = 0;
  // The closed blades' largest turn of the tangent where an edge meets a
  // face (close_blade, core/parts/closed_blade.h), degrees: ~0 when the
  // faces carry the edges' rounds or end tangent to a round; tens of degrees
  // for a measured blade's faces cut off short of its edges, whose closed
  // surface is then not the blade near the edges (the ball is refused there).
  double edge_kink_deg = 0;
  double setup_seconds = 0;
  // Geometry kept for the simulation and the writers.
  std::shared_ptr<const Surface> blade_closed, next_closed;
  std::shared_ptr<const Surface> hub_sector;   // the hub around blades k and k+1 (u meridian, v angle)
  bool hub_sector_flip = false;                // its pu x pv points into the hub
  std::vector<double> fillet_v, fillet_u;      // the fillet row's contacts on blade_closed, v increasing
  std::vector<double> floor_z, floor_theta0, floor_theta1;  // each floor row: centre z and end angles
  std::vector<double> floor_cell0, floor_cell1;              // and its cell's (the blades' mid-lines)
  // The root's last pose to the channel's first (both parts planned): a
  // link as the plan's own between passes (plan_link with `links`, up the
  // tool axis; every leg proved against the world with the whole tool and
  // by the gouge guards), by the first route that proves: "through the
  // channel" (over the middle of the channel's rows from the root's last
  // height to the channel's first row, links.retract_mm up their axes, rows
  // >= 3 mm apart: the root ends on blade k's suction flank, the channel
  // starts in front of its leading edge, and the straight traverse between
  // them runs through the blade); "straight" (the plan's own link between
  // passes); "over the blades" (up both axes until the ball is outside the
  // blades' tips). Its moves replace the root's lead-out and the channel's
  // lead-in in hub_finish_moves(result). Not clear: the reasons of every
  // route, and a Stop there.
  HubFinishConnection join;
  std::string join_route;           // the route that proved; empty when none did
  double join_offset_mm = 0;        // its retract up the axes
  // How close it comes: the smallest margin over its clearance of any tool
  // part between its two retracted poses, against the world and both
  // blades' closed surfaces (0.05 mm meshes, that as margin), sampled every
  // 0.5 mm of tool motion (the minimum within 0.25 mm), resolved up to
  // 2 mm; and what it is against.
  double join_margin_mm = 0;
  std::string join_margin_at;
  double join_deepest_cut_mm = 0;   // deepest dip below the design the guards measured over its legs (<= 0)
  double join_seconds = 0;
};

// Throws ParameterError naming the option for missing surfaces, a tool that
// is not a ball or tapered ball end, a lean not above the taper's half
// angle, non-positive scallop, chord, top or spacing, z_inlet >= z_outlet,
// or bad link options.
HubFinishResult plan_hub_finish(const HubFinishRequest& request, Progress& progress = Progress::none());

// The program of one part (or both: root, then channel) in order: the
// lead-in (Rapid), each pass's poses (Feed, "cut"; the first "approach" or
// "step"), steps (Feed) and links (Rapid) between passes, the lead-out; a
// Stop with the reason where a connection was refused. With both parts the
// root's last pass and the channel's first are joined by `join` (Rapid,
// "link"; its last leg ends at the channel's first pose, a Feed
// "approach") in place of the root's lead-out and the channel's lead-in;
// where no route proved, the lead-out, a Stop with the join's reason and
// the lead-in: nothing implies a motion from one part to the other.
Toolpath hub_finish_moves(const HubFinishResult& result);
Toolpath hub_finish_moves(const HubFinishPart& part);

// The material left by every move of the plan (core/sim), on blade k's
// closed surface over the root strip and on the hub over the channel.
//  - Root: samples over the root window (around, and from below the hub to
//    root_top_mm + 0.5 mm). A sample above the hub is "fillet" below the
//    fillet row's contact, "strip" up to root_top_mm.
//  - Floor: samples of the hub sector between the inlet and outlet planes;
//    "floor" where the ball resting on the hub there is clear of both blades
//    (between the floor rows' ends, interpolated in z).
// The statistics of each cover its strip / floor samples; the overcut covers
// every sample.
// Samples ~0.07 mm apart across the rows (the cusp's top read within
// ~0.7 um); the sweep at 0.1 mm of the fastest cutter point (the flute's
// top as the axis turns) misses < 1 um on the ball (d^2 / 8 r).
struct HubFinishSimOptions {
  int root_samples_u = 100, root_samples_v = 1200;
  int floor_samples_u = 500, floor_samples_v = 300;
  double sweep_step_mm = 0.1;
  int threads = 2;
};
struct HubFinishRegionStats {
  int samples = 0;       // in the region
  int unreached = 0;     // of those, never reached by the tool (within search_above)
  double left_max_mm = 0, left_mean_mm = 0;  // material left over the region's reached samples
  long left_max_sample = -1;                 // where the most is left (row-major index of its map)
  double overcut_mm = 0;  // deepest cut below the design over every sample (<= 0)
};
struct HubFinishSimulation {
  UndercutResult root, floor;
  // channel_middle: the floor samples 1 mm or more inside both rows' ends,
  // where only the rows' own cusps are left (the closed form's h).
  HubFinishRegionStats strip, fillet, channel_floor, channel_middle;
  double seconds = 0;
};
// The surfaces, windows and regions simulate_hub_finish measures, for any
// simulation of them (a job's whole-blade map sweeps every operation's
// moves over them): the closed blade's root window — `strip` above the
// fillet row, `fillet` below it, both between the hub and the top height —
// and the hub sector's window between the inlet and outlet planes — its
// `channel_floor` between the floor rows' ends (where the ball fits) and
// `channel_middle` 1 mm inside them. Masks per sample of their window,
// row-major (u outer); a window with no surface (blade or hub null) is not
// part of the plan.
struct HubFinishRegions {
  std::shared_ptr<const Surface> blade, hub;
  UndercutOptions root, floor;
  std::vector<char> strip, fillet, channel_floor, channel_middle;
};
HubFinishRegions hub_finish_regions(const HubFinishResult& result, const HubFinishRequest& request,
                                    const HubFinishSimOptions& options);

HubFinishSimulation simulate_hub_finish(const HubFinishResult& result, const HubFinishRequest& request,
                                        const HubFinishSimOptions& options, Progress& progress = Progress::none());

// APT/CL text of the moves (as drum_finish_apt).
std::string hub_finish_apt(const HubFinishResult& result, const HubFinishRequest& request);

}  // namespace bliskrun
