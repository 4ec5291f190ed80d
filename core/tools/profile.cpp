#include "core/tools/profile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {
namespace {

constexpr double kJoinTolMm = 1e-9;
constexpr double kAngleTol = 1e-12;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Angle of v in (-pi, pi].
double angle_of(const Vec2& v) { return std::atan2(v.y(), v.x()); }

// a - b wrapped into [0, 2pi).
double ccw_from(double a, double b) {
  double d = std::fmod(a - b, 2 * kPi);
  if (d < 0) d += 2 * kPi;
  return d;
}

double arc_start_angle(const ProfileElement& e) { return angle_of(e.start - e.centre); }
double arc_sweep(const ProfileElement& e) {
  return ccw_from(angle_of(e.end - e.centre), arc_start_angle(e));
}

// Whether the angle lies in the arc's span (with a tiny tolerance).
bool arc_contains_angle(const ProfileElement& e, double angle) {
  const double d = ccw_from(angle, arc_start_angle(e));
  return d <= arc_sweep(e) + kAngleTol || d >= 2 * kPi - kAngleTol;
}

double element_length(const ProfileElement& e) {
  if (e.kind == ProfileElement::Kind::Segment) return (e.end - e.start).norm();
  return e.radius * arc_sweep(e);
}

Vec2 start_tangent(const ProfileElement& e) {
  if (e.kind == ProfileElement::Kind::Segment) return (e.end - e.start).normalized();
  const Vec2 u = (e.start - e.centre) / e.radius;
  return Vec2(-u.y(), u.x());
}

Vec2 end_tangent(const ProfileElement& e) {
  if (e.kind == ProfileElement::Kind::Segment) return (e.end - e.start).normalized();
  const Vec2 u = (e.end - e.centre) / e.radius;
  return Vec2(-u.y(), u.x());
}

// Outward normal of a counter-clockwise chain: the right-hand side.
Vec2 outward_of_tangent(const Vec2& t) { return Vec2(t.y(), -t.x()); }

struct Closest {
  Vec2 point;
  Vec2 normal;
  double distance;
};

Closest closest_on_element(const ProfileElement& e, const Vec2& p) {
  if (e.kind == ProfileElement::Kind::Segment) {
    const Vec2 d = e.end - e.start;
    const double u = std::clamp((p - e.start).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const Vec2 q = e.start + u * d;
    return {q, outward_of_tangent(d.normalized()), (p - q).norm()};
  }
  const Vec2 rel = p - e.centre;
  if (rel.norm() > 0 && arc_contains_angle(e, angle_of(rel))) {
    const Vec2 u = rel.normalized();
    return {e.centre + e.radius * u, u, std::abs(rel.norm() - e.radius)};
  }
  if (rel.norm() == 0) {  // every arc point is equally near
    return {e.start, (e.start - e.centre) / e.radius, e.radius};
  }
  const double ds = (p - e.start).norm(), de = (p - e.end).norm();
  if (ds <= de) return {e.start, (e.start - e.centre) / e.radius, ds};
  return {e.end, (e.end - e.centre) / e.radius, de};
}

[[noreturn]] void bad_profile(int index, const std::string& why) {
  std::ostringstream os;
  os << "element " << index << ": " << why;
  throw ParameterError("profile", os.str());
}

}  // namespace

ProfileElement ProfileElement::segment(const Vec2& a, const Vec2& b) {
  ProfileElement e;
  e.kind = Kind::Segment;
  e.start = a;
  e.end = b;
  return e;
}

ProfileElement ProfileElement::arc(const Vec2& centre, double radius, const Vec2& a,
                                   const Vec2& b) {
  ProfileElement e;
  e.kind = Kind::Arc;
  e.centre = centre;
  e.radius = radius;
  e.start = a;
  e.end = b;
  return e;
}

Profile::Profile(std::vector<ProfileElement> elements) : elements_(std::move(elements)) {
  if (elements_.empty()) throw ParameterError("profile", "needs at least one element");
  for (int i = 0; i < static_cast<int>(elements_.size()); ++i) {
    const ProfileElement& e = elements_[i];
    if (!e.start.allFinite() || !e.end.allFinite()) bad_profile(i, "end points must be finite");
    if ((e.end - e.start).norm() < kJoinTolMm) bad_profile(i, "has zero length");
    if (e.start.x() < -kJoinTolMm || e.end.x() < -kJoinTolMm) bad_profile(i, "reaches r < 0");
    if (e.end.y() < e.start.y() - kJoinTolMm) bad_profile(i, "runs downwards (z must not decrease)");
    if (e.kind == ProfileElement::Kind::Arc) {
      if (!(e.radius > 0) || !e.centre.allFinite()) bad_profile(i, "arc radius must be positive");
      const double tol = 1e-9 * std::max(1.0, e.radius);
      if (std::abs((e.start - e.centre).norm() - e.radius) > tol ||
          std::abs((e.end - e.centre).norm() - e.radius) > tol) {
        bad_profile(i, "arc end points are not on its circle");
      }
      const double a0 = arc_start_angle(e);
      // Counter-clockwise and inside the right half of its circle: z rises
      // and the arc is convex as seen from outside.
      if (a0 < -kPi / 2 - 1e-9 || a0 + arc_sweep(e) > kPi / 2 + 1e-9) {
        bad_profile(i, "arc must run counter-clockwise within the half of its circle facing +r");
      }
    }
    if (i > 0) {
      const ProfileElement& prev = elements_[i - 1];
      if ((prev.end - e.start).norm() > kJoinTolMm) bad_profile(i, "does not start where the previous element ends");
      if (cross2(end_tangent(prev), start_tangent(e)) < -1e-9) {
        bad_profile(i, "turns clockwise at its start: the profile must be convex");
      }
    }
  }
  if (std::abs(elements_.front().start.x()) > kJoinTolMm) {
    throw ParameterError("profile", "must start on the axis (r = 0)");
  }
  if (std::abs(elements_.back().end.x()) > kJoinTolMm) {
    throw ParameterError("profile", "must end on the axis (r = 0)");
  }
  z_min_ = elements_.front().start.y();
  z_max_ = elements_.back().end.y();
  if (!(z_max_ > z_min_)) throw ParameterError("profile", "must have positive height");
  for (const ProfileElement& e : elements_) {
    for (const Vec2& p : {e.start, e.end}) {
      max_radius_ = std::max(max_radius_, p.x());
      reach_ = std::max(reach_, p.norm());
    }
    if (e.kind == ProfileElement::Kind::Arc) {
      if (arc_contains_angle(e, 0.0)) max_radius_ = std::max(max_radius_, e.centre.x() + e.radius);
      if (e.centre.norm() > 0 && arc_contains_angle(e, angle_of(e.centre))) {
        reach_ = std::max(reach_, e.centre.norm() + e.radius);
      }
    }
  }
  // The longest segment along the cylinder's side (exactly at max_radius:
  // only there is the cylinder's nearest point the solid's). None: the side
  // range empty, the corner boxes each the cylinder's whole height.
  side_z_lo_ = z_max_;
  side_z_hi_ = z_min_;
  bool side_found = false;
  for (const ProfileElement& e : elements_) {
    if (e.kind == ProfileElement::Kind::Segment && e.start.x() == max_radius_ && e.end.x() == max_radius_ &&
        (!side_found || e.end.y() - e.start.y() > side_z_hi_ - side_z_lo_)) {
      side_found = true;
      side_z_lo_ = e.start.y();
      side_z_hi_ = e.end.y();
    }
  }
  const ProfileElement& first = elements_.front();
  if (first.kind == ProfileElement::Kind::Segment && first.start.y() == z_min_ && first.end.y() == z_min_)
    flat_bottom_r_ = first.end.x();
  const ProfileElement& last = elements_.back();
  if (last.kind == ProfileElement::Kind::Segment && last.start.y() == z_max_ && last.end.y() == z_max_)
    flat_top_r_ = last.start.x();
}

std::pair<Profile, Profile> Profile::split_at(double z) const {
  if (!(z > z_min_ && z < z_max_)) throw ParameterError("split", "expected a height strictly inside the profile");
  const double r = radius_at(z);
  std::vector<ProfileElement> below, above;
  for (const ProfileElement& e : elements_) {
    if (e.end.y() <= z) {
      below.push_back(e);
    } else if (e.start.y() >= z) {
      above.push_back(e);
    } else if (e.kind == ProfileElement::Kind::Segment) {
      const Vec2 p = e.start + (e.end - e.start) * ((z - e.start.y()) / (e.end.y() - e.start.y()));
      below.push_back(ProfileElement::segment(e.start, p));
      above.push_back(ProfileElement::segment(p, e.end));
    } else {
      // Arcs lie in the half of their circle facing +r.
      const double dz = z - e.centre.y();
      const Vec2 p(e.centre.x() + std::sqrt(std::max(0.0, e.radius * e.radius - dz * dz)), z);
      below.push_back(ProfileElement::arc(e.centre, e.radius, e.start, p));
      above.push_back(ProfileElement::arc(e.centre, e.radius, p, e.end));
    }
  }
  below.push_back(ProfileElement::segment({r, z}, {0, z}));
  above.insert(above.begin(), ProfileElement::segment({0, z}, {r, z}));
  return {Profile(std::move(below)), Profile(std::move(above))};
}

std::vector<Vec3> Profile::surface_samples(double z0, double z1, int rings, int around) const {
  z0 = std::max(z0, z_min_);
  z1 = std::max(z0, std::min(z1, z_max_));
  std::vector<Vec3> out;
  for (int i = 0; i <= rings; ++i) {
    const double z = z0 + (z1 - z0) * i / std::max(rings, 1);
    const double r = radius_at(z);
    for (int k = 0; k < around; ++k) {
      const double a = 2 * kPi * k / around;
      out.emplace_back(r * std::cos(a), r * std::sin(a), z);
      if (i == 0) out.emplace_back(0.5 * r * std::cos(a), 0.5 * r * std::sin(a), z);
    }
  }
  out.emplace_back(0, 0, z0);
  return out;
}

double Profile::radius_at(double z) const {
  if (z < z_min_ || z > z_max_) return 0;
  double r = 0;
  for (const ProfileElement& e : elements_) {
    const double za = e.start.y(), zb = e.end.y();
    if (z < za || z > zb) continue;
    if (e.kind == ProfileElement::Kind::Segment) {
      if (zb - za < kJoinTolMm) {
        r = std::max({r, e.start.x(), e.end.x()});
      } else {
        const double u = (z - za) / (zb - za);
        r = std::max(r, e.start.x() + u * (e.end.x() - e.start.x()));
      }
    } else {
      const double dz = z - e.centre.y();
      r = std::max(r, e.centre.x() + std::sqrt(std::max(0.0, e.radius * e.radius - dz * dz)));
    }
  }
  return r;
}

ProfilePoint Profile::closest_point(const Vec2& rz) const {
  ProfilePoint best;
  double best_d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < static_cast<int>(elements_.size()); ++i) {
    const Closest c = closest_on_element(elements_[i], rz);
    if (c.distance < best_d) {
      best_d = c.distance;
      best = ProfilePoint{c.point, c.normal, i};
    }
  }
  return best;
}

