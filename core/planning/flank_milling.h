#pragma once
// Five-axis flank (swarf) milling of a ruled blade face (impeller paper
// §4.3, eq. 21–32) and its geometric residual (§5, eq. 33–36).
//
// The face is any Surface in the SPEC §2 orientation (u hub -> shroud along
// the rulings, v along the chord, pu x pv out of the material); for an
// impeller blade that is Impeller::face(). Its boundary curves are
// C2(v) = S(u_hub, v) (hub) and C1(v) = S(1, v) (shroud), with unit normals
// n1, n2 of the face there (eq. 21–22). With a hub, u_hub is where the ruling
// meets it (the ruling followed past u = 0 or cut back before it: eq. 10's
// offset hub curve leaves the hub by h times the lean of the ruling, up to
// 2.3 mm on the built-in impeller); without one, u_hub = 0.
//
// The cutter, seen from its axis, is a union of spheres: the point of the
// axis at height s above the ball centre is the centre of the largest
// sphere inside the cutter, of radius rho(s) (for a ball end rho = r, a
// cylinder; for a tapered ball end rho = r + s sin(beta), the cone being the
// envelope of those spheres). rho is derived from the tool's own profile
// (the distance from the axis point to the cutter surface), not assumed.
// The axis is the line through D1 = C1 + rho(s1) n1 and D2 = C2 + rho(s2) n2
// (eq. 23–25 with the radius at each contact's own height s1, s2), and the
// ball centre c is where the axis meets the hub offset at the ball radius r
// (eq. 26–32: the offset of a surface of revolution is found in the
// meridian plane, SurfaceOfRevolution::radial_offset = ±r on the side of the
// shroud contact, a 1-D root along the axis). s1, s2 depend on c, so D1, D2, c are iterated to a fixed point
// (a few iterations; for a ball end the first is exact).
//
// Residual (eq. 33–36): for points P along the axis between D2 and D1, the
// shortest distance from P to the face (point inversion, eq. 33–35) minus
// rho at P's height: > 0 undercut (material left), < 0 overcut.
//
// Axis optimisation (issue 40 item 0; optimise_flank_axis below). The
// two-contact axis is exact only on a developable face; on a twisted ruled
// face the normals turn along the ruling and the axis through D1, D2 leaves
// the paper's "concave overcut" mid-ruling. The literature positions the
// cutter from one or two contacts and then moves ("lifts and twists") it to
// reduce an error measured along the surface normal: Li, Mann & Bedi, "Error
// measurements for flank milling", CAD 37 (2005); Menzel, Bedi & Mann,
// "Triple tangent flank milling of ruled surfaces", CAD 36 (2004); and, with
// the signed error (point-to-surface distance minus the cutter radius)
// minimised by bounded least squares over the axis, "Optimal tool size and
// tool path for flank milling ruled surface with a conical cutter based on
// normal mapping", Adv. Mech. Eng. 9(8) (2017), doi 10.1177/1687814017724704.
// Gong, Cao & Liu (CAD 2005) and Zhu, Ding & Xiong (CAD 2010), named in
// issue 40, are of the same family (not in our reference store; not
// checked). Here each pose's axis is fitted to the face by the residual the
// plan reports (eq. 33–36 sampled along the axis):
//   * unknowns: the axis line (4: its mid point moved across the axis in
//     two directions, its direction turned in two) and, for a tool of
//     revolution, its height along the line. With a hub the height is not
//     free: the ball rides the hub (centre on the hub offset, eq. 26–32),
//     found again for every trial line; without one, a tapered cutter slides
//     along its axis as a fifth unknown (a cylinder's slide changes nothing).
//   * least squares first (Levenberg–Marquardt, Eigen's unsupported
//     NonLinearOptimization module), the Jacobian from the envelope theorem:
//     the gradient of the distance to the face is the unit normal at the
//     foot, so only the axis points are differentiated, no projection.
//   * then a minimax refinement (the tolerance is a band): Lawson's
//     iteratively reweighted least squares (weights grow with each point's
//     error), the best maximum kept.
//   * overcut counts `overcut_weight` times material left (>= 1: a bias
//     towards leaving material, stated in the options); 1 = a centred band.
//   * smoothness: the optimised axis turns at most max_axis_correction away
//     from the two-contact axis (a hard bound in the parametrisation), so
//     neighbouring poses turn by at most the two-contact axes' turn plus
//     twice that (triangle inequality); the two-contact axes are a smooth
//     sequence along the chord.
//   * a pose is never made worse: the fitted axis is kept only where its
//     largest (weighted) residual over the reported points is below the
//     start's, else the start stays.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/geometry/revolution.h"
#include "core/planning/links.h"
#include "core/geometry/surface.h"
#include "core/planning/row_steps.h"
#include "core/tools/pose.h"
#include "core/tools/tool.h"

