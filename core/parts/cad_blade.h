#pragma once
// A blade from CAD (issue 36 item 3): a closed airfoil surface split into its
// two flanks at the leading and trailing edges, and the hub and casing of
// revolution from meridian curves. The flanks are exact re-parametrisations
// of the CAD surface (windows of it, and the cylindrical wrap below when the
// file is in unwrapped coordinates), not fits.
#include <memory>
#include <string>

#include "core/geometry/curve.h"
#include "core/geometry/revolution.h"
#include "core/geometry/surface.h"

namespace bliskrun {

// How the file's (x, y, z) relate to bliskrun's frame (rotation axis Z).
enum class CadCoordinates {
  kCartesianZ,  // already bliskrun's: axis Z, radius hypot(x, y)
  // Turbomachinery "unwrapped" coordinates as NASA's E3 files use them:
  // x axial, y = R theta (arc length at radius R), z = R. Mapped exactly to
  // (R cos(y/R), R sin(y/R), x - axial_origin).
  kAxialRthetaR,
};

// s(u, v) mapped from unwrapped (x, R theta, R) to Cartesian about Z, with
// derivatives by the chain rule (exact, to second order).
class UnwrappedSurface : public Surface {
 public:
  UnwrappedSurface(std::shared_ptr<const Surface> unwrapped, double axial_origin_mm);
  SurfaceDerivs eval(double u, double v) const override;

 private:
  std::shared_ptr<const Surface> s_;
  double origin_;
};

struct CadBladeOptions {
  CadCoordinates coordinates = CadCoordinates::kCartesianZ;
  double axial_origin_mm = 0;  // the file's axial coordinate that becomes z = 0
  int samples = 2000;          // chordwise samples that find the edges
};

struct CadBlade {
  // u hub -> tip, v along the chord; pu x pv points out of the material on
  // both. The suction flank is the convex one (normal curvature along the
  // chord below the pressure flank's, with outward normals).
  std::shared_ptr<const Surface> pressure, suction;
  // The airfoil in bliskrun's frame (after the wrap, if any).
  std::shared_ptr<const Surface> airfoil;
  // Chordwise parameter of the closed surface at the leading edge (lowest
  // axial z at mid-span) and at the trailing edge (highest), and whether
  // the closed direction is the surface's u (else its v).
  double le = 0, te = 0;
  bool closed_in_u = true;
};

// Splits a surface closed in one parameter direction (the airfoil around)
// and open in the other (hub to tip) into its two flanks. Throws
// ParameterError when the surface does not close in either direction (end
// gap above 1e-6 of its size), or when the edges cannot be told apart.
CadBlade cad_blade(std::shared_ptr<const Surface> closed, const CadBladeOptions& options = {});

// A hub or casing of revolution from a meridian curve of the file: `samples`
// points of it as (axial, radius) in bliskrun's frame — for kAxialRthetaR,
// axial = x - axial_origin and radius = hypot(y, z) (a curve in the plane
// z = 0 with y the radius, as E3's hub.igs); for kCartesianZ, axial = z and
// radius = hypot(x, y). Throws ParameterError when the axial coordinate does
// not increase along the curve (a profile must be single-valued).
SurfaceOfRevolution revolution_from_curve(const Curve& meridian, const CadBladeOptions& options,
                                          int samples = 200);

}  // namespace bliskrun
