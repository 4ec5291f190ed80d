#include "core/repair/damaged_rebuild.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/common/fixed_text.h"
#include "core/common/parallel.h"
#include "core/common/progress.h"
#include "core/common/statistics.h"
#include "core/geometry/point_index.h"
#include "core/repair/section_curve.h"

namespace bliskrun {

namespace {

Vec3 lift(const Vec2& p) { return Vec3(p.x(), p.y(), 0); }

// Least-squares polynomial of degree `degree` through (x, y), evaluated at x0.
double extrapolate(const std::vector<double>& x, const std::vector<double>& y, int degree, double x0) {
  const int n = static_cast<int>(x.size());
  Eigen::MatrixXd A(n, degree + 1);
  Eigen::VectorXd b(n);
  const double xc = x.back();  // centred for conditioning
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d <= degree; ++d) A(i, d) = std::pow(x[i] - xc, d);
    b[i] = y[i];
  }
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
  double out = 0;
  for (int d = 0; d <= degree; ++d) out += c[d] * std::pow(x0 - xc, d);
  return out;
}

// Distance from q to the closed polygon through poly, near its vertex j.
double distance_near(const Vec2& q, const std::vector<Vec2>& poly, int j) {
  const int m = static_cast<int>(poly.size());
  double best = 1e300;
  for (int s = -2; s < 2; ++s) {
    const Vec2& a = poly[((j + s) % m + m) % m];
    const Vec2& b = poly[((j + s + 1) % m + m) % m];
    const double len2 = (b - a).squaredNorm();
    const double t = len2 > 0 ? std::clamp((q - a).dot(b - a) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * (b - a) - q).norm());
  }
  return best;
}

// The parameter of the point of a closed curve nearest to p: the nearest of
// 2048 samples, then Newton on (c(t) - p) . c'(t).
double nearest_parameter(const ClosedCurve& c, const Vec3& p) {
  const int n = 2048;
  const double period = c.t_max() - c.t_min();
  double best_t = c.t_min(), best = 1e300;
  for (int i = 0; i < n; ++i) {
    const double t = c.t_min() + period * i / n;
    const double d = (c.eval(t).p - p).squaredNorm();
    if (d < best) {
      best = d;
      best_t = t;
    }
  }
  double t = best_t;
  for (int it = 0; it < 20; ++it) {
    const CurveDerivs d = c.eval(t);
    const Vec3 r = d.p - p;
    const double f = r.dot(d.dt), df = d.dt.squaredNorm() + r.dot(d.dtt);
    if (!(df > 0)) break;
    const double step = std::clamp(-f / df, -period / n, period / n);
    t += step;
    if (std::abs(step) < 1e-12) break;
  }
  return t;
}

}  // namespace

// The loft's plane section at height h against the design's registered to it.
BetweenSectionCheck check_between(const SectionLoft& loft, const DesignBlade& design, double h, int samples,
                                  const SectionRegistrationOptions& registration) {
  BetweenSectionCheck c;
  c.height_mm = h;
  const std::vector<Vec2> rebuilt = plane_section(loft, design.frame, h, samples);
  std::vector<Vec2> model = plane_section(design.loft, design.frame, h, samples);
  const SectionRegistration r = register_section(rebuilt, model, registration);
  for (Vec2& p : model) p = r.motion.apply(p);
  std::vector<Vec3> lifted;
  double perimeter = 0;
  for (size_t j = 0; j < model.size(); ++j) {
    lifted.push_back(lift(model[j]));
    perimeter += (model[(j + 1) % model.size()] - model[j]).norm();
  }
  const PointIndex index(lifted, perimeter / model.size());
  double sum2 = 0;
  for (const Vec2& p : rebuilt) {
    const int j = index.nearest(lift(p), 1e3);
    const double d = j < 0 ? 1e3 : distance_near(p, model, j);
    c.max_mm = std::max(c.max_mm, d);
    sum2 += d * d;
  }
  c.rms_mm = std::sqrt(sum2 / rebuilt.size());
  return c;
}

Vec2 Rigid2::apply(const Vec2& p) const { return rotate(p, angle_rad) + shift; }

