#pragma once
// Interference between a tool and the part's check surfaces, with FCL.
//
// A CollisionWorld holds the check surfaces (neighbouring blades, hub,
// casing, any tessellated surface) as named FCL BVH meshes (OBBRSS), built
// once. A ToolBody holds a tool's FCL meshes (tool_fcl.h), built once. Per
// pose the world answers the clearance of each tool part (cutter, shank,
// holder) to the nearest check surface; between two poses it proves or
// refutes that the motion keeps every part clear (check_motion).
//
// Distances are those of the FCL bodies: exact for the check meshes, and
// for the tool at most ToolBody::overestimate_mm() below the true distance
// (the body encloses the tool), so "clear" is never optimistic. A motion
// proof asks a finely meshed cutter's coarse body first (FclPiece::coarse,
// 0.01 mm) and keeps its distance where that is far from the clearance:
// a cutter tens of mm from a blade then costs a traversal of ~700
// triangles, not ~6000.
//
// Mesh-to-mesh distance sees surfaces only; a piece of check surface lying
// wholly inside a tool part, crossing none of its faces, is caught by
// testing one vertex of every connected piece of each check mesh against
// the tool's exact solid (a piece that crosses no face is wholly inside or
// wholly outside). A vertex within overestimate_mm of the true solid counts
// as touching — conservative by at most that much.
//
// Queries take a horizon: distances beyond clearance + horizon are not
// resolved (FCL's traversal is seeded with that bound and prunes every
// bounding volume farther away), which is what makes a clear/not-clear
// answer cost microseconds against a 100k-triangle blade.
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/tools/fcl_fwd.h"

#include "core/geometry/mesh.h"
#include "core/geometry/revolution_distance.h"
#include "core/tools/pose.h"
#include "core/tools/tool_fcl.h"

namespace bliskrun {

// Required clearance of each part from every check surface, mm (>= 0).
struct Clearances {
  double cutter_mm = 0;
  double shank_mm = 0;
  double holder_mm = 0;
  double of(ToolPartId part) const;
};

// A tool's FCL geometry, built once and shared by every query.
class ToolBody {
 public:
  // tol_mm: tessellation tolerance of non-cylindrical cutters (tool_fcl.h).
  explicit ToolBody(Tool tool, double tol_mm = 1e-3);
  const Tool& tool() const { return tool_; }
  const std::vector<FclToolPart>& parts() const { return parts_; }
  // Largest overestimate over the parts.
  double overestimate_mm() const;

 private:
  Tool tool_;
  std::vector<FclToolPart> parts_;
};

struct PartClearance {
  ToolPartId part = ToolPartId::Cutter;
  // FCL distance from the part's body to the nearest check surface; 0 when
  // they touch or overlap. When not `resolved`, the distance exceeds the
  // query's bound and distance_mm holds that bound (a lower bound).
  double distance_mm = 0;
  bool resolved = true;
  bool collides = false;
  int object = -1;  // index of the nearest check surface; -1 if none within the bound
  // Nearest points in the workpiece frame (when object >= 0).
  Vec3 on_tool = Vec3::Zero(), on_object = Vec3::Zero();
};

struct PoseCheck {
  std::vector<PartClearance> parts;  // one per present tool part, cutter first
  bool clear = true;                 // every part at least its clearance away
  int worst = -1;                    // index into parts of the smallest margin
  double min_margin_mm = 0;          // min over parts of distance - clearance
};

// Result of check_motion.
struct MotionCheck {
  bool clear = true;
  // Where the first sample closer than its clearance lies (t in [0, 1]) and
  // what was found there; t = -1 when clear.
  double t = -1;
  PoseCheck at;
  bool undecided = false;  // gave up after max_samples; treated as not clear
  int samples = 0;
  // Smallest sampled margin; distances beyond what the proof needed are
  // not resolved, so this is the smallest margin the proof used.
  double min_margin_mm = 0;
};

// Which tool parts a check surface is checked against: every part by
// default. The blade being machined is a check surface for the shank and
// holder only — the cutter touches it by design.
struct PartMask {
  bool cutter = true, shank = true, holder = true;
  bool has(ToolPartId part) const;
};

// How a check surface is checked: against which parts, and with what extra
// margin (mm) added to every clearance against it — e.g. the chord
// tolerance of a coarse mesh, so that a mesh that may lie up to that far
// behind the true surface is never optimistic.
struct CheckSurfaceOptions {
  PartMask parts;
  double margin_mm = 0;
  // Stock still on a face (a roughing's): an obstacle for the parts given
  // (the shank and holder), never for the cutter, which cuts it — so not
  // one of the pairs unchecked_pairs() adds back for the cutter.
  bool stock = false;
};

class CollisionWorld {
 public:
  CollisionWorld() = default;

