#pragma once
// Flat-end (corner-radius) mill positioning on a convex edge and the
// machining strip width by directed distances (edge paper §1.2, §3.1-3.2,
// SPEC §6.2).
//
// Local frame at the contact C (§1.2): X_L along the feed (the surface's pu),
// Z_L the surface normal out of the material, Y_L = Z_L x X_L (across the
// feed). A pose is one of
//   - Bottom: the contact lies on the flat bottom at distance l from the axis
//     (0 < l <= R - r), the axis is the surface normal; the tool is then
//     turned about Z_L through C by the side-slip angle φ. At φ = 0 the axis
//     lies behind C along the feed (tool centre at -l X_L).
//   - Corner: the contact lies on the corner torus, the axis leans forward
//     by the lead angle θ in the X_L Z_L plane (the torus point whose normal
//     is -Z_L), then turned by φ about Z_L. θ = 0 is the bottom's rim,
//     l = R - r.
// The paper's equations (3)-(6) (the rotation tool -> local and the tool
// centre) are this composition: p_L = Rz(φ) Ry(θ) (p_T - c_T), c_T the
// contact in the tool frame.
//
// Strip width (§3.1): the design surface is sampled around C on a small
// grid — across the feed (along pv, arc-length spaced) and a few offsets
// along the feed — and for each sample the directed distance from the
// design surface along its normal to the cutter is measured (sphere tracing
// on the cutter's exact signed distance, negative = gouge). Sweeping the
// tool along the feed takes a sample's residual to the smallest distance
// over its along-feed offsets (exact when the surface is invariant along the
// feed, as a cylinder around its axis or a sphere along a great circle; on
// the edge a good local model). The strip is the contiguous run of
// across-feed samples around C whose residual is within the band; its ends
// are interpolated linearly between samples. Conditions: ① no sample's
// distance below e1 (gouge: the pose is refused), ② at least one within e2,
// ③ l >= r_e (cutting speed; the bottom's pose only).
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "core/common/types.h"
#include "core/geometry/surface.h"
#include "core/tools/pose.h"
#include "core/tools/tool.h"