bool Profile::on_own_boundary(double r, double z) const {
  return (r == max_radius_ && z >= side_z_lo_ && z <= side_z_hi_) || (z == z_min_ && r <= flat_bottom_r_) ||
         (z == z_max_ && r <= flat_top_r_);
}

// The distance alone, as closest_point finds it, without its angles: the
// simulation and the gouge guards trace every sample's normal line on it,
// millions of times a plan. A point lies in an arc's span (less than a half
// turn, counter-clockwise from start to end) when it is left of the start
// radius and right of the end radius — two cross products where
// closest_point takes four arc tangents and two fmods; squared distances,
// one square root.
double Profile::signed_distance(const Vec2& rz) const {
  // First the bounding cylinder's signed distance, where it is provably the
  // solid's: most points a sweep asks lie under a flat bottom or beside a
  // straight side, and need no loop over the elements.
  const double r = rz.x(), z = rz.y();
  if (r < 0) {
    // Off the half-plane of a solid of revolution (an arc's centre, asked
    // by the tests): the chain's own distance below.
  } else if (r > max_radius_ || z < z_min_ || z > z_max_) {
    // Outside: the solid lies within the cylinder, so it is no nearer than
    // the cylinder's nearest point c; where c is the solid's too, it is as
    // near.
    const double cr = std::min(r, max_radius_), cz = std::clamp(z, z_min_, z_max_);
    if (on_own_boundary(cr, cz)) return std::sqrt((r - cr) * (r - cr) + (z - cz) * (z - cz));
  } else {
    // Inside: the cylinder's distance d bounds the solid's from above. What
    // of the cylinder is not the solid lies in its two corner boxes (r past
    // the flat end faces, z beyond the straight side: the solid is convex
    // and holds those faces and the side); where both lie at least d away,
    // the disc of radius d about rz is the solid's and d is exact.
    const double d = std::min({max_radius_ - r, z - z_min_, z_max_ - z});
    auto clear_of = [&](double box_r0, double dz) {
      const double dr = std::max(box_r0 - r, 0.0);
      dz = std::max(dz, 0.0);
      const double gap2 = dr * dr + dz * dz;
      return d > 0 ? gap2 >= d * d : gap2 > 0;  // on the cylinder: not in a box
    };
    if (clear_of(flat_bottom_r_, z - side_z_lo_) && clear_of(flat_top_r_, side_z_hi_ - z)) return -d;
  }
  // The solid is convex: where the nearest point lies inside an element (not
  // on a vertex), the side of that element's line or circle says whether rz
  // is inside; only at a vertex is R(z) asked (a loop over the elements).
  double best2 = std::numeric_limits<double>::infinity();
  int side = 0;  // of the nearest element where decided: -1 inside, +1 outside, 0 ask R(z)
  for (const ProfileElement& e : elements_) {
    double d2;
    int s = 0;
    if (e.kind == ProfileElement::Kind::Segment) {
      const Vec2 d = e.end - e.start;
      const double len2 = d.squaredNorm();
      const double t = len2 > 0 ? (rz - e.start).dot(d) / len2 : 0.0;
      const double u = std::clamp(t, 0.0, 1.0);
      const Vec2 off = rz - (e.start + u * d);
      d2 = off.squaredNorm();
      // Outward normal of a chain run with the solid on its left: (d_z, -d_r).
      if (t > 0 && t < 1) s = off.x() * d.y() - off.y() * d.x() > 0 ? 1 : -1;
    } else {
      const Vec2 rel = rz - e.centre;
      if (cross2(e.start - e.centre, rel) >= 0 && cross2(rel, e.end - e.centre) >= 0) {
        const double g = rel.norm() - e.radius;
        d2 = g * g;
        s = g > 0 ? 1 : -1;
      } else {
        d2 = std::min((rz - e.start).squaredNorm(), (rz - e.end).squaredNorm());
      }
    }
    if (d2 < best2) {
      best2 = d2;
      side = s;
    } else if (d2 == best2 && s != side) {
      side = 0;  // a tie between elements: let R(z) decide
    }
  }
  const double d = std::sqrt(best2);
  if (side == 0) side = rz.y() > z_min_ && rz.y() < z_max_ && rz.x() < radius_at(rz.y()) ? -1 : 1;
  if (d == 0) return 0;
  return side < 0 ? -d : d;
}

