#pragma once
// A flank trimmed between two boundary curves and reparametrised so that its
// iso-u lines run from one boundary to the other (blisk paper §3.1, Fig. 5,
// eq. 16).
//
// The reconstructed flank reaches past hub and tip, as CAD grids do; the
// region to machine lies between flank ∩ hub and flank ∩ casing. Iso-u lines
// of the untrimmed flank leave triangular regions at the root; on the trimmed
// surface every iso-u' line starts on the hub curve (u' = 0) and ends on the
// tip curve (u' = 1).
#include <memory>
#include <vector>

#include "core/geometry/curve.h"
#include "core/geometry/revolution.h"
#include "core/geometry/surface.h"

namespace bliskrun {

// A boundary given in the flank's parameter plane as u = f(v), v in [0, 1]:
// the hub and tip curves of a blade flank cross every iso-v (chordwise
// station) exactly once, which is what makes eq. 16 well defined.
class ParameterBoundary {
 public:
  // Fits a cubic u(v) through (v_i, u_i) samples (v strictly increasing,
  // covering [0, 1]). Throws ParameterError otherwise.
  ParameterBoundary(const std::vector<double>& v, const std::vector<double>& u);
  // u, du/dv, d2u/dv2 at v.
  struct Value { double u, du, ddu; };
  Value at(double v) const;

 private:
  BSplineCurve fit_;  // (u, 0, 0) as a function of parameter v
};

// p'(u', v) = p(u1(v) + u' (u2(v) - u1(v)), v)      (eq. 16)
class TrimmedSurface : public Surface {
 public:
  // `lower` (u1, e.g. the hub curve) must lie below `upper` (u2) for every v;
  // throws ParameterError naming the v where it does not.
  TrimmedSurface(std::shared_ptr<const Surface> base, ParameterBoundary lower,
                 ParameterBoundary upper);

  SurfaceDerivs eval(double u, double v) const override;

  // The base-surface parameters of a trimmed-surface point.
  Vec2 base_parameters(double u, double v) const;
  const Surface& base() const { return *base_; }

 private:
  std::shared_ptr<const Surface> base_;
  ParameterBoundary lower_, upper_;
};

// The flank trimmed between a hub and a casing of revolution (blisk paper
// §3.1): each boundary found along `samples_v` iso-v lines
// (intersect_with_revolution) and fitted as u(v). The region a drum finish
// machines, and the one Table 1 describes.
std::shared_ptr<const TrimmedSurface> trim_between(std::shared_ptr<const Surface> flank,
                                                   const SurfaceOfRevolution& hub,
                                                   const SurfaceOfRevolution& casing, int samples_v = 200);

}  // namespace bliskrun
