#include "core/geometry/projection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/error.h"
#include "core/common/progress.h"

namespace bliskrun {

namespace {

struct Seed {
  double u, v, d2;
};

// Projected Newton on f(u, v) = |S(u, v) - q|^2 / 2 over [0, 1]^2. A variable
// sitting on its bound with the gradient pushing outwards is held there and
// the other one is minimised alone, so feet on edges and corners come out
// exactly on them.
SurfaceProjection newton_surface(const Surface& s, const Vec3& q, double u, double v,
                                 const ProjectionOptions& o) {
  SurfaceProjection r;
  for (int it = 0; it < o.max_iterations; ++it) {
    const SurfaceDerivs d = s.eval(u, v);
    const Vec3 e = d.p - q;
    Eigen::Vector2d g(e.dot(d.pu), e.dot(d.pv));
    Eigen::Matrix2d H;
    H << d.pu.dot(d.pu) + e.dot(d.puu), d.pu.dot(d.pv) + e.dot(d.puv),
        d.pu.dot(d.pv) + e.dot(d.puv), d.pv.dot(d.pv) + e.dot(d.pvv);
    // Gauss-Newton when the full Hessian is not positive definite (far from
    // a minimum on a strongly curved surface).
    if (H.determinant() <= 0 || H(0, 0) <= 0) {
      H << d.pu.dot(d.pu), d.pu.dot(d.pv), d.pu.dot(d.pv), d.pv.dot(d.pv);
    }
    const bool hold_u = (u <= 0 && g.x() > 0) || (u >= 1 && g.x() < 0);
    const bool hold_v = (v <= 0 && g.y() > 0) || (v >= 1 && g.y() < 0);
    Eigen::Vector2d step(0, 0);
    if (!hold_u && !hold_v) {
      step = -H.ldlt().solve(g);
    } else if (!hold_u) {
      step.x() = -g.x() / H(0, 0);
    } else if (!hold_v) {
      step.y() = -g.y() / H(1, 1);
    }
    // Damp: never move more than a quarter of the domain at once.
    const double big = std::max(std::abs(step.x()), std::abs(step.y()));
    if (big > 0.25) step *= 0.25 / big;
    const double nu = std::clamp(u + step.x(), 0.0, 1.0);
    const double nv = std::clamp(v + step.y(), 0.0, 1.0);
    const double moved = (d.pu * (nu - u) + d.pv * (nv - v)).norm();
    u = nu;
    v = nv;
    if (moved < o.tol_mm) {
      const SurfaceDerivs f = s.eval(u, v);
      const Vec3 ef = f.p - q;
      // Optimality (KKT): the residual is orthogonal to every free tangent
      // direction; on a bound only the inward direction must not descend.
      // Tangential residual in mm: the foot is off by about this much.
      const double gu = ef.dot(f.pu) / f.pu.norm();
      const double gv = ef.dot(f.pv) / f.pv.norm();
      const double slack = std::max(10 * o.tol_mm, 1e-6 * ef.norm());
      const bool ok_u = std::abs(gu) < slack || (u <= 0 && gu > 0) || (u >= 1 && gu < 0);
      const bool ok_v = std::abs(gv) < slack || (v <= 0 && gv > 0) || (v >= 1 && gv < 0);
      if (ok_u && ok_v) {
        r.ok = true;
        r.u = u;
        r.v = v;
        r.point = f.p;
        r.distance = ef.norm();
        r.on_boundary = u <= 0 || u >= 1 || v <= 0 || v >= 1;
        return r;
      }
    }
  }
  r.failure = "Newton iteration did not converge in " + std::to_string(o.max_iterations) +
              " steps from (" + std::to_string(u) + ", " + std::to_string(v) + ")";
  return r;
}

}  // namespace

SurfaceProjection project_to_surface(const Surface& s, const Vec3& q, const ProjectionOptions& o) {
  if (o.seed) {
    SurfaceProjection r = newton_surface(s, q, std::clamp(o.seed->x(), 0.0, 1.0), std::clamp(o.seed->y(), 0.0, 1.0), o);
    if (r.ok) return r;
  }
  const int nu = std::max(2, o.seed_samples_u), nv = std::max(2, o.seed_samples_v);
  // Seeds: the best few local minima of the coarse sample grid, so that a
  // surface folding back towards q still finds the global foot.
  std::vector<double> d2(static_cast<size_t>(nu) * nv);
  for (int i = 0; i < nu; ++i) {
    cancellation_point();
    for (int j = 0; j < nv; ++j)
      d2[static_cast<size_t>(i) * nv + j] =
          (s.point(static_cast<double>(i) / (nu - 1), static_cast<double>(j) / (nv - 1)) - q).squaredNorm();
  }
  std::vector<Seed> seeds;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double here = d2[static_cast<size_t>(i) * nv + j];
      bool local_min = true;
      for (int di = -1; di <= 1 && local_min; ++di)
        for (int dj = -1; dj <= 1; ++dj) {
          const int a = i + di, b = j + dj;
          if ((di || dj) && a >= 0 && a < nu && b >= 0 && b < nv &&
              d2[static_cast<size_t>(a) * nv + b] < here) {
            local_min = false;
            break;
          }
        }
      if (local_min)
        seeds.push_back({static_cast<double>(i) / (nu - 1), static_cast<double>(j) / (nv - 1), here});
    }
  std::sort(seeds.begin(), seeds.end(), [](const Seed& a, const Seed& b) { return a.d2 < b.d2; });
  if (seeds.size() > 4) seeds.resize(4);