double Profile::signed_distance(const Vec3& p) const {
  return signed_distance(Vec2(std::sqrt(p.x() * p.x() + p.y() * p.y()), p.z()));
}

ProfilePoint Profile::point_with_normal(const Vec2& n_in) const {
  if (!(n_in.norm() > 0) || n_in.x() < -1e-12) {
    throw ParameterError("normal", "must be a non-zero (r, z) direction with r >= 0");
  }
  const double psi = angle_of(n_in);
  const int count = static_cast<int>(elements_.size());
  // Normal angles rise monotonically from -pi/2 to pi/2 along a convex chain;
  // walk vertex cone, element, vertex cone, ... and take the first match.
  auto in_cone = [&](double lo, double hi) { return psi >= lo - kAngleTol && psi <= hi + kAngleTol; };
  auto normal_angle_at_start = [&](const ProfileElement& e) { return angle_of(outward_of_tangent(start_tangent(e))); };
  auto normal_angle_at_end = [&](const ProfileElement& e) { return angle_of(outward_of_tangent(end_tangent(e))); };
  for (int i = 0; i < count; ++i) {
    const ProfileElement& e = elements_[i];
    const double cone_lo = i == 0 ? -kPi / 2 : normal_angle_at_end(elements_[i - 1]);
    if (in_cone(cone_lo, normal_angle_at_start(e))) {
      return ProfilePoint{e.start, Vec2(std::cos(psi), std::sin(psi)), i};
    }
    if (e.kind == ProfileElement::Kind::Arc && arc_contains_angle(e, psi)) {
      const Vec2 u(std::cos(psi), std::sin(psi));
      return ProfilePoint{e.centre + e.radius * u, u, i};
    }
  }
  return ProfilePoint{elements_.back().end, Vec2(std::cos(psi), std::sin(psi)), count - 1};
}