SectionRegistration register_section(const std::vector<Vec2>& points, const std::vector<Vec2>& model,
                                     const SectionRegistrationOptions& o, const Rigid2& initial) {
  const int m = static_cast<int>(model.size());
  if (m < 8) throw ParameterError("model", "a section model needs at least 8 points");
  if (points.size() < 3) throw ParameterError("points", "registration needs at least 3 measured points");
  double perimeter = 0;
  for (int j = 0; j < m; ++j) perimeter += (model[(j + 1) % m] - model[j]).norm();
  if (!(perimeter > 0)) throw ParameterError("model", "the model's points coincide");
  // Unit normals of the model polygon at its vertices (the chord through the
  // two neighbours turned a quarter).
  std::vector<Vec2> normals(m);
  for (int j = 0; j < m; ++j) {
    const Vec2 d = model[(j + 1) % m] - model[(j + m - 1) % m];
    normals[j] = Vec2(d.y(), -d.x()).normalized();
  }
  // The model is moved, the index built once: pair by the measured points
  // moved back into the model's frame.
  std::vector<Vec3> lifted;
  lifted.reserve(m);
  for (const Vec2& p : model) lifted.push_back(lift(p));
  const PointIndex index(lifted, perimeter / m);

  SectionRegistration out;
  out.motion = initial;
  double reach = o.initial_reach_mm;
  double radius = 0;
  for (const Vec2& p : model) radius = std::max(radius, p.norm());
  for (int it = 0; it < o.max_iterations; ++it) {
    cancellation_point();
    out.iterations = it + 1;
    // Measured points into the model frame: R^T (q - t).
    std::vector<double> dist;
    std::vector<std::pair<int, int>> pairs;  // measured, model
    for (size_t i = 0; i < points.size(); ++i) {
      const Vec2 back = rotate(points[i] - out.motion.shift, -out.motion.angle_rad);
      const int j = index.nearest(lift(back), reach);
      if (j < 0) continue;
      pairs.emplace_back(static_cast<int>(i), j);
      dist.push_back(std::abs((back - model[j]).dot(normals[j])));
    }
    if (pairs.size() < 3)
      throw Error("section registration: no measured point within " + std::to_string(reach) + " mm of the model");
    // Solve for a small motion of the moved model: model point x = R p + t,
    // measured q; residual (x + dθ J x + dt - q) . n, n turned with the model.
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    const double cut = std::max(o.min_reach_mm, o.outlier_factor * median(dist));
    double sum2 = 0;
    int inliers = 0;
    for (size_t k = 0; k < pairs.size(); ++k) {
      if (it > 0 && dist[k] > cut) continue;
      const Vec2& q = points[pairs[k].first];
      const Vec2 x = out.motion.apply(model[pairs[k].second]);
      const Vec2 n = rotate(normals[pairs[k].second], out.motion.angle_rad);
      const Eigen::Vector3d a(n.dot(Vec2(-x.y(), x.x())), n.x(), n.y());
      const double r = (x - q).dot(n);
      A += a * a.transpose();
      b -= a * r;
      sum2 += r * r;
      ++inliers;
    }
    out.inliers = inliers;
    out.rms_mm = std::sqrt(sum2 / std::max(inliers, 1));
    if (A(0, 0) < 1e-12 * A.trace()) throw Error("section registration: the pairs do not fix the rotation");
    const Eigen::Vector3d x = A.ldlt().solve(b);
    out.motion.angle_rad += x[0];
    out.motion.shift = rotate(out.motion.shift, x[0]) + Vec2(x[1], x[2]);
    reach = std::max(o.min_reach_mm, o.outlier_factor * std::max(median(dist), 1e-9));
    reach = std::max(reach, 10 * o.min_reach_mm);
    if (std::abs(x[0]) * radius + Vec2(x[1], x[2]).norm() < o.converged_mm) {
      out.converged = true;
      break;
    }
  }
  return out;
}

