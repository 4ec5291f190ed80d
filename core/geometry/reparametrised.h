#pragma once
// A surface turned about Z, and a surface with its parameters swapped or
// reversed: exact (derivatives by the chain rule), shared by the parts that
// repeat a blade around the axis (impeller.cpp, cad_blisk.cpp) and those
// that orient a CAD face (cad_blisk.cpp); the chain rule of a face trimmed
// in u.
#include <memory>
#include <utility>

#include "core/geometry/surface.h"

namespace bliskrun {

// s turned by angle_rad about +Z: R p(u, v).
class RotatedSurface : public Surface {
 public:
  RotatedSurface(std::shared_ptr<const Surface> s, double angle_rad)
      : s_(std::move(s)), r_(Eigen::AngleAxisd(angle_rad, Vec3::UnitZ()).toRotationMatrix()) {}
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d = s_->eval(u, v);
    for (Vec3* x : {&d.p, &d.pu, &d.pv, &d.puu, &d.puv, &d.pvv}) *x = r_ * *x;
    return d;
  }
  const Surface& base() const { return *s_; }

 private:
  std::shared_ptr<const Surface> s_;
  Mat3 r_;
};

// s with its parameters swapped and/or reversed: with a = (flip_u ? 1 - u :
// u), b = (flip_v ? 1 - v : v), the point is s(b, a) when swapped, else
// s(a, b).
class ReorientedSurface : public Surface {
 public:
  ReorientedSurface(std::shared_ptr<const Surface> s, bool swap, bool flip_u, bool flip_v)
      : s_(std::move(s)), swap_(swap), flip_u_(flip_u), flip_v_(flip_v) {}
  SurfaceDerivs eval(double u, double v) const override {
    const double a = flip_u_ ? 1 - u : u, b = flip_v_ ? 1 - v : v;
    const SurfaceDerivs q = swap_ ? s_->eval(b, a) : s_->eval(a, b);
    const double su = flip_u_ ? -1 : 1, sv = flip_v_ ? -1 : 1;
    SurfaceDerivs d;
    d.p = q.p;
    d.pu = su * (swap_ ? q.pv : q.pu);
    d.pv = sv * (swap_ ? q.pu : q.pv);
    d.puu = swap_ ? q.pvv : q.puu;
    d.pvv = swap_ ? q.puu : q.pvv;
    d.puv = su * sv * q.puv;
    return d;
  }

 private:
  std::shared_ptr<const Surface> s_;
  bool swap_, flip_u_, flip_v_;
};

// The derivatives of p(U(u, v), v) with U = lo(v) + u w(v) (a face's u
// trimmed between two curves in its parameters; trimmed_surface.cpp,
// point_milling.cpp's face above the fillet line) from b, the base's at
// (U, v): w = dU/du, dw = w', Uv = dU/dv, Uvv = d2U/dv2.
inline SurfaceDerivs chain_trimmed_u(const SurfaceDerivs& b, double w, double dw, double Uv, double Uvv) {
  SurfaceDerivs d;
  d.p = b.p;
  d.pu = b.pu * w;
  d.pv = b.pu * Uv + b.pv;
  d.puu = b.puu * (w * w);
  d.puv = (b.puu * Uv + b.puv) * w + b.pu * dw;
  d.pvv = b.puu * (Uv * Uv) + 2.0 * b.puv * Uv + b.pvv + b.pu * Uvv;
  return d;
}

}  // namespace bliskrun
