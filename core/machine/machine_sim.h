#pragma once
// Machine simulation of a posted program: every block read back is replayed
// with the controller's interpolation (motion.h controller_axes — the model
// the read-back sweeps the tool with) and the machine's own bodies
// (machine_bodies.h), the fixture, the stock and the tool checked against
// each other with FCL, as VERICUT's machine simulation does.
//
// Which pairs. Bodies on one rigid link never move relative to each other
// and are not checked (the fixture, the stock and the part on the part
// link). The machine's bodies on two links joined by one joint (the cradle
// and the table it carries, the table slide and the bed) are the machine
// builder's business — their bearing keeps them apart — and are not checked
// either; every other pair is: the head and spindle housing against the
// table, cradle, fixture, stock and part; the cradle against the column.
// The tool (cutter, shank, holder) is checked against every part-side and
// base body except the stock, which it cuts; against the part (its blades)
// the shank and the holder are checked and the cutter is not — it touches
// the part by design, and the planner proved it (with the shank and holder)
// against the blade it cuts, that blade's neighbours and the hub, and the
// read-back sweep kept the controller's motion within the body tolerance
// of that proof. Each tool part stands as cylinders over six slices of its
// length, each of the slice's largest radius (conservative); neighbouring
// slices of one radius are one cylinder.
//
// The bound. Along a block each body point moves at most
//     V_b = S + sum_i |dtheta_i| R_i     (per unit of the block's parameter t)
// S the speed of the slides carrying it (joint-linear: |dq|; TCP: |dtip| +
// sum_i |dtheta_i| rho_i, rho_i the tip's reach from rotary i), R_i the
// body's reach from the pivot of rotary i carrying it (its bounding sphere's
// far side, plus twice the pivot distances of the rotaries between). The
// distance of a pair therefore changes by at most V = V_a + V_b per unit t.
// Under TCP a body on the spindle's link moves relative to the part's link
// at most |dtip| + W r (r its reach from the tip, W the rotaries' relative
// turn: sqrt(w1^2 + w2^2 + 2 |w1 w2| cos) with the rotaries linear, w1 + w2
// with vector orientation), and a pair of such bodies takes the smaller.
// A body on a link that carries the other's (the cradle and the part on
// the table it carries) moves with it under every joint but those between
// them: V is the joints between alone (the table's turn times the part's
// reach from its pivot).
// From a distance d measured at t, with m the pair's closest approach so
// far and e = max(c, m / 10, m - N) (c the clearance, N the near-miss zone),
// the next sample is taken at t + (d - m + e) / V (conservative
// advancement): in between the pair stays at least m - e apart — never
// closer than -c, as m - m/10 > 0 where e > c. So no contact deeper than c
// is missed, and a closest approach within the zone is reported never above
// the truth by more than c, or a tenth of itself where that is larger. A
// pair that never enters the zone is only proved to stay out of it (its
// sampled nearest is reported with `beyond_zone`, "> N mm"): as VERICUT's
// near-miss zone, accuracy is spent where the machine comes close — a pair
// hovering 30 mm apart all program long would otherwise be measured every
// 3 mm of its motion, most of the cost of a blisk's program. The
// budget carries over blocks: a pair far apart is not measured again until
// the blocks' summed motion bounds could have brought it within reach —
// the broad phase over each block's swept bounds that keeps this cheap. A
// mesh (the part's blades) is asked first by its box (a sample where the
// box lies no nearer than m - e/4), then only whether it lies nearer than
// d_s = m - (e - c)/2 (FCL prunes its hierarchy by that bound): a sample
// nearer is measured exactly, else d_s — a lower bound, at least m - e/2 —
// stands for d and the step is at least (e + c)/2 / V. A pair near the
// part (e = c) is asked down to m itself; a far one is not, which would
// cost nearly the whole near side of the blade for a pair hovering just
// beyond its closest approach (the HECC impeller job's shank, 20-30 mm off
// its blade for a million blocks).
//
// Vector orientation. Under TCP with vector orientation the tool axis runs
// along the great circle at a constant rate Theta and the rotaries follow
// it (controller_axes), not linearly: their turn over a block is bounded
// (vector_turn_bound) from the orientation k = R(d1, t1) R(d2, t2) s
// (kinematics.h). With c = d1.k, s_phi = sqrt(1 - c^2) and G(c) = 1 -
// (d1.d2)^2 - (d2.s)^2 - c^2 + 2 (d1.d2)(d2.s) c (the squared triple
// product of d1, d2 and R(d2, t2) s):
//     |t2'| <= Theta s_phi / sqrt(G(c)),
//     |t1'| <= (Theta s_phi + |t2'| |d1.d2 - (d2.s) c|) / s_phi^2,
// rates that depend on c alone. Along the arc c is a sinusoid, so over
// each of 16 sub-steps its range is known in closed form, and the largest
// rate over that range bounds the sub-step's turn; their sum bounds the
// block's. This holds while the rotaries follow one branch of the
// solution. Where the arc passes through the primary axis' pole (s_phi = 0)
// or the secondary's reach limit (G = 0) the rates are unbounded, and where
// the modelled controller switches branches (its rotaries at a sub-step's
// end are not the continuation of the last sub-step's: near the pole the
// solution nearest the linear one jumps by half a turn of the primary) the
// model itself jumps: such a block is counted
// (MachineSimReport::unbounded_blocks) and swept with its sampled turn, an
// estimate, not a bound.
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/machine/kinematics.h"
#include "core/machine/machine_bodies.h"
#include "core/machine/program_reader.h"