// Is the tip broken (DamagedRebuild::tip_extended)? `basis` says why, with
// the heights, for the report.
static bool judge_tip(const SectionMeasurement& m, const DamagedRebuildOptions& o, const DesignBlade& design, double lowest_mm,
               double highest_mm, double step_mm, std::string& basis) {
  auto mm = [](double v) { return fixed_text(v, 2) + " mm"; };
  const double planned = std::isfinite(m.planned_top_mm) ? m.planned_top_mm : o.planned_top_mm;
  if (highest_mm >= design.h_hi - 0.5 * step_mm) {
    basis = "the highest measured section at " + mm(highest_mm) + " reaches the design's tip (" + mm(design.h_hi) +
            ") within half a section step";
    return false;
  }
  if (std::isfinite(planned)) {
    const std::string stated = std::isfinite(m.planned_top_mm) ? "the measurement's" : "the options'";
    if (highest_mm < planned - 0.5 * step_mm) {
      basis = "broken tip: the plan's top section is at " + mm(planned) + " (" + stated + " planned_top), the highest " +
              "measured at " + mm(highest_mm) + ": the probe found no section above it";
      return true;
    }
    basis = "intact tip: the highest measured section at " + mm(highest_mm) + " is the plan's top (" + stated +
            " planned_top " + mm(planned) + "); the " + mm(design.h_hi - highest_mm) + " above it to the design's tip " +
            "is the plan's margin";
    return false;
  }
  const double above = design.h_hi - highest_mm, below = lowest_mm - design.h_lo;
  if (above > below + 1.5 * step_mm) {
    basis = "broken tip: " + mm(above) + " unmeasured above the highest section, " + mm(below) +
            " below the lowest and the sections " + mm(step_mm) + " apart (no planned_top stated: margins taken as "
            "alike at both ends)";
    return true;
  }
  basis = "intact tip: " + mm(above) + " unmeasured above the highest section, like the " + mm(below) +
          " below the lowest (no planned_top stated: a break within " + mm(below + 1.5 * step_mm) +
          " of the tip cannot be told from sections alone)";
  return false;
}