namespace bliskrun {

struct EdgeFrame {
  Vec3 point = Vec3::Zero();
  Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();  // feed, across, normal (out)
};
// Frame at S(u, v) with the feed along pu. flip_normal: the material lies on
// the +pu x pv side.
EdgeFrame edge_frame(const SurfaceDerivs& d, bool flip_normal = false);

enum class EdgeContact { Bottom, Corner };
const char* to_string(EdgeContact c);

struct EdgePosition {
  EdgeContact contact = EdgeContact::Bottom;
  double l_mm = 0;           // Bottom: distance of C from the axis
  double lead_rad = 0;       // Corner: θ
  double side_slip_rad = 0;  // φ
};

// R and r of a flat-end mill's cutting part (from its profile). Throws
// ParameterError("tool") for any other tool.
struct FlatEnd {
  double radius_mm = 0, corner_mm = 0;
  // Exact signed distance (tool frame, mm) to the cutting end: the points
  // within corner_mm of the quadrant {ρ <= R - r, z >= r} — bottom, corner
  // torus and side, the side continued upwards (the flute's top and the
  // shank are far from any strip sample). One square root, where the
  // general profile distance visits every element.
  double signed_distance(const Vec3& p_tool) const {
    const double x = std::sqrt(p_tool.x() * p_tool.x() + p_tool.y() * p_tool.y()) - (radius_mm - corner_mm);
    const double y = corner_mm - p_tool.z();
    const double d = x <= 0 && y <= 0 ? std::max(x, y) : std::sqrt(std::max(x, 0.0) * std::max(x, 0.0) +
                                                                    std::max(y, 0.0) * std::max(y, 0.0));
    return d - corner_mm;
  }
};
FlatEnd flat_end_of(const Tool& tool);

// The tool pose (tip = centre of the bottom, axis) for a position at a
// contact frame. Throws ParameterError for l outside (0, R - r] (Bottom) or
// θ outside [0, 90°) (Corner).
ToolPose position_tool(const FlatEnd& tool, const EdgeFrame& frame, const EdgePosition& position);

struct StripSampling {
  double half_width_mm = 6.0;   // across the feed on each side of C
  int across = 81;              // samples across (odd: one at C)
  double along_half_mm = 0.12;  // along the feed on each side of C
  int along = 5;                // samples along (odd: one at C)
  // Condition ① must hold over the tool's whole footprint, not only the
  // narrow strip around the row: gouge-only samples over ±gouge_half_mm
  // along the feed (gouge_along of them) on every gouge_stride-th across
  // line.
  double gouge_half_mm = 6.0;
  int gouge_along = 13;
  int gouge_stride = 4;
  // Instead of ±gouge_half_mm: gouge_along samples over the surface's whole
  // u range (a small surface such as an edge region, whose round would fall
  // between samples spaced for the tool's size).
  bool gouge_whole_u = false;
};

// Samples of the design surface around a contact: points and unit normals
// (out of the material), across-feed index j outer, along-feed k inner, with
// the across-feed arc offset of each j (negative towards -pv).
struct StripSamples {
  int across = 0, along = 0, centre = 0;
  std::vector<double> s_mm;
  std::vector<Vec3> p, n;
  std::vector<Vec3> gouge_p, gouge_n;  // condition ① only
};
// Samples stop at the surface's parameter bounds (fewer on that side).
StripSamples sample_strip(const Surface& surface, double u, double v, const StripSampling& sampling,
                          bool flip_normal = false);

// Adds condition-① samples (gouge_p / gouge_n): sampling.gouge_along of
// them on each iso-v line at `lines` — over the surface's whole u range
// (gouge_whole_u) or ±gouge_half_mm along the feed around u, where |pu| is
// pu_norm. sample_strip takes a contact's every gouge_stride-th line across;
// a row can sample its lines once for all its contacts.
void add_gouge_lines(StripSamples& samples, const Surface& surface, double u, double pu_norm,
                     const std::vector<double>& lines, const StripSampling& sampling, bool flip_normal = false);

// Adds condition-① samples on a flank beyond an edge region: at flank
// parameter u_f (the contact's span) ± half_width_mm along the flank's u,
// and from the flank's edge end (v = end_v, 0 or 1) gouge_half_mm of arc
// into the flank, so a flat bottom reaching over a concave flank past the
// edge region is seen. Normals pu x pv of the flank (out of the material).
void add_flank_samples(StripSamples& samples, const Surface& flank, double u_f, double end_v,
                       const StripSampling& sampling);

struct Band {
  double e1_mm = -0.001;  // overcut limit (<= 0)
  double e2_mm = 0.02;    // undercut limit (> e1)
};

struct StripWidth {
  bool gouges = false;       // condition ① violated somewhere
  // Smallest directed distance over all samples — exact where it is below
  // 0; where no sample is inside the cutter a ContactStrip may report a
  // lower bound >= 0 instead (it screens samples by tiles), and where one
  // gouges, the first it found below e1 (the deepest may lie deeper;
  // ContactStrip::deepest finds it).
  double deepest_mm = 0;
  bool touches = false;      // condition ②
  double left_mm = 0, right_mm = 0;  // strip extent towards -pv / +pv from C
  double width_mm = 0;       // left + right; 0 when gouging or not touching
};

// Directed distance from a design point along its normal to the cutter of
// `tool` at `pose` (sphere tracing, both ways); +cap_mm when the normal
// misses the cutter within cap_mm.
double directed_distance(const FlatEnd& cutter, const Eigen::Isometry3d& part_to_tool, const Vec3& p,
                         const Vec3& n, double cap_mm);

StripWidth strip_width(const Tool& tool, const ToolPose& pose, const StripSamples& samples, const Band& band);
// Condition ① alone: the smallest directed distance over every sample.
double deepest_distance(const Tool& tool, const ToolPose& pose, const StripSamples& samples, const Band& band);

// --- optimisation (§3.2) ----------------------------------------------------

// The paper's two-sided variable-step search of φ for a width function:
// from -90° stepping up and from +90° stepping down, each climbs with step
// start_step while the width grows, then turns back with the step halved,
// until the step is below min_step; the better of the two maxima wins.
struct SideSlipSearch {
  double start_step_rad = 10.0 * kPi / 180.0;
  double min_step_rad = 0.05 * kPi / 180.0;
};
struct SearchResult {
  double phi_rad = 0, width_mm = 0;  // the better of the two
  double phi_from_minus_rad = 0, width_from_minus_mm = 0;  // the climb from -90°
  double phi_from_plus_rad = 0, width_from_plus_mm = 0;    // the climb from +90°
  int evaluations = 0;
};
template <class F>
SearchResult search_side_slip(F width, const SideSlipSearch& s);

// A run of consecutive samples (neighbours on the surface) within `radius`
// of `centre`: the cutter's signed distance is 1-Lipschitz, so a tile whose
// centre is more than its radius outside the cutter has no sample inside.
struct SampleTile {
  Vec3 centre = Vec3::Zero();
  double radius = 0;
  size_t begin = 0, end = 0;
  // A box about the centre holding the samples (a group's: all its tiles'
  // samples; infinite where their normals cancel): axes[2] the samples' mean normal, half[i] their
  // largest offset along axes[i]. Under a flat bottom lying on the surface
  // a tile's sphere reaches above the bottom plane while its samples lie
  // within microns below it: the box tells them outside from one product
  // per axis (screen_deepest).
  Vec3 axes[3] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  double half[3] = {kInf, kInf, kInf};
};
// Tiles of 8 samples, and groups of 8 consecutive tiles bounding them (a
// group's begin/end index tiles): a row's shared samples span the whole
// round and both flanks, a few mm of which the cutter can reach, so most
// of a pose's screening ends at the groups.
struct SampleTiles {
  std::vector<SampleTile> tiles, groups;
};

// Condition-① samples several contacts share — a row's flanks beyond the
// edge region, over half of each contact's samples — with their tiles, held
// once however many contacts the row has.
struct SharedGougeSamples {
  std::vector<Vec3> p, n;
  SampleTiles tiles;
};
std::shared_ptr<const SharedGougeSamples> share_gouge_samples(std::vector<Vec3> p, std::vector<Vec3> n);

// One contact: samples + the width of any bottom/corner position there.
class ContactStrip {
 public:
  // `shared` (may be null): more condition-① samples, as if appended to
  // samples.gouge_p / gouge_n.
  ContactStrip(const Tool& tool, const EdgeFrame& frame, StripSamples samples, Band band,
               std::shared_ptr<const SharedGougeSamples> shared = nullptr);
  StripWidth width(const EdgePosition& pos) const;
  StripWidth width(const ToolPose& pose) const;  // any pose (e.g. one tilted clear of the world)
  ToolPose pose(const EdgePosition& pos) const;
  const EdgeFrame& frame() const { return frame_; }
  const FlatEnd& flat_end() const { return flat_; }
  // Smallest directed distance over this contact's samples from the cutter
  // at any pose (e.g. between two planned poses): condition ① for motion.
  double deepest(const ToolPose& pose) const;

