#pragma once
// Machine simulation of a posted program: every block read back is replayed
// with the controller's interpolation (motion.h controller_axes — the model
// the read-back sweeps the tool with) and the machine's own bodies
// (machine_bodies.h), the fixture, the stock and the tool checked against
// each other with FCL, as VERICUT's machine simulation does.
//
// Which pairs. Bodies on one rigid link never move relative to each other
// and are not checked. The machine's bodies on two links joined by one joint
// (the cradle and the table it carries, the table slide and the bed) are the
// machine builder's business — their bearing keeps them apart — and are not
// checked either; every other pair is: the head and spindle housing against
// the table, cradle, fixture and stock; the cradle against the column. The
// tool (cutter, shank, holder) is checked against every part-side and base
// body except the stock, which it cuts (its clearance from the part was
// proved when it was planned). Each tool part stands as six stacked
// cylinders, each of its largest radius over its slice (conservative).
//
// The bound. Along a block each body point moves at most
//     V_b = S + sum_i |dtheta_i| R_i     (per unit of the block's parameter t)
// S the speed of the slides carrying it (joint-linear: |dq|; TCP: |dtip| +
// sum_i |dtheta_i| rho_i, rho_i the tip's reach from rotary i), R_i the
// body's reach from the pivot of rotary i carrying it (its bounding sphere's
// far side, plus twice the pivot distances of the rotaries between). The
// distance of a pair therefore changes by at most V = V_a + V_b per unit t.
// From a distance d measured at t, with m the pair's closest approach so
// far and e = max(c, m / 10) (c the clearance), the next sample is taken at
// t + (d - m + e) / V (conservative advancement): in between the pair stays
// at least m - e apart — never closer than -c, as m - m/10 > 0 where
// e > c. So no contact deeper than c is missed, and the closest approach
// reported is never above the truth by more than c, or a tenth of itself
// where that is larger (a pair 200 mm apart is measured every 20 mm). The
// budget carries over blocks: a pair far apart is not measured again until
// the blocks' summed motion bounds could have brought it within reach —
// the broad phase over each block's swept bounds that keeps this cheap.
// Under TCP with vector orientation the rotaries are not linear in t; their
// motion is summed over 16 sub-steps, an estimate, not a bound.
#include <memory>
#include <string>
#include <vector>

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
};

struct MachineSimReport {
  double clearance_mm = 0;
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

// Replays `blocks` (read_program) on `machine` with its bodies, the setup's
// fixture and stock (frame "part" or any other frame of the machine) and
// the tools. Throws ParameterError for a body on an unknown frame, a block
// calling a tool not in `tools`.
MachineSimReport simulate_machine(const std::vector<ProgramMove>& blocks, const MachineDefinition& machine,
                                  const std::vector<SimTool>& tools, const std::vector<MachineBody>& fixture,
                                  const std::vector<MachineBody>& stock, const MachineSimOptions& options);

// "PASS: closest approach 3.2 mm (head / fixture, line 120), clearance 0.5 mm"
// or "FAIL: collision head / table at line 80 (block 12), depth 4.1 mm".
std::string machine_sim_summary(const MachineSimReport& report);

}  // namespace bliskrun