DamagedRebuild rebuild_damaged(const SectionMeasurement& measurement, const DesignBlade& design,
                               const DamagedRebuildOptions& o) {
  const int n = static_cast<int>(measurement.sections.size());
  const std::string source = measurement.file.empty() ? "" : measurement.file + ": ";
  if (n < 2)
    throw ParameterError("sections", source + "a blade needs at least 2 measured sections, got " + std::to_string(n));
  const BladeFrame& frame = design.frame;
  DamagedRebuild out;
  out.frame = frame;

  // 1. Order every section; heights from the points themselves.
  struct Work {
    double h = 0;
    std::vector<Vec3> loop;   // kept points in order, gaps filled once completed
    std::vector<Vec3> kept;   // the measured points kept
    std::vector<Vec2> rejected;  // the ones the ordering rejected, in the plane
    OrderedSection ordered;
    DamagedSection report;
  };
  std::vector<Work> work(n);
  // Each section on its own (o.rebuild.threads, one slot each; an error is
  // the lowest section's, as a plain loop would give).
  parallel_for_index(n, o.rebuild.threads, [&](size_t k) {
    cancellation_point();
    const MeasuredSection& ms = measurement.sections[k];
    Work& w = work[k];
    // Read from a file, the section is named at its line there (issue 43).
    const std::string what = (ms.line > 0 ? measurement.file + ":" + std::to_string(ms.line) + ": " : std::string()) +
                             "section " + std::to_string(ms.index);
    // Ordered in the plane's own coordinates: the same distances, but the
    // ordering's cell grid (PointIndex, dense over the points' bounding box)
    // is one cell thick instead of spanning a plane tilted in the part frame
    // (3x faster for the built-in blade's sections).
    std::vector<Vec3> flat;
    flat.reserve(ms.points.size());
    for (const Vec3& p : ms.points) flat.push_back(lift(frame.in_plane(p)) + Vec3(0, 0, frame.height(p)));
    // A section far denser than the rebuild can use is thinned first
    // (RebuildOptions::thin_above): one measured point per cell.
    const std::vector<int> thinned = section_thinning(flat, o.rebuild);
    const std::vector<Vec3>& points = thinned.empty() ? ms.points : w.kept;
    if (!thinned.empty()) {
      w.kept = pick(ms.points, thinned);
      flat = pick(flat, thinned);
      w.report.thinned = static_cast<int>(ms.points.size() - thinned.size());
    }
    try {
      w.ordered = order_section(flat, o.rebuild.order);
    } catch (const ParameterError& e) {
      throw ParameterError(what, e.what());
    }
    std::vector<Vec3> kept = pick(points, w.ordered.order);
    for (const int i : w.ordered.rejected) w.rejected.push_back(frame.in_plane(points[i]));
    w.kept = std::move(kept);
    for (const Vec3& p : w.kept) w.h += frame.height(p) / w.kept.size();
    if (w.h < design.h_lo || w.h > design.h_hi)
      throw ParameterError("sections", what + " at height " + std::to_string(w.h) +
                                           " mm is outside the design's range [" + std::to_string(design.h_lo) + ", " +
                                           std::to_string(design.h_hi) + "] mm");
    w.loop = w.kept;
    w.report.height_mm = w.h;
    w.report.index = ms.index;
    w.report.kept = static_cast<int>(w.kept.size());
    w.report.rejected = static_cast<int>(w.ordered.rejected.size());
    w.report.gaps = static_cast<int>(w.ordered.gaps.size());
    for (const SectionGap& g : w.ordered.gaps) w.report.gap_mm += g.length_mm;
  });
  std::sort(work.begin(), work.end(), [](const Work& a, const Work& b) { return a.h < b.h; });
  out.top_measured_mm = work.back().h;
  std::vector<double> steps;
  for (int k = 1; k < n; ++k) steps.push_back(work[k].h - work[k - 1].h);
  const double step = median(steps);
  const bool extend = judge_tip(measurement, o, design, work.front().h, out.top_measured_mm, step, out.tip_basis);

  // 2. Register the design where it is needed: sections with gaps, and the
  // top six when the tip is to be extended.
  auto register_at = [&](Work& w) {
    std::vector<Vec2> measured;
    for (const Vec3& p : w.kept) measured.push_back(frame.in_plane(p));
    const std::vector<Vec2> model = plane_section(design.loft, frame, w.h, o.design_samples);
    const SectionRegistration r = register_section(measured, model, o.registration);
    w.report.registered = true;
    w.report.motion = r.motion;
    w.report.registration_rms_mm = r.rms_mm;
    return model;
  };
  // Each section on its own (o.rebuild.threads), its fills gathered in
  // section order afterwards.
  std::vector<std::vector<SectionGapFill>> section_fills(n);
  parallel_for_index(n, o.rebuild.threads, [&](size_t k) {
    cancellation_point();
    Work& w = work[k];
    const bool top = extend && static_cast<int>(k) >= n - 6;
    const bool dents = o.dent_depth_mm > 0;
    if (w.ordered.gaps.empty() && !top && !dents) return;
    std::vector<Vec2> model = register_at(w);
    if (w.ordered.gaps.empty() && !dents) return;
    for (Vec2& p : model) p = w.report.motion.apply(p);
    const int m = static_cast<int>(model.size());
    const int kept_n = static_cast<int>(w.kept.size());
    std::vector<Vec3> lifted;
    for (const Vec2& p : model) lifted.push_back(lift(p));
    const PointIndex model_index(lifted, w.ordered.spacing_mm);
    std::vector<Vec2> plane(kept_n);
    std::vector<Vec3> kept_plane;
    for (int i = 0; i < kept_n; ++i) {
      plane[i] = frame.in_plane(w.kept[i]);
      kept_plane.push_back(lift(plane[i]));
    }
    const PointIndex kept_index(kept_plane, w.ordered.spacing_mm);
    const double far = 1e3;
    auto at = [&](int i) -> const Vec2& { return model[((i % m) + m) % m]; };
    std::vector<std::vector<Vec3>> fill(kept_n);
    std::vector<char> drop(kept_n, 0);
    // The registered design's arc from model point ia (near pa) `count`
    // steps in direction dir to pb, into the loop after kept point `after`.
    auto put_arc = [&](SectionGapFill& f, int after, int ia, int dir, int count) {
      const Vec2 chord = f.end_b - f.end_a;
      Vec2 last = f.end_a;
      for (int s = 1; s < count; ++s) {
        const Vec2& q = at(ia + dir * s);
        if (chord.norm() > 0)
          f.sagitta_mm = std::max(f.sagitta_mm, std::abs(chord.x() * (q - f.end_a).y() - chord.y() * (q - f.end_a).x()) / chord.norm());
        if ((q - last).norm() < 0.5 * w.ordered.spacing_mm || (q - f.end_b).norm() < 0.5 * w.ordered.spacing_mm) continue;
        fill[after].push_back(frame.point(w.h, q));
        last = q;
      }
      f.arc_middle = at(ia + dir * (count / 2));
    };
    // The point `dist` along the arc from the foot of p near model point ia,
    // in direction dir, at most `limit` steps of the model.
    auto walk = [&](const Vec2& p, int ia, int dir, double dist, int limit) {
      // The foot of p on the segment ia -> ia + dir (or the one before it).
      Vec2 from = at(ia);
      int next = ia + dir;
      for (const int s : {ia, ia - dir}) {
        const Vec2& a = at(s);
        const Vec2 e = at(s + dir) - a;
        const double t = e.squaredNorm() > 0 ? (p - a).dot(e) / e.squaredNorm() : 0;
        if (t >= 0 && t <= 1) {
          from = a + t * e;
          next = s + dir;
          break;
        }
      }
      for (int steps = 0; steps < limit; ++steps, next += dir) {
        const double len = (at(next) - from).norm();
        if (len >= dist) return Vec2(from + (at(next) - from) * (dist / len));
        dist -= len;
        from = at(next);
      }
      return from;
    };
    std::vector<SectionGapFill>& fills = section_fills[k];
    for (const SectionGap& g : w.ordered.gaps) {
      const int a = g.after, b = (g.after + 1) % kept_n;
      const Vec2 pa = plane[a], pb = plane[b];
      const int ia = model_index.nearest(lift(pa), far), ib = model_index.nearest(lift(pb), far);
      if (ia < 0 || ib < 0 || ia == ib) continue;  // a gap narrower than the model's spacing: nothing to put in
      // Of the two arcs from ia to ib, the one the measured points do not
      // cover: the fewer of its model points with a kept point within two
      // spacings (a count, not a fraction: the ends of a short arc are
      // always covered). (Judging by the arc's middle alone picks the long way
      // round when the section has a second gap there — a stray's hole
      // beside a nick put the whole design loop into the hole, issue 43.)
      const int forward = ((ib - ia) % m + m) % m;
      auto covered = [&](int steps, int dir) {
        int near = 0;
        for (int s = 1; s < steps; ++s)
          if (kept_index.nearest(lift(at(ia + dir * s)), 2 * w.ordered.spacing_mm) >= 0) ++near;
        return near;
      };
      const int dir = covered(forward, 1) <= covered(m - forward, -1) ? 1 : -1;
      const int count = dir > 0 ? forward : m - forward;
      SectionGapFill f;
      f.height_mm = w.h;
      f.end_a = pa;
      f.end_b = pb;
      f.length_mm = g.length_mm;
      f.spacing_mm = w.ordered.spacing_mm;
      put_arc(f, a, ia, dir, count);
      // Points the ordering rejected inside the gap that lie on the
      // registered design within the noise: surface the probe did measure
      // (the last point before a gap has neighbours on one side only, and
      // the stray test doubts it; near an edge a run of good points can be
      // doubted beside a true stray). Steps along the arc from end a.
      std::vector<std::pair<int, Vec2>> on;
      for (const Vec2& q : w.rejected) {
        const int j = model_index.nearest(lift(q), w.ordered.max_step_mm);
        if (j < 0) continue;
        const int steps = (((j - ia) * dir) % m + m) % m;
        if (steps == 0 || steps >= count) continue;
        double dist = 1e300;
        for (const int s : {j - 1, j}) {
          const Vec2 e = at(s + 1) - at(s);
          const double t = e.squaredNorm() > 0 ? std::clamp((q - at(s)).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
          dist = std::min(dist, (q - at(s) - t * e).norm());
        }
        if (dist < std::max(3 * w.report.registration_rms_mm, 1e-3)) on.emplace_back(steps, q);
      }
      std::sort(on.begin(), on.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      f.confirmed = static_cast<int>(on.size());
      // Damage is where the probe saw nothing over a stretch whose design arc
      // stands off the chord by a probe step or more (the region's rule for a
      // skipped stretch, g^2/8R, applied to each stretch between the points
      // on the design). A gap with none such is bridged: not damage.
      {
        double worst = 0;
        std::pair<int, Vec2> from{0, pa};
        for (size_t i = 0; i <= on.size(); ++i) {
          const std::pair<int, Vec2> to = i < on.size() ? on[i] : std::make_pair(count, pb);
          const Vec2 chord = to.second - from.second;
          if (chord.norm() > 1e-12) {
            const Vec2 along = chord.normalized();
            for (int st = from.first + 1; st < to.first; ++st) {
              const Vec2 q = at(ia + dir * st) - from.second;
              worst = std::max(worst, std::abs(q.x() * along.y() - q.y() * along.x()));
            }
          }
          from = to;
        }
        f.bridged = !on.empty() && worst < w.ordered.spacing_mm;
      }
      // The damage's edges (header): half a probe step on from each end,
      // the end first moved over those points as long as they follow one
      // another within the largest step, up to half the gap from either end.
      // Steps count from the gap's own end, not from the last point taken
      // (adding them up walked an end of five confirmed points 15 steps
      // into a 17-step gap, the two edges met and the nick's floor line
      // turned through the blade: issue 43, 800 points a section).
      auto extend = [&](Vec2 end, int i_end, int d) {
        const int i_gap_end = i_end;
        auto take = [&](int steps, const Vec2& q) {
          if ((q - end).norm() > w.ordered.max_step_mm) return false;
          end = q;
          i_end = ((i_gap_end + d * steps) % m + m) % m;
          return true;
        };
        if (d == dir) {
          for (const auto& [steps, q] : on)
            if (steps >= count / 2 || !take(steps, q)) break;
        } else {
          for (auto it = on.rbegin(); it != on.rend(); ++it)
            if (count - it->first >= count / 2 || !take(count - it->first, it->second)) break;
        }
        return std::make_pair(end, i_end);
      };
      const auto [ea, ja] = extend(pa, ia, dir);
      const auto [eb, jb] = extend(pb, ib, -dir);
      const double half = 0.5 * w.ordered.spacing_mm;
      f.edge_a = walk(ea, ja, dir, half, std::max(1, count / 3));
      f.edge_b = walk(eb, jb, -dir, half, std::max(1, count / 3));
      fills.push_back(f);
    }
    if (dents) {
      // Points deeper than dent_depth inside the registered design, over at
      // least min_dent of the profile, are a dent's floor (header).
      double twice = 0;
      for (int j = 0; j < m; ++j) twice += at(j).x() * at(j + 1).y() - at(j).y() * at(j + 1).x();
      const double inside_sign = twice > 0 ? 1 : -1;  // left of travel is inside for a counter-clockwise loop
      std::vector<double> depth(kept_n, 0);
      for (int i = 0; i < kept_n; ++i) {
        const int j = model_index.nearest(kept_plane[i], far);
        if (j < 0) continue;
        double best = 1e300, side = 0;
        for (const int s : {j - 1, j}) {
          const Vec2& a = at(s);
          const Vec2 e = at(s + 1) - a;
          const double t = e.squaredNorm() > 0 ? std::clamp((plane[i] - a).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
          const Vec2 r = plane[i] - (a + t * e);
          if (r.norm() < best) {
            best = r.norm();
            side = e.x() * r.y() - e.y() * r.x();
          }
        }
        depth[i] = side * inside_sign > 0 ? best : -best;
      }
      std::vector<char> gap_after(kept_n, 0);
      for (const SectionGap& g : w.ordered.gaps) gap_after[g.after] = 1;
      const double rim = std::max(3 * w.report.registration_rms_mm, 1e-3);
      std::vector<char> used(kept_n, 0);
      for (int i0 = 0; i0 < kept_n; ++i0) {
        if (used[i0] || !(depth[i0] > o.dent_depth_mm)) continue;
        // The run of points inside by more than the noise around i0, not
        // across a gap.
        int first = i0, last = i0, len = 1;
        while (len < kept_n && !gap_after[(first - 1 + kept_n) % kept_n] && depth[(first - 1 + kept_n) % kept_n] > rim)
          first = (first - 1 + kept_n) % kept_n, ++len;
        while (len < kept_n && !gap_after[last] && depth[(last + 1) % kept_n] > rim) last = (last + 1) % kept_n, ++len;
        double deepest = 0, along = 0;
        for (int s = 0; s < len; ++s) {
          const int i = (first + s) % kept_n;
          used[i] = 1;
          deepest = std::max(deepest, depth[i]);
        }
        const int before = (first - 1 + kept_n) % kept_n, after = (last + 1) % kept_n;
        if (len < 3 || len + 2 > kept_n) continue;
        for (int s = 0; s <= len; ++s) along += (plane[(before + s + 1) % kept_n] - plane[(before + s) % kept_n]).norm();
        if (along < o.min_dent_mm) continue;
        const int ia = model_index.nearest(kept_plane[before], far), ib = model_index.nearest(kept_plane[after], far);
        if (ia < 0 || ib < 0 || ia == ib) continue;
        // A dent is the short way round.
        const int forward = ((ib - ia) % m + m) % m;
        const int dir = forward <= m - forward ? 1 : -1;
        SectionGapFill f;
        f.height_mm = w.h;
        f.end_a = f.edge_a = plane[before];
        f.end_b = f.edge_b = plane[after];
        f.length_mm = along;
        f.spacing_mm = w.ordered.spacing_mm;
        f.dent_depth_mm = deepest;
        for (int s = 0; s < len; ++s) {
          const int i = (first + s) % kept_n;
          drop[i] = 1;
          f.floor.push_back(plane[i]);
        }
        put_arc(f, before, ia, dir, dir > 0 ? forward : m - forward);
        fills.push_back(f);
        ++w.report.dents;
      }
    }
    if (fills.empty() && w.ordered.gaps.empty()) return;
    std::vector<Vec3> loop;
    for (int i = 0; i < kept_n; ++i) {
      if (!drop[i]) loop.push_back(w.kept[i]);
      loop.insert(loop.end(), fill[i].begin(), fill[i].end());
    }
    w.loop = std::move(loop);
    w.report.source = SectionSource::completed;
  });
  for (const std::vector<SectionGapFill>& f : section_fills) out.fills.insert(out.fills.end(), f.begin(), f.end());

  // 4. A broken tip: design sections moved by the extrapolated registration.
  std::vector<Work> extension;
  if (extend) {
    std::vector<double> hs, angle, sx, sy;
    for (int k = std::max(0, n - 6); k < n; ++k) {
      hs.push_back(work[k].h);
      angle.push_back(work[k].report.motion.angle_rad);
      sx.push_back(work[k].report.motion.shift.x());
      sy.push_back(work[k].report.motion.shift.y());
    }
    const int degree = hs.size() >= 4 ? 2 : 1;
    const int count = std::max(1, static_cast<int>(std::ceil((design.h_hi - out.top_measured_mm) / step - 1e-9)));
    for (int e = 1; e <= count; ++e) {
      Work w;
      w.h = out.top_measured_mm + (design.h_hi - out.top_measured_mm) * e / count;
      w.report.height_mm = w.h;
      w.report.source = SectionSource::extended;
      w.report.registered = true;
      w.report.motion.angle_rad = extrapolate(hs, angle, degree, w.h);
      w.report.motion.shift = Vec2(extrapolate(hs, sx, degree, w.h), extrapolate(hs, sy, degree, w.h));
      // About the measured sections' spacing around the profile.
      const int samples = std::clamp(static_cast<int>(work.back().loop.size()), 64, 4096);
      for (const Vec2& p : plane_section(design.loft, frame, w.h, samples))
        w.loop.push_back(frame.point(w.h, w.report.motion.apply(p)));
      extension.push_back(std::move(w));
    }
    out.tip_extended = true;
  }
  for (Work& w : extension) work.push_back(std::move(w));

  // 5. Orient, smooth, align, loft, measure (rebuild_blade's chain), the
  // loft checked between its sections (header) and tried again from the
  // design's starts when it fails.
  std::vector<std::vector<Vec3>> loops;
  for (const Work& w : work) loops.push_back(w.loop);
  const std::vector<OrientedSection> oriented = orient_sections(loops, frame.axis);
  std::vector<ClosedCurve> curves(work.size());
  parallel_for_index(work.size(), o.rebuild.threads, [&](size_t k) {
    cancellation_point();
    const SmoothedSection s = smooth_section(oriented[k].loop, o.rebuild.smoothing_mm);
    work[k].report.smoothing_shift_mm = s.rms_shift_mm;
    curves[k] = s.curve;
  });
  const AlignedSections aligned = align_section_starts(curves, o.rebuild.align_samples, o.rebuild.threads);
  RebuildQuality& q = out.quality;
  q.tolerance_mm = o.between_tolerance_mm;
  for (size_t k = 1; k < work.size(); ++k)
    if (work[k].report.source != SectionSource::extended)
      q.least_correlation = std::min(q.least_correlation, aligned.alignments[k].correlation);

  int attempt_number = 0;
  auto sabotage = [&](std::vector<ClosedCurve>& cs) {
    const int k = o.forced_start_section;
    if (++attempt_number <= o.forced_start_attempts && k >= 0 && k < static_cast<int>(cs.size())) cs[k] = cs[k].started_at(cs[k].t_min() + o.forced_start_shift_mm);
  };
  struct Attempt {
    SectionLoft loft;
    std::vector<BetweenSectionCheck> checks;
    double worst = 0, worst_at = 0;
    std::string failure;  // a check that could not be made
  };
  auto attempt = [&](std::vector<ClosedCurve> cs) {
    sabotage(cs);
    Attempt a;
    a.loft = loft_sections(cs, o.rebuild.loft);
    a.checks.resize(work.size() - 1);
    std::vector<std::string> errors(work.size() - 1);
    parallel_for_index(work.size() - 1, o.rebuild.threads, [&](size_t k) {
      cancellation_point();
      BetweenSectionCheck& c = a.checks[k];
      c.height_mm = 0.5 * (work[k].h + work[k + 1].h);
      try {
        c = check_between(a.loft, design, c.height_mm, o.design_samples, o.registration);
      } catch (const Error& e) {
        errors[k] = e.what();
        c.max_mm = c.rms_mm = std::numeric_limits<double>::infinity();
      }
    });
    for (size_t k = 0; k < a.checks.size(); ++k) {
      if (a.failure.empty() && !errors[k].empty())
        a.failure = "the loft's section at height " + short_text(a.checks[k].height_mm) + " mm could not be checked: " + errors[k];
      if (!(a.checks[k].max_mm <= a.worst)) {
        a.worst = a.checks[k].max_mm;
        a.worst_at = a.checks[k].height_mm;
      }
    }
    return a;
  };
  Attempt best = attempt(aligned.curves);
  q.attempts = 1;
  q.start_method = "curvature";
  q.attempt_max_mm.push_back(best.worst);
  if (!(best.worst <= o.between_tolerance_mm)) {
    // The retry: each section started where the registered design's v = 0
    // (its plane section's first point) lands on it.
    for (Work& w : work)
      if (!w.report.registered) register_at(w);
    std::vector<ClosedCurve> restarted(work.size());
    parallel_for_index(work.size(), o.rebuild.threads, [&](size_t k) {
      cancellation_point();
      const Vec2 first = plane_section(design.loft, frame, work[k].h, 16)[0];
      const Vec3 target = frame.point(work[k].h, work[k].report.motion.apply(first));
      restarted[k] = curves[k].started_at(nearest_parameter(curves[k], target));
    });
    // The design's starts are as good as the registrations (um) and the
    // nearest point; refined by the curvature profiles, as the first
    // attempt, but each within 0.5 mm of its design start, so no start can
    // jump along the profile.
    std::vector<CurvatureProfile> profiles(work.size());
    parallel_for_index(work.size(), o.rebuild.threads, [&](size_t k) {
      cancellation_point();
      profiles[k] = curvature_profile(restarted[k], o.rebuild.align_samples);
    });
    CurvatureProfile reference = profiles[0];
    for (size_t k = 1; k < work.size(); ++k) {
      cancellation_point();
      const int window = static_cast<int>(std::ceil(0.5 * o.rebuild.align_samples / profiles[k].length_mm));
      const StartAlignment a = align_start(reference, profiles[k], window);
      restarted[k] = restarted[k].started_at(a.t_start);
      reference = curvature_profile(restarted[k], o.rebuild.align_samples);
    }
    Attempt retry = attempt(restarted);
    q.attempts = 2;
    q.attempt_max_mm.push_back(retry.worst);
    if (retry.worst < best.worst) {
      best = std::move(retry);
      q.start_method = "design";
    }
  }
  out.loft = std::move(best.loft);
  q.between = best.checks;
  q.between_max_mm = best.worst;
  q.between_at_mm = best.worst_at;
  q.trusted = best.worst <= o.between_tolerance_mm;
  if (!q.trusted) {
    q.message = best.failure.empty()
                    ? "the rebuilt blade is not trustworthy between its sections: at height " + short_text(best.worst_at) +
                          " mm its section is " + short_text(1e3 * best.worst) + " um from the design's registered to it "
                          "(tolerance " + short_text(1e3 * o.between_tolerance_mm) + " um), after " +
                          std::to_string(q.attempts) + " start alignments (curvature" +
                          (q.attempts > 1 ? ", design" : "") + "; least start correlation " +
                          short_text(q.least_correlation) + "). Noisy sections are smoothed too little "
                          "(a longer smoothing length), a section with a wrong gap fill or a wrong start shows "
                          "here; the blade may also differ from its design by more than a motion in its planes"
                    : "the rebuilt blade is not trustworthy: " + best.failure;
  }
  std::vector<Vec3> kept;
  for (size_t k = 0; k < work.size(); ++k) {
    work[k].report.start_correlation = aligned.alignments[k].correlation;
    kept.insert(kept.end(), work[k].kept.begin(), work[k].kept.end());
    out.sections.push_back(work[k].report);
  }
  out.deviation = loft_deviation(out.loft, kept, &out.point_deviations, o.rebuild.threads);
  return out;
}

}  // namespace bliskrun