 private:
  FlatEnd flat_;
  EdgeFrame frame_;
  StripSamples samples_;
  Band band_;
  // Condition ① screens thousands of samples per pose (the flanks' and the
  // region's beyond the strip), most far outside the cutter: by tiles.
  SampleTiles tiles_, gouge_tiles_;
  std::shared_ptr<const SharedGougeSamples> shared_;
};

struct BottomOptimum {
  bool feasible = false;     // some bottom position satisfies ①-③
  double phi_rad = 0;        // the paper's φ: averaged over the l_j
  std::vector<double> l_mm;  // the discretised l_j
  std::vector<double> phi_j_rad, width_j_mm;  // per l_j: its best φ and width
  int evaluations = 0;
};
// §3.2 first part: φ by the two-sided search for each l_j in [r_e, R - r]
// (l_count values), averaged.
BottomOptimum optimise_side_slip(const ContactStrip& strip, double r_e_mm, int l_count, const SideSlipSearch& s);

// Beyond the paper: the best (l, φ) jointly — the same two-sided search of
// φ at every l_j, taking the pair with the widest strip rather than the
// average φ (which can fall between two peaks). Returns width and position.
struct JointOptimum {
  bool feasible = false;
  EdgePosition position;
  double width_mm = 0;
};
JointOptimum optimise_jointly(const ContactStrip& strip, double r_e_mm, int l_count, const SideSlipSearch& s);

// The conventional side-edge position: contact on the corner torus, φ = 0,
// the smallest lead θ >= min_lead_rad (in 0.5° steps up to 60°) that does
// not gouge. feasible = false when none.
struct CornerPosition {
  bool feasible = false;
  EdgePosition position;
  StripWidth width;
};
CornerPosition corner_min_lead(const ContactStrip& strip, double min_lead_rad);

// §3.2 second part, l balanced along a row: widths[i][j] is contact i's
// width at l_j (0 = infeasible). The row's width is the smallest over the
// contacts of their best width; each contact then takes the largest l_j
// (cutting speed) whose width still reaches it. Returns the chosen index j
// per contact (-1: no feasible l) and the row width.
struct BalancedRow {
  std::vector<int> l_index;
  double width_mm = 0;
};
BalancedRow balance_l(const std::vector<std::vector<double>>& widths);

// ---- template definition ----------------------------------------------------

template <class F>
SearchResult search_side_slip(F width, const SideSlipSearch& s) {
  SearchResult best;
  best.width_mm = -1;
  const double lo = -kPi / 2, hi = kPi / 2;
  for (int side = 0; side < 2; ++side) {
    double phi = side == 0 ? lo : hi;
    double step = side == 0 ? s.start_step_rad : -s.start_step_rad;
    double w = width(phi);
    ++best.evaluations;
    while (std::abs(step) >= s.min_step_rad) {
      const double next = std::clamp(phi + step, lo, hi);
      const double wn = next == phi ? -2.0 : width(next);
      if (next != phi) ++best.evaluations;
      if (wn > w) {
        phi = next;
        w = wn;
      } else {
        step = -step / 2;  // overshot the peak (or hit the end): turn back, finer
      }
    }
    (side == 0 ? best.phi_from_minus_rad : best.phi_from_plus_rad) = phi;
    (side == 0 ? best.width_from_minus_mm : best.width_from_plus_mm) = w;
    if (w > best.width_mm) {
      best.width_mm = w;
      best.phi_rad = phi;
    }
  }
  return best;
}

}  // namespace bliskrun