  // Adds a check surface. Throws ParameterError for an empty or duplicate
  // name, a mesh with no triangles, indices out of range, or non-finite
  // vertices. Cost ~ n log n in the triangle count (BVH build). Triangles
  // should share vertex indices (tessellate() does): the containment test
  // checks one vertex per connected piece, so a triangle soup makes it
  // linear in the triangle count per query.
  void add(const std::string& name, const TriangleMesh& mesh, CheckSurfaceOptions options = {});
  // The same in two steps: the BVH built apart from any world (pure, so
  // several at once on worker threads: a Rotor 67 world's seven meshes
  // took 18 s one after the other), then added. prepare throws what add
  // throws for the mesh; add(PreparedSurface) what it throws for the name,
  // and ParameterError for one never prepared or already added.
  class PreparedSurface {
   private:
    friend class CollisionWorld;
    struct Built;
    std::shared_ptr<Built> built_;
  };
  static PreparedSurface prepare(const std::string& name, const TriangleMesh& mesh, CheckSurfaceOptions options = {});
  void add(PreparedSurface prepared);
  // Adds a surface of revolution measured analytically: each tool piece by
  // its sphere cover (tool_fcl.h) against the meridian's distance
  // (revolution_distance.h), never more than the true distance. For a
  // check surface a tool part runs close along — a hub the ball finishes —
  // where a mesh fine enough would make every step of a motion proof an FCL
  // traversal of a few hundred thousand triangles. Same name rules as add.
  void add(const std::string& name, std::shared_ptr<const RevolutionDistance> surface,
           CheckSurfaceOptions options = {});

  // The pairs this world leaves out: each surface some tool parts are not
  // checked against (its PartMask), against just those parts; surfaces
  // checked against every part are dropped; null when none is left. Shared,
  // not copied. E.g. the blade being machined for the cutter, which touches
  // it by design, for the non-cutting moves that leave the region its
  // gouge guards sample. Stock surfaces (CheckSurfaceOptions::stock) are
  // left out: the cutter is meant to be in the stock.
  std::shared_ptr<const CollisionWorld> unchecked_pairs() const;

  // This world without the mesh triangles `drop` selects (given a
  // triangle's three corners): each mesh rebuilt from the triangles kept
  // (corners shared where their coordinates are equal), an object left
  // with none dropped, surfaces of revolution kept whole; options as they
  // were. Null when nothing is left. Shared, not copied, where no triangle
  // goes. E.g. the blade being machined for the cutter less what a
  // planner's gouge guards sample (edge_finish's traverse world). Cost: a
  // BVH build of the triangles kept.
  using TriangleFilter = std::function<bool(const Vec3&, const Vec3&, const Vec3&)>;
  std::shared_ptr<const CollisionWorld> without_triangles(const TriangleFilter& drop) const;

  int size() const { return static_cast<int>(objects_.size()); }
  const std::string& name(int index) const { return objects_.at(index).name; }
  int triangle_count(int index) const { return objects_.at(index).triangles; }

  // Clearance of every tool part at one pose. Distances up to the part's
  // clearance + horizon_mm are exact; beyond, reported as that bound with
  // resolved = false. horizon_mm = 0 answers clear / not clear fastest.
  PoseCheck check(const ToolBody& body, const ToolPose& pose, const Clearances& clearances,
                  double horizon_mm = std::numeric_limits<double>::infinity()) const;