namespace bliskrun {

// The cutter seen as spheres along its axis.
class FlankCutter {
 public:
  // `ball_radius_mm`: radius of the tip ball (its centre is that far up the
  // axis from the tip). Throws ParameterError("ball_radius") unless the
  // tool's inscribed sphere at that height has that radius (the tool has a
  // ball end of that size).
  FlankCutter(Tool tool, double ball_radius_mm);
  const Tool& tool() const { return tool_; }
  double ball_radius_mm() const { return r_; }
  // rho(s): radius of the largest sphere in the cutter centred on the axis
  // at height s >= 0 above the ball centre; 0 above the flutes.
  double radius_at(double s_mm) const;
  // Height above the ball centre where the cutting part ends.
  double flute_top_mm() const { return top_; }
  // The cutter's offset surface at distance `by` >= 0: the same axis and
  // ball centre, every radius (the ball's included) `by` larger. A pose of
  // the grown cutter tangent to a face puts the real cutter `by` off it
  // (stock left for finishing). Its tip is `by` below the real one.
  FlankCutter grown(double by_mm) const;
  double grown_by_mm() const { return grow_; }

 private:
  Tool tool_;
  double r_, top_;
  double grow_ = 0;
};

struct FlankAxis {
  double v = 0;                     // chord parameter of the face
  double u_hub = 0;                 // where the ruling meets the hub (0 without a hub)
  Vec3 c1 = Vec3::Zero(), c2 = Vec3::Zero();    // contacts on the shroud / hub boundary
  Vec3 n1 = Vec3::Zero(), n2 = Vec3::Zero();    // face normals there (out of the material)
  Vec3 d1 = Vec3::Zero(), d2 = Vec3::Zero();    // axis points (eq. 23–24)
  double s1 = 0, s2 = 0;            // their heights above the ball centre
  Vec3 ball_centre = Vec3::Zero();
  ToolPose pose;                    // tip = ball centre - r axis; axis towards the shroud
  int iterations = 0;
};

// The axis at chord parameter v. `hub` may be null: then the ball centre is
// D2 (s2 = 0; used for faces without a hub, as in tests). Throws Error when
// the axis does not meet the hub offset or a contact lies above the flutes.
FlankAxis flank_axis(const Surface& face, double v, const SurfaceOfRevolution* hub,
                     const FlankCutter& cutter);

// Chord parameters v where both boundary curves (C1 and C2) meet the chord
// tolerance: the union of the row steps of each (row_steps.h).
std::vector<double> flank_stations(const Surface& face, const StepOptions& steps);

struct ResidualStats {
  double max_mm = 0, min_mm = 0, mean_mm = 0, std_mm = 0;
  double max_abs_mm = 0;
  int samples = 0;
};
struct FlankResidual {
  int axes = 0, points = 0;          // map size: axes x points along each axis
  std::vector<double> residual_mm;   // [axis * points + k], hub (k = 0) -> shroud
  std::vector<double> height_mm;     // height above the ball centre of each point
  std::vector<Vec3> foot;            // nearest face point of each
  ResidualStats stats;
  double at(int axis, int k) const { return residual_mm[axis * points + k]; }
};
// Eq. 33–36 at `points_per_axis` points evenly between D2 and D1 of each
// axis. Throws Error if a point inversion fails.
FlankResidual flank_residual(const Surface& face, const std::vector<FlankAxis>& axes,
                             const FlankCutter& cutter, int points_per_axis);

ResidualStats residual_stats(const std::vector<double>& values);

struct FlankFitOptions {
  int points = 16;                               // residual points along the axis the fit uses
  double max_axis_correction_rad = deg_to_rad(0.5);  // largest turn away from the start axis
  double overcut_weight = 1.0;                   // overcut counts this many times material left (>= 1)
  int minimax_rounds = 5;                        // Lawson reweighting rounds after the least squares
  int check_points = 40;                         // points of the never-worse comparison
};
struct FlankAxisFit {
  FlankAxis axis;                    // the fitted axis, or the start where the fit is no better
  bool improved = false;             // the fitted axis was taken
  ResidualStats before, after;       // over check_points along the axis, against the face
  double correction_rad = 0;         // angle between the start axis and the taken one
  int evaluations = 0;               // residual evaluations (projections of `points` each)
};
// Fits the axis of `start` (a flank_axis, balanced or tilted or not) to
// `face` (the design face) as described at the top. `hub` as for
// flank_axis: with it, every trial ball centre rides the hub offset.
// Throws Error where a residual point has no foot on the face.
FlankAxisFit optimise_flank_axis(const Surface& face, const FlankAxis& start, const SurfaceOfRevolution* hub,
                                 const FlankCutter& cutter, const FlankFitOptions& options);

// ---------------------------------------------------------------------------
// One face planned with interference (issue 12 item 5).
//
// Every pose is checked against the world (neighbouring blades and
// splitters with every tool part; the face being cut and the hub with the
// shank and holder only, the cutter touching them by design) and so is the
// motion from the previous emitted pose. Where a pose collides, the axis is
// tilted about the hub contact normal n2 through the ball centre (the ball
// keeps its place on the hub, the axis stays in the face's tangent plane
// there) by +-tilt_step up to max_tilt; the first clear tilt is taken (its
// residual is computed on the tilted axis). A pose nothing clears, or whose
// motion from the previous pose collides, is refused with the reason and
// not emitted. Lead-in at the first pose and lead-out at the last pose are
// plan_departure() along the face normal (links.h), proved the same way.
struct FlankFaceRequest {
  const Surface* face = nullptr;
  const SurfaceOfRevolution* hub = nullptr;    // may be null (no hub: ball centre at D2)
  const FlankCutter* cutter = nullptr;
  const CollisionWorld* world = nullptr;       // may be null: no interference checks
  const ToolBody* body = nullptr;              // with world
  Clearances clearances;
  StepOptions steps;                           // chord tolerance along both boundary curves
  double max_tilt_rad = deg_to_rad(10);
  double tilt_step_rad = deg_to_rad(1);
  double motion_tol_mm = 1e-3;
  LinkOptions lead;                            // lead-in/out along the face normal
  int residual_points = 40;                    // points along each axis for the residual
  // The design face the residual is measured against, when the plan is made
  // on a ruled approximation of it (a fitted face): null = `face`.
  const Surface* design = nullptr;
  // Better than the paper: on a twisted face the residual along each axis is
  // a concave overcut (0 at the ends, most negative mid-ruling). Shifting the
  // axis along the mean face normal (n1 + n2) by -(max + min) / 2 of its own
  // residual centres the error band on zero, halving its largest magnitude.
  // The shifted pose is checked like any other; where it collides the
  // unshifted one is taken. The residual before (unshifted) is reported.
  bool balance_residual = false;
  // Fit every untilted pose's axis to the design face (optimise_flank_axis,
  // from the balanced axis when balance_residual). The fitted pose is tried
  // first and proved like any other; where it collides, or its motion from
  // the previous pose does, the unfitted pose (and then its tilts) follow as
  // before. Tilted poses are not fitted (the tilt is the clearance's).
  bool optimise = true;
  FlankFitOptions fit;
};

struct FlankRefusal {
  double v = 0;
  std::string reason;
};

struct FlankFacePlan {
  std::vector<FlankAxis> axes;       // emitted poses, in order along v
  std::vector<double> tilt_rad;      // per emitted pose
  std::vector<FlankRefusal> refusals;
  PlannedDeparture lead_in, lead_out;
  FlankResidual residual;            // over the emitted poses
  ResidualStats residual_unbalanced; // the same poses before balance_residual's shift
  ResidualStats residual_before;     // the same poses before the fit (balanced or not): optimise = false's
  int balanced = 0;                  // poses shifted by balance_residual
  int optimised = 0;                 // poses whose fitted axis was taken
  std::vector<double> correction_rad;  // per emitted pose: its turn away from the unfitted axis
  int stations = 0;
  int tilted = 0;
  // Material left in the root corner, per emitted pose: the distance from
  // the corner C2 (where the ruling meets the hub) to the tool there, > 0
  // material left, < 0 cut into (root_corner_material). Apart from the
  // residual, which runs along the axis from the ball centre up: a ball that
  // rides the hub and touches the face leaves r / sin(theta / 2) - r in a
  // corner of dihedral angle theta, more than the residual on a leaning
  // blade. Empty without a hub (no corner).
  std::vector<double> root_corner_mm;
  ResidualStats root_corner;         // over root_corner_mm
  // Smallest clearance margin (world only) over the emitted poses and the
  // clear leads: min(pose_min_margin_mm, lead_min_margin_mm).
  double min_margin_mm = 0;
  double pose_min_margin_mm = 0;     // over poses, resolved up to kMarginHorizonMm
  // Over the lead-in and lead-out motions (CollisionWorld::motion_min_margin, a lower bound
  // within kLeadMarginTolMm); +inf when no lead is clear or no world.
  double lead_min_margin_mm = 0;
};

// Margins beyond this are reported as this bound (resolving them costs more
// than the whole plan).
constexpr double kMarginHorizonMm = 5.0;

// Signed distance from the root corner C2 of `axis` (the face on the hub)
// to the real tool at axis.pose (a grown cutter's tip is its growth below
// the real one): > 0 material left there. The tool is a solid of
// revolution, so its frame is the pose's tip and axis alone.
double root_corner_material(const FlankAxis& axis, const FlankCutter& cutter);

constexpr double kLeadMarginTolMm = 0.01;


// Throws ParameterError for missing face/cutter, or a world without a body.
FlankFacePlan plan_flank_face(const FlankFaceRequest& request);

// APT/CL text: header, lead-in, GOTO/x,y,z,i,j,k (tip, axis) per pose, lead-out.
std::string flank_face_apt(const FlankFacePlan& plan, const std::string& part_name,
                           const std::string& tool_description);

}  // namespace bliskrun