int Profile::element_at(double z) const {
  if (!(z > z_min_ && z < z_max_)) {
    std::ostringstream os;
    os << "height " << z << " mm is outside the profile's open range (" << z_min_ << ", " << z_max_ << ")";
    throw ParameterError("z", os.str());
  }
  for (int i = 0; i < static_cast<int>(elements_.size()); ++i) {
    const ProfileElement& e = elements_[i];
    if (e.end.y() - e.start.y() > kJoinTolMm && z >= e.start.y() && z <= e.end.y()) return i;
  }
  throw ParameterError("z", "no side element spans this height");  // unreachable for a valid chain
}

ProfilePoint Profile::side_point(double z) const {
  const int i = element_at(z);
  const ProfileElement& e = elements_[i];
  const Vec2 p(radius_at(z), z);
  if (e.kind == ProfileElement::Kind::Segment) {
    return ProfilePoint{p, outward_of_tangent((e.end - e.start).normalized()), i};
  }
  return ProfilePoint{p, (p - e.centre).normalized(), i};
}

double Profile::meridian_curvature(double z) const {
  const ProfileElement& e = elements_[element_at(z)];
  return e.kind == ProfileElement::Kind::Arc ? 1.0 / e.radius : 0.0;
}

double Profile::parallel_curvature(double z) const {
  const ProfilePoint p = side_point(z);
  return p.normal.x() / p.point.x();
}