namespace bliskrun {

class Tool;

struct SimTool {
  int number = 1;                    // the T word the program calls it by
  double length_mm = 0;              // tip to spindle gauge point
  std::shared_ptr<const Tool> body;  // null: the tool itself is not checked
};

struct MachineSimOptions {
  double clearance_mm = 0.5;  // see "The bound"; > 0
  double near_zone_mm = 10;   // the near-miss zone (see "The bound"); >= clearance_mm
  std::string file_name = "program";
  MachineAxes start;          // axes before the first block
};

// Where a pair came closest, or met.
struct BodyApproach {
  std::string a, b;
  double distance_mm = 0;  // < 0: penetration depth, negated
  long block = -1;         // index into the blocks read back
  int line = 0;            // program line
  double t = 0;            // along the block
  MachineAxes axes;        // machine axes there (slide words, rotaries)
  int tool = 0;            // the T number in the spindle there (0 before the first call)
  long queries = 0;        // samples the pair took over the program (its share of the cost)
  // The pair never came within the near-miss zone: distance_mm is its
  // nearest sample, the truth only proved above the zone (see "The bound").
  bool beyond_zone = false;
};

struct MachineSimReport {
  double clearance_mm = 0, near_zone_mm = 0;
  long blocks = 0, swept_blocks = 0;
  long unswept_blocks = 0;  // first block of a tool: checked where it ends
  long pairs = 0;
  long queries = 0;          // FCL distance queries
  long skipped = 0;          // pair-blocks the broad phase proved clear
  bool collided = false;
  BodyApproach first_collision;  // the earliest contact (block, then t)
  long colliding_blocks = 0;
  std::vector<BodyApproach> closest;  // one per pair, nearest first
  std::vector<std::string> unchecked;  // tools without a body
  // Vector-orientation blocks whose rotaries' turn is not bounded (see
  // "Vector orientation"), and the program line of the first.
  long unbounded_blocks = 0;
  int first_unbounded_line = 0;
  bool pass() const { return !collided; }
};

// Placing the bodies: the rigid links of the chain and their poses.
class MachineChain {
 public:
  MachineChain(const MachineDefinition& machine, double tool_length_mm);
  int links() const { return static_cast<int>(links_.size()); }
  int link_of(const std::string& frame) const;  // ParameterError("frame") if unknown
  int spindle_link() const { return spindle_; }
  int part_link() const { return part_; }
  bool adjacent(int a, int b) const;
  // Whether link a carries link b (is b, or a link between b and the base).
  bool carries(int a, int b) const;
  bool tool_side(int link) const { return links_[static_cast<size_t>(link)].tool_side; }
  // World (the machine bed) from the link's home coordinates (machine_bodies.h).
  Eigen::Isometry3d pose(int link, const MachineAxes& q) const;
  // The rotaries carrying the link, base outwards (indices into rotary).
  const std::vector<int>& rotaries(int link) const { return links_[static_cast<size_t>(link)].rotaries; }
  // The slides carrying the link (indices into linear).
  const std::vector<int>& slides(int link) const { return links_[static_cast<size_t>(link)].slides; }
  // Bound on how far a point of the sphere (centre, radius; the link's home
  // coordinates) can be from the pivot of rotary `axis` in any position.
  double reach(int link, int axis, const Vec3& centre, double radius) const;
  // The pivot of a rotary in its side's home coordinates.
  const Vec3& pivot(int axis) const { return pivots_[static_cast<size_t>(axis)]; }

