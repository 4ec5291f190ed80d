#include "core/parts/ruled_fit.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/geometry/interpolation.h"

namespace bliskrun {

namespace {

// p(u, v) = H(v) + u (S(v) - H(v)), exact in u outside [0, 1] too.
class RuledSurface : public Surface {
 public:
  RuledSurface(BSplineCurve hub, BSplineCurve tip) : hub_(std::move(hub)), tip_(std::move(tip)) {}
  SurfaceDerivs eval(double u, double v) const override {
    const CurveDerivs h = hub_.eval(v), t = tip_.eval(v);
    SurfaceDerivs d;
    d.p = h.p + (t.p - h.p) * u;
    d.pu = t.p - h.p;
    d.pv = h.dt + (t.dt - h.dt) * u;
    d.puv = t.dt - h.dt;
    d.pvv = h.dtt + (t.dtt - h.dtt) * u;
    return d;
  }

 private:
  BSplineCurve hub_, tip_;
};

}  // namespace

RuledFit fit_ruled(const PointGrid& grid, int row0, int row1) {
  if (row0 < 0 || row1 >= grid.rows || row1 - row0 < 1)
    throw ParameterError("rows", "expected 0 <= row0 < row1 < " + std::to_string(grid.rows) + ", got " +
                                     std::to_string(row0) + ", " + std::to_string(row1));
  if (grid.cols < 4) throw ParameterError("grid", "expected at least 4 columns");
  RuledFit fit;
  std::vector<Vec3> hub_ends, tip_ends;
  double sum2 = 0;
  long n = 0;
  for (int j = 0; j < grid.cols; ++j) {
    Vec3 c = Vec3::Zero();
    for (int i = row0; i <= row1; ++i) c += grid.at(i, j);
    c /= (row1 - row0 + 1);
    Mat3 cov = Mat3::Zero();
    for (int i = row0; i <= row1; ++i) {
      const Vec3 d = grid.at(i, j) - c;
      cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
    Vec3 dir = eig.eigenvectors().col(2);  // largest eigenvalue: the line's direction
    if (dir.dot(grid.at(row1, j) - grid.at(row0, j)) < 0) dir = -dir;
    for (int i = row0; i <= row1; ++i) {
      const Vec3 d = grid.at(i, j) - c;
      const double dist = (d - d.dot(dir) * dir).norm();
      sum2 += dist * dist;
      ++n;
      if (dist > fit.max_mm) {
        fit.max_mm = dist;
        fit.worst_row = i;
        fit.worst_col = j;
      }
    }
    hub_ends.push_back(c + (grid.at(row0, j) - c).dot(dir) * dir);
    tip_ends.push_back(c + (grid.at(row1, j) - c).dot(dir) * dir);
  }
  fit.rms_mm = std::sqrt(sum2 / n);
  std::vector<double> th = chord_length_parameters(hub_ends), tt = chord_length_parameters(tip_ends);
  for (size_t k = 0; k < th.size(); ++k) th[k] = tt[k] = 0.5 * (th[k] + tt[k]);
  fit.surface = std::make_shared<RuledSurface>(interpolate_cubic(hub_ends, th), interpolate_cubic(tip_ends, tt));
  return fit;
}

}  // namespace bliskrun