  // The motion from `from` to `to` (PoseMotion: straight tip, axis turning
  // in one plane), checked by conservative advancement: at a sample t the
  // FCL distances d_k of each piece of a part (tool_fcl.h) bound how far
  // the motion may go before the piece could come within its part's
  // clearance c — every point of piece k moves at most V_k = |Δtip| +
  // θ·reach_k per unit t — so the next sample is t + min_k (d_k − c +
  // tol_mm) / V_k. "clear" is therefore a proof that
  // every part stays at least c_p − tol_mm from every check surface over the
  // whole motion (tol_mm > 0 bounds the number of samples by ~V/tol_mm).
  // A sample closer than its clearance stops the check: not clear, with t
  // and the pose check there. The end pose itself is the caller's per-pose
  // check.
  MotionCheck check_motion(const ToolBody& body, const ToolPose& from, const ToolPose& to,
                           const Clearances& clearances, double tol_mm = 1e-3,
                           int max_samples = 100000) const;

  // Smallest clearance margin (distance - clearance, over every tool part
  // and check surface) over the whole motion from `from` to `to`
  // (PoseMotion), as a lower bound within tol_mm of it — what check_motion's
  // min_margin_mm is not (that is the smallest margin the proof sampled). No
  // tool point moves faster than V = max_point_speed(tool reach) per unit t,
  // so the margin is V-Lipschitz in t and a piece [t0, t1] with margins g0,
  // g1 cannot go below (g0 + g1 - V (t1 - t0)) / 2; pieces are halved until
  // that bound is within tol_mm of the smallest sampled margin (Piyavskii's
  // bound). Distances are exact (no horizon), so far pieces are dropped at
  // once. For a report's "least clearance of a lead"; throws ParameterError
  // for tol_mm <= 0.
  double motion_min_margin(const ToolBody& body, const ToolPose& from, const ToolPose& to,
                           const Clearances& clearances, double tol_mm) const;

 private:
  struct Object {
    std::string name;
    std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> model;  // null for a revolution
    std::shared_ptr<const RevolutionDistance> revolution;
    int triangles = 0;
    std::vector<Vec3> piece_vertices;  // one vertex of every connected piece
    CheckSurfaceOptions options;
  };
  // Per piece (kHintPieces slots per part, the last shared by any more),
  // the object that was nearest it at the last query on this thread (0 at
  // first): check_bounded asks it first.
  static constexpr size_t kHintPieces = 8;  // tool_fcl.h cuts a cutter in two
  std::vector<int>& nearest_hints(size_t parts) const;
  // bound_mm[i][k]: resolve piece k of part i up to this; each piece's
  // distance (or its bound, when farther) into piece_distance when given.
  // With `coarse_far`, a piece's coarse body (FclPiece::coarse) answers
  // first, and its distance stands where it exceeds the clearance by
  // kCoarseFarFactor of its overestimate: never above the truth, and a
  // motion proof's step the shorter by at most 1 / kCoarseFarFactor.
  PoseCheck check_bounded(const ToolBody& body, const Eigen::Isometry3d& tool_to_part,
                          const Clearances& clearances, const std::vector<std::vector<double>>& bound_mm,
                          std::vector<std::vector<double>>* piece_distance, bool coarse_far = false) const;
  static constexpr double kCoarseFarFactor = 10;
  // A motion proof's first answer per piece is also approximate: found
  // within a factor 1 + kFarRelErr of the true distance and taken as a
  // lower bound (mesh_distance.h); it stands where the margin exceeds
  // kCoarseFarFactor times its error, as the coarse body's does. On Rotor
  // 67's TE the links' proofs took 21 s CPU exactly, 11-13 s so.
  static constexpr double kFarRelErr = 0.02;
  void check_name(const std::string& name, const CheckSurfaceOptions& options) const;
  std::vector<Object> objects_;
};

// What a pose check found, for refusal messages: the tool part with the
// smallest margin, the check surface it is nearest and the margin
// ("holder against blade 2 suction (margin -0.31 mm)").
std::string describe(const PoseCheck& check, const CollisionWorld& world);

}  // namespace bliskrun