 private:
  struct Link {
    int parent = -1;
    bool tool_side = false;
    int slide = -1, rotary = -1;  // what joint joins it to its parent
    std::vector<int> slides, rotaries;
  };
  MachineDefinition machine_;
  Vec3 gauge_ = Vec3::Zero();
  std::vector<Link> links_;
  std::vector<Vec3> pivots_;
  int spindle_ = 0, part_ = 0;
};

// What stands on the machine besides its own bodies (frame "part" or any
// other frame of the machine): the fixture, the stock (the tool may cut
// it) and the part itself (meshes: its blades; checked against the
// machine, the shank and the holder).
struct MachineSetupBodies {
  std::vector<MachineBody> fixture, stock, part;
};

// Replays `blocks` (read_program) on `machine` with its bodies, the setup's
// bodies and the tools. Throws ParameterError for a body on an unknown
// frame, a block calling a tool not in `tools`.
MachineSimReport simulate_machine(const std::vector<ProgramMove>& blocks, const MachineDefinition& machine,
                                  const std::vector<SimTool>& tools, const MachineSetupBodies& setup,
                                  const MachineSimOptions& options);

// See "Vector orientation" above: per rotary axis (MachineDefinition::rotary
// order) a bound on its turn (total variation, rad) over a block from
// `from` to `to` under TCP with vector orientation (controller_axes), and
// the same per sub-step. `bounded` is false where the arc passes a singular
// direction (the bounds are then infinite) or where the modelled controller
// switches rotary branches: at a sub-step's end its rotaries are not the
// solution nearest the last sub-step's, or turned further than the bound.
// `sampled_rad`: the turn summed over the sub-steps' ends (an estimate).
struct VectorTurnBound {
  std::array<double, 2> turn_rad{0.0, 0.0};
  std::vector<std::array<double, 2>> step_rad;  // `steps` sub-steps of equal t
  std::array<double, 2> sampled_rad{0.0, 0.0};
  bool bounded = true;
};
VectorTurnBound vector_turn_bound(const Kinematics& kin, const MachineAxes& from, const MachineAxes& to,
                                  const Vec3& tip_from, const Vec3& tip_to, int steps = 16);

// The machine as it stands at one pose of a program (an approach the
// simulation reported): every body placed in the machine frame, for a
// picture (core/machine/machine_picture.h). The pair `at` names is
// highlighted, with its nearest points.
struct PlacedBody {
  std::string name;
  enum Role { Machine, Fixture, Stock, Part, Tool } role = Machine;
  BodyShape shape = BodyShape::Box;
  // Box: its edge lengths, centred on the origin; cylinder and cone: radius
  // and length along +Z, centred on the origin (a cone's apex at
  // +length / 2); mesh: the meshes' own coordinates.
  Vec3 size_mm = Vec3::Zero();
  double radius_mm = 0, length_mm = 0;
  std::vector<std::shared_ptr<const TriangleMesh>> meshes;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // machine frame from the body's coordinates
  bool highlighted = false;
};
struct MachineScene {
  std::vector<PlacedBody> bodies;
  BodyApproach at;
  Vec3 nearest_a = Vec3::Zero(), nearest_b = Vec3::Zero();  // machine frame; equal where they overlap
};
// Throws ParameterError when `at` names no pair of these bodies.
MachineScene machine_scene(const MachineDefinition& machine, const std::vector<SimTool>& tools,
                           const MachineSetupBodies& setup, const BodyApproach& at);

// "PASS: closest approach 3.2 mm (head / fixture, line 120), clearance 0.5 mm"
// ("PASS: no pair within the 10 mm near-miss zone (nearest sampled 31.7 mm:
// head / fixture, line 120), clearance 0.5 mm" where none came within it)
// (with ", N vector-orientation blocks not bounded" where there are)
// or "FAIL: collision head / table at line 80 (block 12), depth 4.1 mm".
std::string machine_sim_summary(const MachineSimReport& report);

}  // namespace bliskrun