double Profile::effective_radius(double z, double angle_from_meridian_rad) const {
  const double c = std::cos(angle_from_meridian_rad), s = std::sin(angle_from_meridian_rad);
  const double k = meridian_curvature(z) * c * c + parallel_curvature(z) * s * s;
  return k > 0 ? 1.0 / k : std::numeric_limits<double>::infinity();
}

namespace {

// Where an element meets a circle or a line, with the arc length from the
// element's start.
struct Hit {
  Vec2 point;
  double along_mm;
};

void hits_with_circle(const ProfileElement& e, const Vec2& c, double rho, std::vector<Hit>& out) {
  if (e.kind == ProfileElement::Kind::Segment) {
    const Vec2 d = e.end - e.start;
    const Vec2 f = e.start - c;
    const double a = d.squaredNorm(), b = 2 * f.dot(d), cc = f.squaredNorm() - rho * rho;
    const double disc = b * b - 4 * a * cc;
    if (disc < 0) return;
    const double sq = std::sqrt(disc);
    for (double u : {(-b - sq) / (2 * a), (-b + sq) / (2 * a)}) {
      if (u >= 0 && u <= 1) out.push_back({e.start + u * d, u * std::sqrt(a)});
    }
    return;
  }
  const Vec2 d = c - e.centre;
  const double dist = d.norm();
  if (dist == 0 || dist > e.radius + rho || dist < std::abs(e.radius - rho)) return;
  const double x = (dist * dist + e.radius * e.radius - rho * rho) / (2 * dist);
  const double h = std::sqrt(std::max(0.0, e.radius * e.radius - x * x));
  const Vec2 u = d / dist, v(-u.y(), u.x());
  for (double sgn : {-1.0, 1.0}) {
    const Vec2 p = e.centre + x * u + sgn * h * v;
    const double angle = angle_of(p - e.centre);
    if (arc_contains_angle(e, angle)) {
      double da = ccw_from(angle, arc_start_angle(e));
      if (da > kPi) da = 0;  // the tolerance band just before the start
      out.push_back({p, e.radius * da});
    }
  }
}

void hits_with_line(const ProfileElement& e, const Vec2& l0, const Vec2& dir, std::vector<Hit>& out) {
  const Vec2 n(-dir.y(), dir.x());  // unit normal of the line
  if (e.kind == ProfileElement::Kind::Segment) {
    const double fa = (e.start - l0).dot(n), fb = (e.end - l0).dot(n);
    if ((fa > 0 && fb > 0) || (fa < 0 && fb < 0) || fa == fb) return;
    const double u = fa / (fa - fb);
    out.push_back({e.start + u * (e.end - e.start), u * (e.end - e.start).norm()});
    return;
  }
  // Points of the circle at signed distance 0 from the line.
  const double dc = (e.centre - l0).dot(n);
  if (std::abs(dc) > e.radius) return;
  const Vec2 foot = e.centre - dc * n;
  const double h = std::sqrt(e.radius * e.radius - dc * dc);
  for (double sgn : {-1.0, 1.0}) {
    const Vec2 p = foot + sgn * h * dir;
    const double angle = angle_of(p - e.centre);
    if (arc_contains_angle(e, angle)) {
      double da = ccw_from(angle, arc_start_angle(e));
      if (da > kPi) da = 0;
      out.push_back({p, e.radius * da});
    }
  }
}

}  // namespace

