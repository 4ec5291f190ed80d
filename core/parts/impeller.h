#pragma once
// A centrifugal impeller with ruled blades, from hub and shroud camber data
// (impeller paper §2–3, eq. 1–11, and the hub of §4.3.2, eq. 26–29).
//
// Per blade the design gives two lists of camber-surface points with the
// blade's half thickness, (x, y, z, h), one on the shroud and one on the hub,
// each ordered leading edge -> trailing edge (along the flow):
//   - pairing rule: hub point i and shroud point i lie on one ruling, so
//     both lists have as many points (else ParameterError);
//   - each list is interpolated by the kernel's cubic, both at the average
//     of the two lists' chord-length parameters t in [0, 1] (end tangents
//     estimated as for grids), and h by a cubic in the same parameter, so
//     h(t), h'(t) are smooth (eq. 1–3);
//   - the camber surface joins equal-parameter points: r_m(t, s) =
//     r_hub(t) + (r_shroud(t) - r_hub(t)) s (eq. 4, s in [0, 1] hub -> shroud);
//   - the normal of the camber surface along each boundary curve is
//     N = r_t x (r_shroud - r_hub) (eq. 5–8), and the blade faces are the
//     ruled surfaces between the variable-distance offsets r ± h n of the
//     hub and shroud curves (eq. 9–11). `CamberSide::kPlus` is the face on
//     the side of +N.
// The derivative of N used for the offsets' tangents (eq. 15–20) is the full
// one, N_t = r_tt x (r_s - r_h) + r_t x (r_s_t - r_h_t); the paper's eq. 19–20
// drop the second term, which is not zero unless the rulings stay parallel.
//
// Faces are exposed in the SPEC §2 orientation: u runs along the span
// (hub -> shroud), v along the chord, and pu x pv points out of the material.
// On the kPlus face v runs TE -> LE, on the kMinus face LE -> TE (only that
// choice gives outward normals on both with u hub -> shroud).
//
// Frame: Z is the impeller axis. Blade k (k = 0 .. blade_count-1) is the
// design blade turned by 2 pi k / blade_count about +Z; splitter k is the
// splitter design turned by 2 pi (k + splitter_offset_pitch) / blade_count.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/common/types.h"
#include "core/geometry/curve.h"
#include "core/geometry/revolution.h"
#include "core/geometry/surface.h"
#include "core/io/impeller_definition.h"

namespace bliskrun {

enum class CamberSide { kPlus, kMinus };  // side of +N / -N (eq. 5–6)

// One blade in its design position.
class RuledBlade {
 public:
  // Throws ParameterError("<name>.shroud" / "<name>.hub", ...) for fewer than
  // 4 points, non-finite values, h <= 0, coincident consecutive points or
  // lists of different lengths (the pairing rule above).
  RuledBlade(const BladeCamber& camber, const std::string& name = "camber");

  CurveDerivs shroud_curve(double t) const { return shroud_.eval(t); }
  CurveDerivs hub_curve(double t) const { return hub_.eval(t); }
  // h and dh/dt along each curve.
  Vec2 shroud_half_thickness(double t) const;
  Vec2 hub_half_thickness(double t) const;

  // Eq. 4.
  Vec3 camber_point(double t, double s) const;
  // Unit camber normal n at the shroud (s = 1) or hub (s = 0) curve (eq. 7–8).
  Vec3 camber_normal(double t, bool at_shroud) const;

  // A point of a boundary curve of a face (eq. 9–10) with its tangent
  // d/dt (eq. 15–16, with the full N_t above).
  struct OffsetPoint {
    Vec3 p = Vec3::Zero();
    Vec3 dt = Vec3::Zero();
  };
  OffsetPoint shroud_offset(double t, CamberSide side) const;
  OffsetPoint hub_offset(double t, CamberSide side) const;

  // The face (eq. 11) in the SPEC orientation (see the header comment).
  // Second derivatives along the chord are central differences of the
  // analytic first derivatives (step 1e-5 in t).
  std::shared_ptr<const Surface> face(CamberSide side) const;

