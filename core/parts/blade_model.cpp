#include "core/parts/blade_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/common/progress.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/projection.h"

namespace bliskrun {

namespace {

// Points closer than this are one point (repeated edge points in the files).
constexpr double kSamePointMm = 1e-7;

// A loop without repeated points, and where each point came from.
struct Loop {
  std::vector<Vec3> p;
  std::vector<int> source;  // index into the given loop
  std::vector<double> s;    // arc length at p[i] from p[0]
  double perimeter = 0;
  int n() const { return static_cast<int>(p.size()); }
  int wrap(int i) const { return ((i % n()) + n()) % n(); }
  // Arc length from i forwards to j.
  double ahead(int i, int j) const {
    const double d = s[wrap(j)] - s[wrap(i)];
    return d < 0 ? d + perimeter : d;
  }
};

Loop clean(const std::vector<Vec3>& given, const std::string& what) {
  Loop l;
  for (size_t i = 0; i < given.size(); ++i) {
    if (!given[i].allFinite()) throw ParameterError(what, "point " + std::to_string(i + 1) + " is not finite");
    if (!l.p.empty() && (given[i] - l.p.back()).norm() < kSamePointMm) continue;
    l.p.push_back(given[i]);
    l.source.push_back(static_cast<int>(i));
  }
  while (l.p.size() > 1 && (l.p.back() - l.p.front()).norm() < kSamePointMm) {
    l.p.pop_back();
    l.source.pop_back();
  }
  if (l.p.size() < 8)
    throw ParameterError(what, "a closed section loop needs at least 8 distinct points, got " + std::to_string(l.p.size()));
  l.s.assign(l.p.size(), 0.0);
  for (int i = 1; i < l.n(); ++i) l.s[i] = l.s[i - 1] + (l.p[i] - l.p[i - 1]).norm();
  l.perimeter = l.s.back() + (l.p.front() - l.p.back()).norm();
  return l;
}

struct Circle2 {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  double r = 0;
  bool ok = false;
};

// Algebraic (Kasa) start, then Gauss-Newton on the geometric distances.
Circle2 fit_circle(const std::vector<Eigen::Vector2d>& q) {
  Circle2 out;
  if (q.size() < 3) return out;
  Eigen::MatrixXd A(q.size(), 3);
  Eigen::VectorXd b(q.size());
  for (size_t i = 0; i < q.size(); ++i) {
    A.row(i) << q[i].x(), q[i].y(), 1.0;
    b(i) = -q[i].squaredNorm();
  }
  const Eigen::Vector3d x = A.colPivHouseholderQr().solve(b);
  Eigen::Vector2d c(-x(0) / 2, -x(1) / 2);
  const double r2 = c.squaredNorm() - x(2);
  if (!(r2 > 0) || !std::isfinite(r2)) return out;
  double r = std::sqrt(r2);
  for (int it = 0; it < 20; ++it) {
    Eigen::MatrixXd J(q.size(), 3);
    Eigen::VectorXd e(q.size());
    for (size_t i = 0; i < q.size(); ++i) {
      const Eigen::Vector2d d = q[i] - c;
      const double len = d.norm();
      if (len == 0) return out;
      e(i) = len - r;
      J.row(i) << -d.x() / len, -d.y() / len, -1.0;
    }
    const Eigen::Vector3d step = J.colPivHouseholderQr().solve(-e);
    c += step.head<2>();
    r += step(2);
    if (step.norm() < 1e-12 * std::max(1.0, r)) break;
  }
  out.c = c;
  out.r = std::abs(r);
  out.ok = std::isfinite(out.r) && out.r > 0;
  return out;
}

// The circle of the edge around loop point e. `away` points from the blade
// towards this edge. The window is the arc within `half` of the edge point;
// it starts at two neighbours either side and settles at half = 45 degrees of
// the fitted circle (well inside the tangent points to the flanks), at most
// 2 % of the perimeter.
EdgeCircle fit_edge(const Loop& l, int e, const Vec3& away) {
  const double cap = 0.02 * l.perimeter;
  double half = std::max(l.ahead(e, e + 2), l.ahead(e - 2, e));
  EdgeCircle best;
  best.point = e;
  for (int it = 0; it < 30; ++it) {
    half = std::min(half, cap);
    int a = e, b = e;  // window [a .. b] going forwards
    while (l.ahead(a - 1, e) <= half && l.wrap(a - 1) != b) a = l.wrap(a - 1);
    while (l.ahead(e, b + 1) <= half && l.wrap(b + 1) != a) b = l.wrap(b + 1);
    if (l.ahead(a, e) == 0 || l.ahead(e, b) == 0 || l.ahead(a, b) < 2 * 1e-12) {
      a = l.wrap(e - 2);
      b = l.wrap(e + 2);
    }
    // Plane of the circle: across the edge (a -> b) and along the camber.
    const Vec3 across = l.p[b] - l.p[a];
    Vec3 x = across.normalized();
    Vec3 y = l.p[e] - 0.5 * (l.p[a] + l.p[b]);
    y -= y.dot(x) * x;
    if (y.norm() < 1e-12 * across.norm()) {
      y = away - away.dot(x) * x;
    }
    y.normalize();
    std::vector<Eigen::Vector2d> q;
    std::vector<int> idx;
    for (int k = a;; k = l.wrap(k + 1)) {
      const Vec3 d = l.p[k] - l.p[e];
      q.emplace_back(d.dot(x), d.dot(y));
      idx.push_back(k);
      if (k == b) break;
    }
    const Circle2 c = fit_circle(q);
    if (!c.ok) break;
    double ss = 0;
    for (const auto& p : q) ss += std::pow((p - c.c).norm() - c.r, 2);
    EdgeCircle cur;
    cur.centre = l.p[e] + c.c.x() * x + c.c.y() * y;
    cur.radius_mm = c.r;
    cur.normal = x.cross(y).normalized();
    cur.fitted_points = static_cast<int>(q.size());
    cur.rms_mm = std::sqrt(ss / q.size());
    cur.point = e;
    const bool round = cur.rms_mm < 0.05 * cur.radius_mm;
    // The edge point: the window point farthest out along the chord from the
    // fitted centre - the circle's own extreme, which the next window is
    // centred on (the loop's raw extreme can sit off it where the points are
    // sparse).
    int next_e = e;
    if (round) {
      double far = -1e300;
      for (int k : idx) {
        const double t = (l.p[k] - cur.centre).dot(away);
        if (t > far) {
          far = t;
          next_e = k;
        }
      }
    }
    const double next_half = std::max(0.5 * (kPi / 2) * cur.radius_mm,
                                      std::max(l.ahead(next_e, next_e + 2), l.ahead(next_e - 2, next_e)));
    const bool settled = next_e == e && std::abs(next_half - half) <= 1e-9 * std::max(1.0, half);
    best = cur;
    best.point = e;
    if (settled || !round) break;
    e = next_e;
    half = next_half;
  }
  return best;
}

// Edges on the cleaned loop (indices into l.p).
SectionEdges edges_of(const Loop& l) {
  int i0 = 0, i1 = 1;
  double far = -1;
  for (int i = 0; i < l.n(); ++i)
    for (int j = i + 1; j < l.n(); ++j) {
      const double d = (l.p[i] - l.p[j]).squaredNorm();
      if (d > far) {
        far = d;
        i0 = i;
        i1 = j;
      }
    }
  if (l.p[i1].z() < l.p[i0].z()) std::swap(i0, i1);  // flow towards +Z: LE first
  const Vec3 chord = (l.p[i1] - l.p[i0]).normalized();
  // The extremes along the chord near the two points.
  int le = i0, te = i1;
  for (int i = 0; i < l.n(); ++i) {
    if (l.p[i].dot(chord) < l.p[le].dot(chord) && (l.p[i] - l.p[i0]).norm() < 0.1 * std::sqrt(far)) le = i;
    if (l.p[i].dot(chord) > l.p[te].dot(chord) && (l.p[i] - l.p[i1]).norm() < 0.1 * std::sqrt(far)) te = i;
  }
  SectionEdges e;
  e.leading = fit_edge(l, le, -chord);
  e.trailing = fit_edge(l, te, chord);
  return e;
}

// One side of a section, LE -> TE, as a cubic with a table of the chord
// measure (arc length, or projection on the chord) against its parameter.
struct Side {
  std::vector<Vec3> points;       // given points, LE -> TE
  std::vector<double> fraction;   // their chord fractions (the measure in use)
  BSplineCurve curve;
  std::vector<double> t;          // table nodes: the points' parameters, subdivided
  std::vector<size_t> node;       // table node of each given point
  std::vector<double> len, proj;  // arc length; projection on the chord, 0 at the LE and 1 at the TE point
  std::vector<double> measure;    // the one in use, non-decreasing