  SurfaceProjection best;
  best.distance = kInf;
  std::string failure;
  for (const Seed& seed : seeds) {
    SurfaceProjection r = newton_surface(s, q, seed.u, seed.v, o);
    if (r.ok && r.distance < best.distance) best = r;
    if (!r.ok) failure = r.failure;
  }
  if (!best.ok) {
    best.failure = failure.empty() ? "no seed found" : failure;
    best.distance = 0;
  }
  return best;
}

std::vector<Vec3> curve_seed_samples(const Curve& c, const ProjectionOptions& o) {
  const double t0 = c.t_min(), t1 = c.t_max();
  const int n = std::max(8, o.seed_samples_u * 4);
  std::vector<Vec3> out(n + 1);
  for (int i = 0; i <= n; ++i) out[i] = c.point(t0 + (t1 - t0) * i / n);
  return out;
}

CurveProjection project_to_curve(const Curve& c, const Vec3& q, const ProjectionOptions& o) {
  return project_to_curve(c, q, o, curve_seed_samples(c, o));
}

CurveProjection project_to_curve(const Curve& c, const Vec3& q, const ProjectionOptions& o,
                                 const std::vector<Vec3>& samples) {
  const double t0 = c.t_min(), t1 = c.t_max();
  const int n = static_cast<int>(samples.size()) - 1;
  if (n < 1) throw ParameterError("seed_samples", "need at least 2 seed samples on the curve");
  std::vector<double> d2(n + 1);
  for (int i = 0; i <= n; ++i) d2[i] = (samples[i] - q).squaredNorm();
  std::vector<std::pair<double, double>> seeds;  // (d2, t)
  for (int i = 0; i <= n; ++i)
    if ((i == 0 || d2[i] <= d2[i - 1]) && (i == n || d2[i] <= d2[i + 1]))
      seeds.push_back({d2[i], t0 + (t1 - t0) * i / n});
  std::sort(seeds.begin(), seeds.end());
  if (seeds.size() > 4) seeds.resize(4);

  CurveProjection best;
  best.distance = kInf;
  std::string failure;
  for (const auto& seed : seeds) {
    double t = seed.second;
    bool converged = false;
    for (int it = 0; it < o.max_iterations; ++it) {
      const CurveDerivs d = c.eval(t);
      const Vec3 e = d.p - q;
      const double g = e.dot(d.dt);
      double h = d.dt.dot(d.dt) + e.dot(d.dtt);
      if (h <= 0) h = d.dt.dot(d.dt);
      if ((t <= t0 && g > 0) || (t >= t1 && g < 0)) { converged = true; break; }
      double step = -g / h;
      step = std::clamp(step, -0.25 * (t1 - t0), 0.25 * (t1 - t0));
      const double nt = std::clamp(t + step, t0, t1);
      const double moved = d.dt.norm() * std::abs(nt - t);
      t = nt;
      if (moved < o.tol_mm) {
        const CurveDerivs f = c.eval(t);
        const Vec3 ef = f.p - q;
        const double gn = ef.dot(f.dt) / f.dt.norm();  // tangential residual, mm
        if (std::abs(gn) < std::max(10 * o.tol_mm, 1e-6 * ef.norm()) || (t <= t0 && gn > 0) ||
            (t >= t1 && gn < 0)) {
          converged = true;
          break;
        }
      }
    }
    if (!converged) {
      // Newton can cycle where the curve's second derivative jumps (a
      // cubic through unevenly spaced meridian points). The seed is a
      // sampled local minimum, so the foot lies within one sample spacing:
      // golden-section search there is slower but cannot fail.
      const double h = (t1 - t0) / n;
      double a = std::max(t0, seed.second - h), b = std::min(t1, seed.second + h);
      const double r = 0.5 * (std::sqrt(5.0) - 1);
      double x1 = b - r * (b - a), x2 = a + r * (b - a);
      double f1 = (c.point(x1) - q).squaredNorm(), f2 = (c.point(x2) - q).squaredNorm();
      for (int it = 0; it < 200 && (b - a) * c.eval(0.5 * (a + b)).dt.norm() > 0.1 * o.tol_mm; ++it) {
        if (f1 <= f2) {
          b = x2; x2 = x1; f2 = f1;
          x1 = b - r * (b - a); f1 = (c.point(x1) - q).squaredNorm();
        } else {
          a = x1; x1 = x2; f1 = f2;
          x2 = a + r * (b - a); f2 = (c.point(x2) - q).squaredNorm();
        }
      }
      t = 0.5 * (a + b);
      if (!((b - a) * c.eval(t).dt.norm() <= 0.1 * o.tol_mm)) {
        failure = "neither Newton iteration nor golden-section search on the curve converged";
        continue;
      }
    }
    const Vec3 p = c.point(t);
    const double dist = (p - q).norm();
    if (dist < best.distance) {
      best.ok = true;
      best.t = t;
      best.point = p;
      best.distance = dist;
    }
  }
  if (!best.ok) {
    best.failure = failure.empty() ? "no seed found" : failure;
    best.distance = 0;
  }
  return best;
}

}  // namespace bliskrun