  // Chord parameter t of face parameter v (the kPlus face runs TE -> LE).
  static double chord_t(CamberSide side, double v) { return side == CamberSide::kPlus ? 1 - v : v; }

 private:
  OffsetPoint offset(double t, CamberSide side, bool at_shroud) const;

  BSplineCurve shroud_, hub_;
  BSplineCurve h_shroud_, h_hub_;  // (h, 0, 0) against t
};

// The design data (ImpellerDefinition, core/io/impeller_definition.h) checked:
// throws ParameterError naming the first invalid field.
void validate(const ImpellerDefinition& d);

enum class BladeKind { kMain, kSplitter };

class Impeller {
 public:
  explicit Impeller(ImpellerDefinition definition);

  const ImpellerDefinition& definition() const { return def_; }
  int blade_count() const { return def_.blade_count; }
  bool has_splitter() const { return splitter_.has_value(); }

  const RuledBlade& blade(BladeKind kind) const;  // design position
  // Rotation of blade / splitter k about +Z (rad).
  double blade_angle_rad(BladeKind kind, int k) const;
  // A face of blade k (0 <= k < blade_count), turned into place.
  std::shared_ptr<const Surface> face(BladeKind kind, int k, CamberSide side) const;

  // Hub of revolution of the main blade's hub camber curve (eq. 26–29):
  // the (z, r) of that curve, evaluated from the curve itself (no
  // interpolant between), extended at both ends by hub_extension_mm along
  // its end tangents, about Z. hub_meridian() lists samples of that profile
  // (the extension ends, 65 points along the curve), TE -> LE.
  const SurfaceOfRevolution& hub() const { return *hub_; }
  const std::vector<Vec2>& hub_meridian() const { return hub_meridian_; }

  // Largest distance from the axis of any blade point (samples of the
  // boundary offset curves).
  double outer_radius_mm() const;

 private:
  ImpellerDefinition def_;
  RuledBlade main_;
  std::optional<RuledBlade> splitter_;
  std::vector<Vec2> hub_meridian_;
  std::shared_ptr<SurfaceOfRevolution> hub_;
};

// The built-in parametric impeller (SPEC §11): a backswept centrifugal
// compressor impeller at the paper's scale (§6: φ410 mm, 17 blades).
// Meridian: hub and shroud are quarter ellipses from the axial inlet
// (z = inlet_z_mm) to the radial outlet (r = outlet_radius_mm); the hub meets
// the outlet at z = 0, the shroud at z = outlet_width_mm.
// Along the shroud the blade angle beta (from the meridional direction)
// varies linearly with the normalised meridional length from beta_inlet to
// beta_outlet, the wrap following r dtheta/dm = -tan(beta): for a rotor
// turning towards +theta the blades lean back against the rotation
// (backswept at the outlet) and face the incoming relative flow at the
// inlet. The hub point at the same meridional fraction has the same theta,
// so each ruling lies in a meridional plane (no rake).
// Half thickness: le + (te - le) s + (max - (le + te)/2) sin^2(pi s).
struct BuiltinImpellerParams {
  int blade_count = 17;
  bool splitters = true;
  double splitter_start = 0.35;  // fraction of the meridional length where splitters start
  double outlet_radius_mm = 205.0;
  double outlet_width_mm = 18.0;
  double inlet_z_mm = 95.0;
  double hub_inlet_radius_mm = 55.0;
  double shroud_inlet_radius_mm = 135.0;
  double beta_inlet_rad = 58.0 * kPi / 180.0;   // at the shroud
  double beta_outlet_rad = 40.0 * kPi / 180.0;  // backsweep from radial
  double half_thickness_le_mm = 0.9;
  double half_thickness_te_mm = 1.2;
  double half_thickness_max_hub_mm = 2.6;
  double half_thickness_max_shroud_mm = 1.6;
  int camber_points = 25;  // per curve, spaced closer near the edges (as design data are)
};

// Throws ParameterError naming the first invalid parameter.
void validate(const BuiltinImpellerParams& p);
ImpellerDefinition builtin_impeller_definition(const BuiltinImpellerParams& p = {});

}  // namespace bliskrun
