#include "core/planning/trimmed_surface.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/reparametrised.h"

namespace bliskrun {

namespace {

BSplineCurve fit_boundary(const std::vector<double>& v, const std::vector<double>& u) {
  if (v.size() != u.size() || v.size() < 4)
    throw ParameterError("boundary", "needs at least 4 (v, u) samples of equal count");
  for (size_t i = 1; i < v.size(); ++i)
    if (!(v[i] > v[i - 1]))
      throw ParameterError("boundary", "v samples must increase strictly (sample " +
                                           std::to_string(i) + ")");
  if (v.front() > 1e-9 || v.back() < 1 - 1e-9)
    throw ParameterError("boundary", "v samples must cover [0, 1]");
  std::vector<Vec3> points(u.size());
  for (size_t i = 0; i < u.size(); ++i) points[i] = Vec3(u[i], 0, 0);
  // The parameter of the fit is v itself, so derivatives are du/dv directly.
  std::vector<double> params(v);
  params.front() = 0;
  params.back() = 1;
  return interpolate_cubic(points, params);
}

}  // namespace

ParameterBoundary::ParameterBoundary(const std::vector<double>& v,
                                     const std::vector<double>& u)
    : fit_(fit_boundary(v, u)) {}

ParameterBoundary::Value ParameterBoundary::at(double v) const {
  const CurveDerivs d = fit_.eval(std::clamp(v, 0.0, 1.0));
  return {d.p.x(), d.dt.x(), d.dtt.x()};
}

TrimmedSurface::TrimmedSurface(std::shared_ptr<const Surface> base,
                               ParameterBoundary lower, ParameterBoundary upper)
    : base_(std::move(base)), lower_(std::move(lower)), upper_(std::move(upper)) {
  if (!base_) throw ParameterError("base", "a trimmed surface needs a base surface");
  // Dense check: a crossing of the boundaries would fold the reparametrisation.
  constexpr int kChecks = 1000;
  for (int i = 0; i <= kChecks; ++i) {
    const double v = static_cast<double>(i) / kChecks;
    if (!(upper_.at(v).u > lower_.at(v).u))
      throw ParameterError("boundary", "upper boundary is not above the lower one at v = " +
                                           std::to_string(v));
  }
}

Vec2 TrimmedSurface::base_parameters(double u, double v) const {
  const double u1 = lower_.at(v).u, u2 = upper_.at(v).u;
  return Vec2(u1 + u * (u2 - u1), v);
}

SurfaceDerivs TrimmedSurface::eval(double u, double v) const {
  const auto lo = lower_.at(v), hi = upper_.at(v);
  const double w = hi.u - lo.u;       // dU/du'
  const double dw = hi.du - lo.du;    // d(w)/dv
  const double ddw = hi.ddu - lo.ddu;
  const double U = lo.u + u * w;
  const double Uv = lo.du + u * dw;   // dU/dv
  const double Uvv = lo.ddu + u * ddw;
  return chain_trimmed_u(base_->eval(U, v), w, dw, Uv, Uvv);
}

std::shared_ptr<const TrimmedSurface> trim_between(std::shared_ptr<const Surface> flank,
                                                   const SurfaceOfRevolution& hub,
                                                   const SurfaceOfRevolution& casing, int samples_v) {
  const SurfaceCurveOnSurface lower = intersect_with_revolution(*flank, hub, samples_v);
  const SurfaceCurveOnSurface upper = intersect_with_revolution(*flank, casing, samples_v);
  return std::make_shared<TrimmedSurface>(std::move(flank), ParameterBoundary(lower.v, lower.u),
                                          ParameterBoundary(upper.v, upper.u));
}

}  // namespace bliskrun
