#include "core/planning/edge_strip.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/error.h"

namespace bliskrun {

EdgeFrame edge_frame(const SurfaceDerivs& d, bool flip_normal) {
  EdgeFrame f;
  f.point = d.p;
  Vec3 n = d.pu.cross(d.pv);
  if (n.squaredNorm() == 0 || d.pu.squaredNorm() == 0) throw Error("contact frame: singular surface point");
  n.normalize();
  if (flip_normal) n = -n;
  f.z = n;
  f.x = (d.pu - d.pu.dot(n) * n).normalized();
  f.y = f.z.cross(f.x);
  return f;
}

const char* to_string(EdgeContact c) { return c == EdgeContact::Bottom ? "bottom" : "corner"; }

FlatEnd flat_end_of(const Tool& tool) {
  if (tool.kind() != ToolKind::FlatEndMill)
    throw ParameterError("tool", std::string("expected a flat-end mill, got a ") + to_string(tool.kind()));
  FlatEnd f;
  f.radius_mm = tool.cutter().max_radius();
  for (const ProfileElement& e : tool.cutter().elements())
    if (e.kind == ProfileElement::Kind::Arc) {
      f.corner_mm = e.radius;
      break;
    }
  return f;
}

ToolPose position_tool(const FlatEnd& tool, const EdgeFrame& frame, const EdgePosition& pos) {
  const double R = tool.radius_mm, r = tool.corner_mm;
  Vec3 c_tool;
  double theta = 0;
  if (pos.contact == EdgeContact::Bottom) {
    if (!(pos.l_mm > 0 && pos.l_mm <= R - r + 1e-12))
      throw ParameterError("l", "the bottom contact must lie in (0, R - r] from the axis");
    c_tool = Vec3(pos.l_mm, 0, 0);
  } else {
    theta = pos.lead_rad;
    if (!(theta >= 0 && theta < kPi / 2)) throw ParameterError("lead", "expected 0 <= lead < 90 deg");
    c_tool = Vec3(R - r + r * std::sin(theta), 0, r * (1 - std::cos(theta)));
  }
  // p_L = Rz(φ) Ry(θ) (p_T - c_T): eq. (3)-(6) of the paper as one rotation.
  const Eigen::Matrix3d m =
      (Eigen::AngleAxisd(pos.side_slip_rad, Vec3::UnitZ()) * Eigen::AngleAxisd(theta, Vec3::UnitY())).toRotationMatrix();
  Eigen::Matrix3d f;
  f.col(0) = frame.x;
  f.col(1) = frame.y;
  f.col(2) = frame.z;
  ToolPose pose;
  pose.tip = frame.point + f * (-(m * c_tool));
  pose.axis = (f * m.col(2)).normalized();
  return pose;
}

StripSamples sample_strip(const Surface& surface, double u, double v, const StripSampling& sm, bool flip_normal) {
  if (sm.across < 3 || sm.across % 2 == 0) throw ParameterError("across", "expected an odd count >= 3");
  if (sm.along < 1 || sm.along % 2 == 0) throw ParameterError("along", "expected an odd count >= 1");
  if (!(sm.half_width_mm > 0) || !(sm.along_half_mm >= 0))
    throw ParameterError("half_width", "expected half_width > 0 and along_half >= 0");
  const SurfaceDerivs d = surface.eval(u, v);
  const int half = sm.across / 2, ahalf = sm.along / 2;
  const double dv = sm.half_width_mm / half / std::max(d.pv.norm(), 1e-12);
  const double du = ahalf > 0 ? sm.along_half_mm / ahalf / std::max(d.pu.norm(), 1e-12) : 0.0;
  std::vector<int> js;
  for (int j = -half; j <= half; ++j) {
    const double vj = v + j * dv;
    if (vj < -1e-12 || vj > 1 + 1e-12) continue;
    js.push_back(j);
  }
  StripSamples out;
  out.along = sm.along;
  out.across = static_cast<int>(js.size());
  out.s_mm.resize(out.across);
  out.p.resize(static_cast<size_t>(out.across) * out.along);
  out.n.resize(out.p.size());
  Vec3 prev = Vec3::Zero();
  for (int idx = 0; idx < out.across; ++idx) {
    const double vj = std::clamp(v + js[idx] * dv, 0.0, 1.0);
    if (js[idx] == 0) out.centre = idx;
    for (int k = 0; k < out.along; ++k) {
      const double uk = std::clamp(u + (k - ahalf) * du, 0.0, 1.0);
      const SurfaceDerivs e = surface.eval(uk, vj);
      Vec3 n = e.pu.cross(e.pv).normalized();
      if (flip_normal) n = -n;
      out.p[static_cast<size_t>(idx) * out.along + k] = e.p;
      out.n[static_cast<size_t>(idx) * out.along + k] = n;
    }
    // Arc offsets along the centre line (k = ahalf), from C.
    const Vec3 c = out.p[static_cast<size_t>(idx) * out.along + ahalf];
    out.s_mm[idx] = idx == 0 ? 0.0 : out.s_mm[idx - 1] + (c - prev).norm();
    prev = c;
  }
  if (sm.gouge_along > 1 && sm.gouge_half_mm > 0) {
    std::vector<double> lines;
    for (int idx = 0; idx < out.across; idx += std::max(sm.gouge_stride, 1))
      lines.push_back(std::clamp(v + js[idx] * dv, 0.0, 1.0));
    add_gouge_lines(out, surface, u, d.pu.norm(), lines, sm, flip_normal);
  }
  const double s0 = out.s_mm[out.centre];
  for (double& s : out.s_mm) s -= s0;
  return out;
}

void add_gouge_lines(StripSamples& out, const Surface& surface, double u, double pu_norm,
                     const std::vector<double>& lines, const StripSampling& sm, bool flip_normal) {
  if (sm.gouge_along < 2) return;
  const double gdu = 2 * sm.gouge_half_mm / (sm.gouge_along - 1) / std::max(pu_norm, 1e-12);
  for (double vj : lines) {
    for (int k = 0; k < sm.gouge_along; ++k) {
      const double uk = sm.gouge_whole_u ? static_cast<double>(k) / (sm.gouge_along - 1)
                                         : u + (k - (sm.gouge_along - 1) / 2.0) * gdu;
      if (uk < 0 || uk > 1) continue;
      const SurfaceDerivs e = surface.eval(uk, vj);
      Vec3 n = e.pu.cross(e.pv).normalized();
      out.gouge_p.push_back(e.p);
      out.gouge_n.push_back(flip_normal ? Vec3(-n) : n);
    }
  }
}

void add_flank_samples(StripSamples& out, const Surface& flank, double u_f, double end_v, const StripSampling& sm) {
  const SurfaceDerivs d = flank.eval(u_f, end_v);
  const int half = sm.across / 2;
  const double du = sm.half_width_mm / half / std::max(d.pu.norm(), 1e-12);
  const double dv = sm.gouge_half_mm / std::max(sm.gouge_along - 1, 1) / std::max(d.pv.norm(), 1e-12);
  const double dir = end_v < 0.5 ? 1.0 : -1.0;  // into the flank from its edge end
  for (int j = -half; j <= half; j += std::max(sm.gouge_stride, 1)) {
    const double uj = u_f + j * du;
    if (uj < 0 || uj > 1) continue;
    for (int k = 1; k < sm.gouge_along; ++k) {
      const double vk = end_v + dir * k * dv;
      if (vk < 0 || vk > 1) break;
      const SurfaceDerivs e = flank.eval(uj, vk);
      out.gouge_p.push_back(e.p);
      out.gouge_n.push_back(e.pu.cross(e.pv).normalized());
    }
  }
}

namespace {

// The cutter's signed distance at p (FlatEnd::signed_distance, the same
// arithmetic) and its rate of change along the unit direction m.
struct DistanceSlope {
  double d, slope;
};
DistanceSlope distance_and_slope(const FlatEnd& cutter, const Vec3& p, const Vec3& m) {
  const double rho = std::sqrt(p.x() * p.x() + p.y() * p.y());
  const double r = cutter.corner_mm;
  const double x = rho - (cutter.radius_mm - r);
  const double y = r - p.z();
  const double drho = rho > 1e-12 ? (p.x() * m.x() + p.y() * m.y()) / rho : 0.0;  // on the axis: a kink, 0 in it
  const double dy = -m.z();
  if (x <= 0 && y <= 0) return x > y ? DistanceSlope{x - r, drho} : DistanceSlope{y - r, dy};
  const double xp = std::max(x, 0.0), yp = std::max(y, 0.0);
  const double n = std::sqrt(xp * xp + yp * yp);
  return {n - r, (xp * drho + yp * dy) / n};
}

}  // namespace

double directed_distance(const FlatEnd& cutter, const Eigen::Isometry3d& part_to_tool, const Vec3& p,
                         const Vec3& n, double cap_mm) {
  const Vec3 q = part_to_tool * p;
  const Vec3 m = part_to_tool.linear() * n;
  constexpr double kTol = 1e-8;
  double t = 0;
  DistanceSlope ds = distance_and_slope(cutter, q, m);
  if (std::abs(ds.d) < kTol) return 0;
  // Where the line crosses the flat bottom (z = 0 within R - r of the axis,
  // the cutter above it) it crosses the convex cutter's boundary there and
  // nowhere else on that side: the crossing, in closed form.
  if (m.z() > 1e-9) {
    const double tp = -q.z() / m.z();
    if ((ds.d > 0) == (tp > 0)) {  // outside: ahead along +n; inside: behind
      const Vec3 h = q + tp * m;
      const double b = cutter.radius_mm - cutter.corner_mm;
      if (h.x() * h.x() + h.y() * h.y() <= b * b) return std::clamp(tp, -cap_mm, cap_mm);
    }
  }
  // The signed distance to a convex body is convex along any line: from
  // outside, Newton steps along +n never pass the surface (the tangent's
  // zero lies short of the crossing) and converge fast at any angle;
  // sphere tracing (step d) took ~ log(tol / d) / log(1 - sin a) steps for
  // a line meeting the surface at a, and gave up on lines within ~20 deg of
  // it. A line that does not approach, or meets the cutter not at all, ends
  // beyond the cap (+cap: the strip ends there, never a gouge hidden).
  if (ds.d > 0) {
    for (int it = 0; it < 40; ++it) {
      // Convex: d + slope (s - t) bounds the distance at s from below; where
      // that stays above 0 up to the cap, so does the line.
      if (ds.d + ds.slope * (cap_mm - t) > 0) return cap_mm;
      t += ds.d / -ds.slope;
      if (t > cap_mm) return cap_mm;
      ds = distance_and_slope(cutter, Vec3(q + t * m), m);
      if (ds.d < kTol) return t;
    }
    return cap_mm;
  }
  // Inside: along -n out of it, sphere tracing (a step of |d| stays inside),
  // then bisection once the convex distance rises slowly (a line leaving
  // nearly along the side).
  double d = ds.d;
  for (int it = 0; it < 12; ++it) {
    t += d;
    if (t < -cap_mm) return -cap_mm;
    d = cutter.signed_distance(Vec3(q + t * m));
    if (d > -kTol) return t;
  }
  double lo = -cap_mm, hi = t;  // lo outside (or the cap), hi inside
  if (cutter.signed_distance(Vec3(q + lo * m)) <= 0) return -cap_mm;
  while (hi - lo > kTol) {
    const double mid = 0.5 * (lo + hi);
    (cutter.signed_distance(Vec3(q + mid * m)) > 0 ? lo : hi) = mid;
  }
  return hi;
}

namespace {

// Condition ① over ps: the smallest of each sample's signed distance where
// it is outside the cutter and its directed distance where inside. With
// tiles, a tile wholly outside the cutter counts as its lower bound (>= 0):
// the result is the same wherever it is below 0.
// Stops at the first sample found below stop_below (returning its
// distance): whether a pose gouges needs no more.
double screen_deepest(const FlatEnd& cutter, const Eigen::Isometry3d& to_tool, const std::vector<Vec3>& ps,
                      const std::vector<Vec3>& ns, const SampleTiles* tiles, double cap, double stop_below) {
  double deepest = std::numeric_limits<double>::infinity();
  // The tool axis in the part frame: z (tool frame) = axis . p + z0. No
  // point of the cutter lies below its bottom plane z = 0, and a point at
  // z < 0 is at least -z outside it (FlatEnd::signed_distance).
  const Vec3 axis = to_tool.linear().row(2).transpose();
  const double z0 = to_tool.translation().z();
  auto range = [&](size_t a, size_t b) {
    for (size_t i = a; i < b; ++i) {
      if (tiles) {
        // A sample below the bottom plane stands for itself by that bound,
        // as a tile below it does (below_bottom): one dot product where the
        // whole transform and distance took two square roots (most samples
        // of a tile the box test leaves lie under a flat bottom).
        const double z = axis.dot(ps[i]) + z0;
        if (z < -1e-9) {
          deepest = std::min(deepest, -z);
          continue;
        }
      }
      const double sd = cutter.signed_distance(Vec3(to_tool * ps[i]));
      deepest = std::min(deepest, sd >= 0 ? sd : directed_distance(cutter, to_tool, ps[i], ns[i], cap));
      if (deepest < stop_below) return true;
    }
    return false;
  };
  if (!tiles) {
    range(0, ps.size());
    return deepest;
  }
  // A bound wholly outside the cutter stands for what it bounds.
  auto outside = [&](const SampleTile& t) { return cutter.signed_distance(Vec3(to_tool * t.centre)) - t.radius; };
  // A tile whose box lies wholly below the bottom plane stands for its
  // samples by that bound — positive, as the sphere's: the result is the
  // same wherever it is below 0 (every caller compares it with e1 <= 0),
  // and the first sample below stop_below is the same one.
  auto below_bottom = [&](const SampleTile& t) {
    double top = axis.dot(t.centre) + z0;
    for (int i = 0; i < 3; ++i) top += t.half[i] * std::abs(axis.dot(t.axes[i]));
    return -top;
  };
  for (const SampleTile& g : tiles->groups) {
    const double og = outside(g);
    if (og > 0) {
      deepest = std::min(deepest, og);
      continue;
    }
    const double bg = below_bottom(g);
    if (bg > 1e-9) {
      deepest = std::min(deepest, bg);
      continue;
    }
    for (size_t k = g.begin; k < g.end; ++k) {
      const SampleTile& t = tiles->tiles[k];
      const double ot = outside(t);
      if (ot > 0) {
        deepest = std::min(deepest, ot);
        continue;
      }
      const double bt = below_bottom(t);
      if (bt > 1e-9) deepest = std::min(deepest, bt);  // clear of rounding in the bound
      else if (range(t.begin, t.end)) return deepest;
    }
  }
  return deepest;
}

// Runs of `size` consecutive points (or tiles: centres and radii) bounded
// by a sphere about their mean.
template <class Centre, class Radius>
std::vector<SampleTile> bound_runs(size_t count, size_t size, Centre centre, Radius radius) {
  std::vector<SampleTile> out;
  for (size_t a = 0; a < count; a += size) {
    SampleTile t;
    t.begin = a;
    t.end = std::min(count, a + size);
    for (size_t i = t.begin; i < t.end; ++i) t.centre += centre(i);
    t.centre /= static_cast<double>(t.end - t.begin);
    for (size_t i = t.begin; i < t.end; ++i) t.radius = std::max(t.radius, (centre(i) - t.centre).norm() + radius(i));
    out.push_back(t);
  }
  return out;
}

// A tile's box (SampleTile::axes, half): its samples' mean normal, the
// direction across it from its first sample to the one farthest from that,
// and the third; each half size the largest offset along it. No box (the
// half sizes left infinite) where the normals cancel.
void box_tile(SampleTile& t, const std::vector<Vec3>& ps, const std::vector<Vec3>& ns) {
  Vec3 n = Vec3::Zero();
  for (size_t i = t.begin; i < t.end; ++i) n += ns[i];
  if (!(n.norm() > 1e-9)) return;
  n.normalize();
  size_t far = t.begin;
  for (size_t i = t.begin; i < t.end; ++i)
    if ((ps[i] - ps[t.begin]).norm() > (ps[far] - ps[t.begin]).norm()) far = i;
  Vec3 d = ps[far] - ps[t.begin];
  d -= n.dot(d) * n;
  if (!(d.norm() > 1e-12)) d = n.unitOrthogonal();
  d.normalize();
  t.axes[0] = d;
  t.axes[1] = n.cross(d);
  t.axes[2] = n;
  for (int k = 0; k < 3; ++k) {
    t.half[k] = 0;
    for (size_t i = t.begin; i < t.end; ++i) t.half[k] = std::max(t.half[k], std::abs(t.axes[k].dot(ps[i] - t.centre)));
  }
}

SampleTiles tile_samples(const std::vector<Vec3>& ps, const std::vector<Vec3>& ns) {
  constexpr size_t kTile = 8, kGroup = 8;
  SampleTiles st;
  st.tiles = bound_runs(ps.size(), kTile, [&](size_t i) { return ps[i]; }, [](size_t) { return 0.0; });
  for (SampleTile& t : st.tiles) box_tile(t, ps, ns);
  st.groups = bound_runs(st.tiles.size(), kGroup, [&](size_t i) { return st.tiles[i].centre; },
                         [&](size_t i) { return st.tiles[i].radius; });
  // A group's box over its samples (its tiles' range), for the same test.
  for (SampleTile& g : st.groups) {
    SampleTile over = g;
    over.begin = st.tiles[g.begin].begin;
    over.end = st.tiles[g.end - 1].end;
    box_tile(over, ps, ns);
    for (int k = 0; k < 3; ++k) {
      g.axes[k] = over.axes[k];
      g.half[k] = over.half[k];
    }
  }
  return st;
}

double deepest_over(const FlatEnd& cutter, const Eigen::Isometry3d& to_tool, const StripSamples& smp, double cap,
                    const SampleTiles* tiles, const SampleTiles* gouge_tiles,
                    const SharedGougeSamples* shared, double stop_below = -std::numeric_limits<double>::infinity()) {
  double d = screen_deepest(cutter, to_tool, smp.p, smp.n, tiles, cap, stop_below);
  if (d < stop_below) return d;
  d = std::min(d, screen_deepest(cutter, to_tool, smp.gouge_p, smp.gouge_n, gouge_tiles, cap, stop_below));
  if (d < stop_below) return d;
  if (shared) d = std::min(d, screen_deepest(cutter, to_tool, shared->p, shared->n, &shared->tiles, cap, stop_below));
  return d;
}

StripWidth width_of(const FlatEnd& cutter, const ToolPose& pose, const StripSamples& smp, const Band& band,
                    const SampleTiles* tiles, const SampleTiles* gouge_tiles,
                    const SharedGougeSamples* shared) {
  StripWidth w;
  const Eigen::Isometry3d to_tool = tool_to_part(pose).inverse();
  const double cap = 2 * (band.e2_mm - band.e1_mm);
  // ① every sample: cheap signed distance first, the directed one only where
  // the sample is inside the cutter. Screened (a contact's strip: the
  // searches try many gouging poses), the first sample below e1 ends it.
  w.deepest_mm = deepest_over(cutter, to_tool, smp, cap, tiles, gouge_tiles, shared,
                              tiles ? band.e1_mm : -std::numeric_limits<double>::infinity());
  if (w.deepest_mm < band.e1_mm) {
    w.gouges = true;
    return w;
  }
  // The least directed distance over a line across's samples along the
  // feed, the middle one first. A sample outside the cutter is no nearer
  // along its normal than its signed distance, less the trace's stop
  // (1e-8 mm: Newton stops that near the surface, never past it): where
  // that is at least the least found, its trace cannot lower it and is
  // skipped (the line's neighbours along the feed, mostly). Inside, the
  // trace runs the other way and can: never skipped.
  auto residual = [&](int j) {
    double r = std::numeric_limits<double>::infinity();
    for (int m = 0; m < smp.along; ++m) {
      const int k = (smp.along / 2 + m) % smp.along;
      const size_t i = static_cast<size_t>(j) * smp.along + k;
      if (m > 0) {
        const double sd = cutter.signed_distance(Vec3(to_tool * smp.p[i]));
        if (sd >= 0 && sd >= r + 1e-8) continue;
      }
      r = std::min(r, directed_distance(cutter, to_tool, smp.p[i], smp.n[i], cap));
    }
    return r;
  };
  const double rc = residual(smp.centre);
  w.touches = rc <= band.e2_mm;
  if (!w.touches) return w;
  // Walk out from C on each side while the residual stays in the band.
  auto extent = [&](int dir) {
    int j = smp.centre;
    double r_in = rc;
    while (true) {
      const int next = j + dir;
      if (next < 0 || next >= smp.across) return std::abs(smp.s_mm[j]);
      const double r = residual(next);
      if (r > band.e2_mm) {
        const double f = (band.e2_mm - r_in) / (r - r_in);
        return std::abs(smp.s_mm[j] + f * (smp.s_mm[next] - smp.s_mm[j]));
      }
      j = next;
      r_in = r;
    }
  };
  w.left_mm = extent(-1);
  w.right_mm = extent(+1);
  w.width_mm = w.left_mm + w.right_mm;
  return w;
}

double deepest_of(const FlatEnd& cutter, const ToolPose& pose, const StripSamples& smp, const Band& band,
                  const SampleTiles* tiles, const SampleTiles* gouge_tiles,
                  const SharedGougeSamples* shared) {
  const Eigen::Isometry3d to_tool = tool_to_part(pose).inverse();
  return deepest_over(cutter, to_tool, smp, 2 * (band.e2_mm - band.e1_mm), tiles, gouge_tiles, shared);
}

}  // namespace

StripWidth strip_width(const Tool& tool, const ToolPose& pose, const StripSamples& smp, const Band& band) {
  return width_of(flat_end_of(tool), pose, smp, band, nullptr, nullptr, nullptr);
}

double deepest_distance(const Tool& tool, const ToolPose& pose, const StripSamples& smp, const Band& band) {
  return deepest_of(flat_end_of(tool), pose, smp, band, nullptr, nullptr, nullptr);
}

double ContactStrip::deepest(const ToolPose& pose) const {
  return deepest_of(flat_, pose, samples_, band_, &tiles_, &gouge_tiles_, shared_.get());
}

std::shared_ptr<const SharedGougeSamples> share_gouge_samples(std::vector<Vec3> p, std::vector<Vec3> n) {
  if (p.size() != n.size()) throw ParameterError("samples", "as many normals as points expected");
  auto out = std::make_shared<SharedGougeSamples>();
  out->p = std::move(p);
  out->n = std::move(n);
  out->tiles = tile_samples(out->p, out->n);
  return out;
}

ContactStrip::ContactStrip(const Tool& tool, const EdgeFrame& frame, StripSamples samples, Band band,
                           std::shared_ptr<const SharedGougeSamples> shared)
    : flat_(flat_end_of(tool)),
      frame_(frame),
      samples_(std::move(samples)),
      band_(band),
      tiles_(tile_samples(samples_.p, samples_.n)),
      gouge_tiles_(tile_samples(samples_.gouge_p, samples_.gouge_n)),
      shared_(std::move(shared)) {}

ToolPose ContactStrip::pose(const EdgePosition& pos) const { return position_tool(flat_, frame_, pos); }

StripWidth ContactStrip::width(const EdgePosition& pos) const { return width(pose(pos)); }

StripWidth ContactStrip::width(const ToolPose& pose) const {
  return width_of(flat_, pose, samples_, band_, &tiles_, &gouge_tiles_, shared_.get());
}

namespace {

std::vector<double> l_values(const FlatEnd& f, double r_e, int count) {
  const double hi = f.radius_mm - f.corner_mm;
  if (!(r_e > 0)) throw ParameterError("r_e", "the cutting-speed radius must be > 0");
  if (r_e > hi) throw ParameterError("r_e", "the cutting-speed radius exceeds the flat bottom (R - r)");
  if (count < 1) throw ParameterError("l_count", "must be >= 1");
  std::vector<double> l;
  if (count == 1) return {hi};
  for (int j = 0; j < count; ++j) l.push_back(r_e + (hi - r_e) * j / (count - 1));
  return l;
}

double score(const StripWidth& w) { return w.gouges || !w.touches ? -1.0 : w.width_mm; }

}  // namespace

BottomOptimum optimise_side_slip(const ContactStrip& strip, double r_e_mm, int l_count, const SideSlipSearch& s) {
  BottomOptimum o;
  o.l_mm = l_values(strip.flat_end(), r_e_mm, l_count);
  double sum = 0;
  int n = 0;
  for (double l : o.l_mm) {
    const SearchResult r = search_side_slip(
        [&](double phi) { return score(strip.width({EdgeContact::Bottom, l, 0, phi})); }, s);
    o.evaluations += r.evaluations;
    o.phi_j_rad.push_back(r.phi_rad);
    o.width_j_mm.push_back(std::max(r.width_mm, 0.0));
    if (r.width_mm > 0) {
      sum += r.phi_rad;
      ++n;
    }
  }
  o.feasible = n > 0;
  o.phi_rad = n > 0 ? sum / n : 0.0;
  return o;
}

JointOptimum optimise_jointly(const ContactStrip& strip, double r_e_mm, int l_count, const SideSlipSearch& s) {
  JointOptimum o;
  for (double l : l_values(strip.flat_end(), r_e_mm, l_count)) {
    const SearchResult r = search_side_slip(
        [&](double phi) { return score(strip.width({EdgeContact::Bottom, l, 0, phi})); }, s);
    if (r.width_mm > 0 && r.width_mm >= o.width_mm) {  // ties: the larger l (cutting speed)
      o.feasible = true;
      o.width_mm = r.width_mm;
      o.position = {EdgeContact::Bottom, l, 0, r.phi_rad};
    }
  }
  return o;
}

CornerPosition corner_min_lead(const ContactStrip& strip, double min_lead_rad) {
  CornerPosition c;
  const double step = 0.5 * kPi / 180;
  for (double theta = std::max(min_lead_rad, 0.0); theta <= 60 * kPi / 180 + 1e-12; theta += step) {
    const EdgePosition pos{EdgeContact::Corner, 0, theta, 0};
    const StripWidth w = strip.width(pos);
    if (!w.gouges && w.touches) {
      c.feasible = true;
      c.position = pos;
      c.width = w;
      return c;
    }
  }
  return c;
}

BalancedRow balance_l(const std::vector<std::vector<double>>& widths) {
  BalancedRow b;
  b.width_mm = std::numeric_limits<double>::infinity();
  bool any = false;
  for (const auto& w : widths) {
    const double best = w.empty() ? 0.0 : *std::max_element(w.begin(), w.end());
    if (best > 0) {
      b.width_mm = std::min(b.width_mm, best);
      any = true;
    }
  }
  if (!any) b.width_mm = 0;
  for (const auto& w : widths) {
    int pick = -1;
    for (int j = static_cast<int>(w.size()) - 1; j >= 0; --j)
      if (w[j] > 0 && w[j] >= b.width_mm) {
        pick = j;
        break;
      }
    b.l_index.push_back(pick);
  }
  return b;
}

}  // namespace bliskrun