CutWidth Profile::cut_width(double z_contact, double k_surface, double residual_height_mm) const {
  if (!(residual_height_mm > 0) || !std::isfinite(residual_height_mm)) {
    throw ParameterError("residual_height", "must be a positive length in mm");
  }
  if (!std::isfinite(k_surface)) throw ParameterError("normal_curvature", "must be finite");
  const ProfilePoint contact = side_point(z_contact);
  const double k_tool = meridian_curvature(z_contact);
  if (k_surface >= k_tool) {
    std::ostringstream os;
    os << "surface normal curvature " << k_surface << " /mm is not below the profile's curvature "
       << k_tool << " /mm at z = " << z_contact
       << " mm: the profile does not separate from the surface (gouge or no finite width)";
    throw ParameterError("normal_curvature", os.str());
  }
  if (k_surface > 0 && residual_height_mm >= 1.0 / k_surface) {
    throw ParameterError("residual_height", "must be smaller than the surface's radius of curvature");
  }
  // Section frame (s, t) in (r, z): the profile's outward normal at the
  // contact points into the part, i.e. along -t.
  const Vec2 P = contact.point, n = contact.normal, tau(-n.y(), n.x());
  auto to_section = [&](const Vec2& q) { return Vec2((q - P).dot(tau), -(q - P).dot(n)); };

  std::vector<Hit> hits;
  std::vector<double> element_start_mm;
  double along = 0;
  for (const ProfileElement& e : elements_) {
    element_start_mm.push_back(along);
    std::vector<Hit> local;
    if (k_surface == 0) {
      hits_with_line(e, P - residual_height_mm * n, tau, local);
    } else {
      const Vec2 centre = P - (1.0 / k_surface) * n;
      const double rho = k_surface > 0 ? 1.0 / k_surface - residual_height_mm
                                       : -1.0 / k_surface + residual_height_mm;
      hits_with_circle(e, centre, rho, local);
    }
    for (Hit& h : local) hits.push_back({h.point, along + h.along_mm});
    along += element_length(e);
  }
  const ProfileElement& ce = elements_[contact.element];
  double contact_along = element_start_mm[contact.element];
  if (ce.kind == ProfileElement::Kind::Segment) {
    contact_along += (P - ce.start).norm();
  } else {
    contact_along += ce.radius * ccw_from(angle_of(P - ce.centre), arc_start_angle(ce));
  }
  const Hit* before = nullptr;
  const Hit* after = nullptr;
  for (const Hit& h : hits) {
    if (h.along_mm < contact_along && (!before || h.along_mm > before->along_mm)) before = &h;
    if (h.along_mm > contact_along && (!after || h.along_mm < after->along_mm)) after = &h;
  }
  if (!before || !after) {
    std::ostringstream os;
    os << "the profile ends before it rises " << residual_height_mm << " mm above the surface on the "
       << (before ? "shank" : "tip") << " side of the contact at z = " << z_contact << " mm";
    throw ParameterError("residual_height", os.str());
  }
  CutWidth w;
  w.a = to_section(before->point);
  w.b = to_section(after->point);
  w.width_mm = (w.a - w.b).norm();
  return w;
}

std::vector<Vec2> Profile::circumscribed_polyline(double tol_mm) const {
  if (!(tol_mm > 0)) throw ParameterError("tol_mm", "tessellation tolerance must be positive");
  std::vector<Vec2> out{elements_.front().start};
  auto push = [&](const Vec2& p) {
    if ((p - out.back()).norm() > kJoinTolMm) out.push_back(p);
  };
  for (const ProfileElement& e : elements_) {
    if (e.kind == ProfileElement::Kind::Arc) {
      // Tangent polygon: corners at radius rho / cos(step/2) stay within tol.
      const double max_step = 2 * std::acos(1.0 / (1.0 + tol_mm / e.radius));
      const double sweep = arc_sweep(e);
      const int n = std::max(1, static_cast<int>(std::ceil(sweep / max_step)));
      const double step = sweep / n, a0 = arc_start_angle(e);
      const double corner = e.radius / std::cos(step / 2);
      for (int k = 0; k < n; ++k) {
        const double a = a0 + (k + 0.5) * step;
        push(e.centre + corner * Vec2(std::cos(a), std::sin(a)));
      }
    }
    push(e.end);
  }
  return out;
}

}  // namespace bliskrun