  // Projection increases along the side inside [margin, 1 - margin]: the
  // side does not fold back along its chord there.
  bool projection_monotonic(double margin) const {
    for (size_t k = 1; k < proj.size(); ++k)
      if (proj[k] <= proj[k - 1] && proj[k - 1] >= margin && proj[k] <= 1 - margin) return false;
    return true;
  }
  void use(ChordFraction how) {
    if (how == ChordFraction::arc_length) {
      measure = len;
    } else {
      measure.clear();
      double best = 0;
      for (size_t k = 0; k < proj.size(); ++k) {
        best = std::max(best, proj[k]);
        measure.push_back(best + 1e-13 * k);  // strictly increasing for the search
      }
    }
    fraction.clear();
    for (size_t n : node) fraction.push_back(measure[n] / measure.back());
  }
  Vec3 at_fraction(double f) const {
    const double target = f * measure.back();
    const size_t k =
        std::min<size_t>(std::upper_bound(measure.begin(), measure.end(), target) - measure.begin(), measure.size() - 1);
    const size_t k0 = k == 0 ? 0 : k - 1;
    const double w = measure[k] > measure[k0] ? (target - measure[k0]) / (measure[k] - measure[k0]) : 0.0;
    return curve.point(t[k0] + w * (t[k] - t[k0]));
  }
};

Side make_side(const Loop& l, int from, int to, int step) {
  Side s;
  for (int k = from;; k = l.wrap(k + step)) {
    s.points.push_back(l.p[k]);
    if (k == to) break;
  }
  // The cubic runs on kPast loop points past each edge point, so that the
  // two sides share the edge's curvature there: a side interpolated alone
  // takes its end tangent from its end condition, and on Rotor 67's leading
  // edge (0.45 mm round, points 0.1 mm apart) the two sides met 5 degrees
  // apart at the edge point. Beyond the edge points the cubic is not used.
  constexpr int kPast = 3;
  const int n = static_cast<int>(s.points.size());
  const int past = std::min(kPast, (l.n() - n) / 2);
  std::vector<Vec3> run;
  for (int k = past; k > 0; --k) run.push_back(l.p[l.wrap(from - k * step)]);
  run.insert(run.end(), s.points.begin(), s.points.end());
  for (int k = 1; k <= past; ++k) run.push_back(l.p[l.wrap(to + k * step)]);
  const std::vector<double> run_params = chord_length_parameters(run);
  s.curve = interpolate_cubic(run, run_params);
  const std::vector<double> params(run_params.begin() + past, run_params.begin() + past + n);
  const Vec3 a = s.points.front(), chord = s.points.back() - a;
  constexpr int kSub = 16;
  s.t.push_back(params[0]);
  s.len.push_back(0);
  s.proj.push_back(0);
  s.node.push_back(0);
  Vec3 prev = s.curve.point(params[0]);
  for (size_t i = 1; i < params.size(); ++i) {
    for (int k = 1; k <= kSub; ++k) {
      const double t = params[i - 1] + (params[i] - params[i - 1]) * k / kSub;
      const Vec3 p = s.curve.point(t);
      s.t.push_back(t);
      s.len.push_back(s.len.back() + (p - prev).norm());
      s.proj.push_back((p - a).dot(chord) / chord.squaredNorm());
      prev = p;
    }
    s.node.push_back(s.t.size() - 1);
  }
  s.use(ChordFraction::arc_length);
  return s;
}

// In the blade-to-blade plane (conformal meridional coordinate m' = ∫dm/r
// along side A's meridian trace, θ from the LE): whether A lies at larger θ
// than B (+1/-1), and whether the camber line bulges towards A (A convex).
struct SideJudgement {
  int a_faces = 0;      // +1: A faces +θ
  bool a_convex = false;
};

SideJudgement judge(const Side& A, const Side& B) {
  const double theta0 = std::atan2(A.points.front().y(), A.points.front().x());
  std::vector<Eigen::Vector2d> mer;  // (z, r) of A
  for (const Vec3& p : A.points) mer.emplace_back(p.z(), std::hypot(p.x(), p.y()));
  std::vector<double> mp(mer.size(), 0.0);
  for (size_t i = 1; i < mer.size(); ++i)
    mp[i] = mp[i - 1] + (mer[i] - mer[i - 1]).norm() / std::max(1e-9, 0.5 * (mer[i].y() + mer[i - 1].y()));
  auto plane = [&](const Vec3& p) {
    const Eigen::Vector2d zr(p.z(), std::hypot(p.x(), p.y()));
    double best = 1e300, m = 0;
    for (size_t i = 1; i < mer.size(); ++i) {
      const Eigen::Vector2d d = mer[i] - mer[i - 1];
      const double len2 = d.squaredNorm();
      const double w = len2 > 0 ? std::clamp((zr - mer[i - 1]).dot(d) / len2, 0.0, 1.0) : 0.0;
      const double dist = (mer[i - 1] + w * d - zr).squaredNorm();
      if (dist < best) {
        best = dist;
        m = mp[i - 1] + w * (mp[i] - mp[i - 1]);
      }
    }
    return Eigen::Vector2d(m, wrap_angle(std::atan2(p.y(), p.x()) - theta0));
  };
  std::vector<Eigen::Vector2d> a2, b2;
  for (const Vec3& p : A.points) a2.push_back(plane(p));
  for (const Vec3& p : B.points) b2.push_back(plane(p));
  const Eigen::Vector2d le = a2.front(), chord = a2.back() - a2.front();
  auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  double faces = 0, bulge = 0, a_left = 0;
  for (size_t i = 0; i < a2.size(); ++i) {
    if (A.fraction[i] < 0.2 || A.fraction[i] > 0.8) continue;
    double best = 1e300;
    Eigen::Vector2d foot = b2.front();
    for (size_t j = 1; j < b2.size(); ++j) {
      const Eigen::Vector2d d = b2[j] - b2[j - 1];
      const double len2 = d.squaredNorm();
      const double w = len2 > 0 ? std::clamp((a2[i] - b2[j - 1]).dot(d) / len2, 0.0, 1.0) : 0.0;
      const Eigen::Vector2d f = b2[j - 1] + w * d;
      if ((f - a2[i]).squaredNorm() < best) {
        best = (f - a2[i]).squaredNorm();
        foot = f;
      }
    }
    const Eigen::Vector2d n = a2[i] - foot;
    faces += n.y();
    bulge += cross(chord, 0.5 * (a2[i] + foot) - le);
    a_left += cross(chord, n);
  }
  SideJudgement j;
  j.a_faces = faces >= 0 ? 1 : -1;
  j.a_convex = (bulge >= 0) == (a_left >= 0);
  return j;
}

void reverse_columns(PointGrid& g) {
  for (int i = 0; i < g.rows; ++i)
    for (int j = 0; j < g.cols / 2; ++j) std::swap(g.at(i, j), g.at(i, g.cols - 1 - j));
}

// +1 when pu x pv of `g` points away from `other` (same shape, same v
// direction), over the interior.
int outward(const PointGrid& g, const PointGrid& other) {
  double votes = 0;
  for (int i = 0; i < g.rows; ++i)
    for (int j = 1; j + 1 < g.cols; j += std::max(1, g.cols / 8)) {
      const int i0 = std::max(0, i - 1), i1 = std::min(g.rows - 1, i + 1);
      const Vec3 n = (g.at(i1, j) - g.at(i0, j)).cross(g.at(i, j + 1) - g.at(i, j - 1));
      votes += n.dot(g.at(i, j) - other.at(i, j)) > 0 ? 1 : -1;
    }
  return votes >= 0 ? 1 : -1;
}

// Extends the grid by one row before the first and after the last, along
// each column's end tangent by `fraction` of the column's length.
PointGrid extend_span(const PointGrid& g, double fraction) {
  PointGrid out(g.rows + 2, g.cols);
  for (int j = 0; j < g.cols; ++j) {
    std::vector<Vec3> col;
    double length = 0;
    for (int i = 0; i < g.rows; ++i) {
      col.push_back(g.at(i, j));
      out.at(i + 1, j) = g.at(i, j);
      if (i) length += (g.at(i, j) - g.at(i - 1, j)).norm();
    }
    const BSplineCurve c = interpolate_cubic(col);
    const Vec3 t0 = c.eval(c.t_min()).dt.normalized(), t1 = c.eval(c.t_max()).dt.normalized();
    out.at(0, j) = col.front() - fraction * length * t0;
    out.at(g.rows + 1, j) = col.back() + fraction * length * t1;
  }
  return out;
}

// Chord fraction of grid column j, and the (fractional) column of chord
// fraction f: the inverse.
double column_fraction(const LoftOptions& o, int j) {
  const double t = static_cast<double>(j) / (o.cols - 1);
  const double g = o.spacing == ColumnSpacing::cosine ? 0.5 * (1 - std::cos(kPi * t)) : t;
  return o.edge_margin + (1 - 2 * o.edge_margin) * g;
}
double column_of_fraction(const LoftOptions& o, double f) {
  const double g = std::clamp((f - o.edge_margin) / (1 - 2 * o.edge_margin), 0.0, 1.0);
  const double t = o.spacing == ColumnSpacing::cosine ? std::acos(1 - 2 * g) / kPi : g;
  return t * (o.cols - 1);
}

double interp(const std::vector<double>& v, double x) {
  const double c = std::clamp(x, 0.0, static_cast<double>(v.size() - 1));
  const size_t k = std::min(static_cast<size_t>(c), v.size() - 2);
  return v[k] + (c - k) * (v[k + 1] - v[k]);
}

void accumulate(FitStats& s, double d) {
  s.max_mm = std::max(s.max_mm, d);
  s.rms_mm += d * d;  // sum of squares until finish()
  ++s.points;
}
void finish(FitStats& s) { s.rms_mm = s.points ? std::sqrt(s.rms_mm / s.points) : 0.0; }

}  // namespace

SectionEdges find_section_edges(const std::vector<Vec3>& loop) {
  const Loop l = clean(loop, "section");
  SectionEdges e = edges_of(l);
  e.leading.point = l.source[e.leading.point];
  e.trailing.point = l.source[e.trailing.point];
  return e;
}

namespace {

// The loft without the fit, with each section's sides as assigned.
struct Lofted {
  BladeLoft loft;
  std::vector<Side> pside, sside;
  bool p_forward = true, s_forward = false;
};

Lofted loft_core(const BladeSections& blade, const LoftOptions& o) {
  if (o.cols < 4) throw ParameterError("cols", "need at least 4 columns, got " + std::to_string(o.cols));
  if (!(o.edge_margin >= 0 && o.edge_margin < 0.5)) throw ParameterError("edge_margin", "must be in [0, 0.5)");
  if (!(o.span_extension >= 0 && o.span_extension <= 0.5))
    throw ParameterError("span_extension", "must be in [0, 0.5]");
  if (blade.sections.size() < 2)
    throw ParameterError("sections", "a blade needs at least 2 section loops, got " + std::to_string(blade.sections.size()));
  if (blade.rotation_sign < -1 || blade.rotation_sign > 1)
    throw ParameterError("rotation_sign", "must be -1, 0 or +1");
  const int ns = static_cast<int>(blade.sections.size());

  Lofted result;
  BladeLoft& out = result.loft;
  std::vector<Side> first(ns), second(ns);  // A: forwards from the LE; B: backwards
  std::vector<SideJudgement> judged(ns);
  int implied = 0;
  for (int k = 0; k < ns; ++k) {
    cancellation_point();
    const std::string what = "section " + std::to_string(k + 1);
    const Loop l = clean(blade.sections[k], what);
    SectionEdges e = edges_of(l);
    const int le = e.leading.point, te = e.trailing.point;
    if (le == te) throw ParameterError(what, "leading and trailing edge fall on one point");
    first[k] = make_side(l, le, te, +1);
    second[k] = make_side(l, le, te, -1);
    if (first[k].points.size() < 3 || second[k].points.size() < 3)
      throw ParameterError(what, "a side between the edges has fewer than 3 points");
    judged[k] = judge(first[k], second[k]);
    // The concave side faces the rotation when the data do not say.
    implied += judged[k].a_convex ? -judged[k].a_faces : judged[k].a_faces;
    e.leading.point = l.source[le];
    e.trailing.point = l.source[te];
    out.edges.push_back(e);
  }
  out.rotation_given = blade.rotation_sign != 0;
  out.rotation_sign = out.rotation_given ? blade.rotation_sign : (implied >= 0 ? 1 : -1);
  // One chord measure for every section, so that columns correspond.
  out.chord_fraction = o.chord_fraction;
  for (int k = 0; k < ns; ++k)
    if (!first[k].projection_monotonic(o.edge_margin) || !second[k].projection_monotonic(o.edge_margin))
      out.chord_fraction = ChordFraction::arc_length;
  for (int k = 0; k < ns; ++k) {
    first[k].use(out.chord_fraction);
    second[k].use(out.chord_fraction);
  }

  // Rows: the resampled sides, LE -> TE for now.
  const int cols = o.cols;
  PointGrid pres(ns, cols), suct(ns, cols);
  std::vector<const Side*> pside(ns), sside(ns);
  int agree = 0;
  for (int k = 0; k < ns; ++k) {
    const bool a_is_pressure = judged[k].a_faces == out.rotation_sign;
    pside[k] = a_is_pressure ? &first[k] : &second[k];
    sside[k] = a_is_pressure ? &second[k] : &first[k];
    agree += (a_is_pressure != judged[k].a_convex) ? 1 : -1;
    for (int j = 0; j < cols; ++j) {
      const double f = column_fraction(o, j);
      pres.at(k, j) = pside[k]->at_fraction(f);
      suct.at(k, j) = sside[k]->at_fraction(f);
    }
  }
  out.camber_agrees = agree > 0;
  const bool p_forward = outward(pres, suct) > 0;
  const bool s_forward = outward(suct, pres) > 0;
  if (p_forward == s_forward)
    throw ParameterError("sections", "cannot orient the flanks: both normals point the same way (sides crossing?)");
  out.pressure_v_le_to_te = p_forward;
  if (!p_forward) reverse_columns(pres);
  if (!s_forward) reverse_columns(suct);
  if (o.span_extension > 0) {
    pres = extend_span(pres, o.span_extension);
    suct = extend_span(suct, o.span_extension);
    out.hub_row = 1;
  }
  out.tip_row = out.hub_row + ns - 1;

  out.pressure = std::move(pres);
  out.suction = std::move(suct);
  for (int k = 0; k < ns; ++k) {
    result.pside.push_back(*pside[k]);
    result.sside.push_back(*sside[k]);
  }
  result.p_forward = p_forward;
  result.s_forward = s_forward;
  return result;
}

// Distances of side `s`'s given points inside the chord range to `surf`
// (grid `g`, `forward` its v direction), Newton from the point's own row
// parameter `u` and column.
void measure(const Side& s, const BSplineSurface& surf, const std::vector<double>& v_params, double u, bool forward,
             const LoftOptions& o, const std::string& where, std::vector<FitStats*> into) {
  for (size_t i = 0; i < s.points.size(); ++i) {
    const double f = s.fraction[i];
    if (f < o.edge_margin - 1e-12 || f > 1 - o.edge_margin + 1e-12) continue;
    double c = column_of_fraction(o, f);
    if (!forward) c = o.cols - 1 - c;
    ProjectionOptions po;
    po.seed = Eigen::Vector2d(u, interp(v_params, c));
    const SurfaceProjection pr = project_to_surface(surf, s.points[i], po);
    if (!pr.ok)
      throw Error("blade fit: " + where + ", point " + std::to_string(i + 1) + " does not project onto the flank: " +
                  pr.failure);
    for (FitStats* f : into) accumulate(*f, pr.distance);
  }
}

}  // namespace

BladeLoft loft_blade(const BladeSections& blade, const LoftOptions& o) {
  Lofted l = loft_core(blade, o);
  BladeLoft& out = l.loft;
  const int ns = static_cast<int>(blade.sections.size());
  out.fit_sections.assign(ns, FitStats{});
  for (int side = 0; side < 2; ++side) {
    const PointGrid& g = side == 0 ? out.pressure : out.suction;
    const BSplineSurface surf = interpolate_grid(g);
    const GridParameters params = averaged_grid_parameters(g);
    FitStats& total = side == 0 ? out.fit_pressure : out.fit_suction;
    for (int k = 0; k < ns; ++k)
      measure(side == 0 ? l.pside[k] : l.sside[k], surf, params.v, params.u[out.hub_row + k],
              side == 0 ? l.p_forward : l.s_forward, o,
              "section " + std::to_string(k + 1) + (side == 0 ? " pressure" : " suction"),
              {&total, &out.fit, &out.fit_sections[k]});
  }
  finish(out.fit);
  finish(out.fit_pressure);
  finish(out.fit_suction);
  for (FitStats& s : out.fit_sections) finish(s);

  // Leave one out: each interior section against the loft of the others.
  if (o.cross_check && ns >= 3) {
    out.cross_sections.assign(ns, FitStats{});
    LoftOptions without = o;
    without.span_extension = 0;
    without.cross_check = false;
    for (int k = 1; k + 1 < ns; ++k) {
      BladeSections rest = blade;
      rest.sections.erase(rest.sections.begin() + k);
      rest.rotation_sign = out.rotation_sign;  // the same sides as the whole blade
      const Lofted r = loft_core(rest, without);
      for (int side = 0; side < 2; ++side) {
        const PointGrid& g = side == 0 ? r.loft.pressure : r.loft.suction;
        const BSplineSurface surf = interpolate_grid(g);
        const GridParameters params = averaged_grid_parameters(g);
        measure(side == 0 ? l.pside[k] : l.sside[k], surf, params.v, 0.5 * (params.u[k - 1] + params.u[k]),
                side == 0 ? r.p_forward : r.s_forward, without, "section " + std::to_string(k + 1) + " (left out)",
                {&out.cross, &out.cross_sections[k]});
      }
    }
    finish(out.cross);
    for (FitStats& s : out.cross_sections) finish(s);
  }
  return out;
}

}  // namespace bliskrun
