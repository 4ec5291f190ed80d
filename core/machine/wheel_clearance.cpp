#include "core/machine/wheel_clearance.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/common/error.h"
#include "core/machine/robot.h"

namespace bliskrun {

namespace {

// A blade point this close to the wheel's or belt's surface touches it: the
// samples' rounding, not a collision (a point on the plane of the wheel's
// side face, at the end of its width, is at depth 0 in floating point).
constexpr double kTouchMm = 1e-3;

// Arc length of the iso-line of s at fixed t (along u when along_u), the
// longest of five, on 64 chords: enough to size a sampling lattice.
double longest_iso_length(const Surface& s, bool along_u) {
  double longest = 0;
  for (int k = 0; k <= 4; ++k) {
    const double fixed = k / 4.0;
    double length = 0;
    Vec3 prev = along_u ? s.point(0, fixed) : s.point(fixed, 0);
    for (int i = 1; i <= 64; ++i) {
      const double t = i / 64.0;
      const Vec3 p = along_u ? s.point(t, fixed) : s.point(fixed, t);
      length += (p - prev).norm();
      prev = p;
    }
    longest = std::max(longest, length);
  }
  return longest;
}

}  // namespace

BladeBody BladeBody::sample(const std::vector<std::pair<std::string, std::shared_ptr<const Surface>>>& faces,
                            double spacing_mm) {
  if (!(spacing_mm > 0)) throw ParameterError("spacing", "expected a sample spacing > 0 in mm");
  if (faces.empty()) throw ParameterError("faces", "expected at least one face of the blade");
  BladeBody body;
  body.spacing_mm = spacing_mm;
  // Named members, not a structured binding: C++17 lambdas cannot capture
  // structured bindings (clang refuses; gcc allows it as an extension).
  for (const auto& named_face : faces) {
    const std::string& name = named_face.first;
    const std::shared_ptr<const Surface>& surface = named_face.second;
    if (!surface) throw ParameterError("faces." + name, "expected a surface");
    const int face = static_cast<int>(body.face_names.size());
    body.face_names.push_back(name);
    // 1 % more samples than the iso-line lengths ask for: the lattice's
    // spacing is uneven where the parametrisation is.
    const auto count = [&](bool along_u) {
      const double n = std::ceil(1.01 * longest_iso_length(*surface, along_u) / spacing_mm);
      if (n > 20000) throw ParameterError("spacing", "expected a spacing the face '" + name + "' can be sampled at (" +
                                                         std::to_string(n) + " samples along one side)");
      return static_cast<int>(n) + 1;
    };
    const int nu = count(true), nv = count(false);
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        body.points.push_back(surface->point(static_cast<double>(i) / (nu - 1), static_cast<double>(j) / (nv - 1)));
        body.face.push_back(face);
      }
  }
  return body;
}

WheelClearance::WheelClearance(const BladeBody& blade, const BeltStation& station, WheelClearanceOptions options)
    : blade_(blade),
      r_(station.wheel_radius_mm),
      half_w_(0.5 * station.wheel_width_mm),
      cap_(station.compliance_mm),
      belt_run_(station.belt_run_mm),
      options_(options),
      index_(blade.points, std::max({station.wheel_radius_mm / 3, 4 * blade.spacing_mm, 1e-3})) {
  if (!(r_ > 0) || !(half_w_ > 0)) throw ParameterError("wheel", "expected a wheel radius and width > 0");
  if (!(cap_ >= 0) || cap_ >= r_) throw ParameterError("compliance", "expected 0 <= compliance < the wheel radius, mm");
  if (!(belt_run_ >= 0)) throw ParameterError("belt_run", "expected a belt run >= 0 in mm");
  if (!(options_.step_mm > 0) || !(options_.step_deg > 0))
    throw ParameterError("step", "expected interpolation steps > 0");
  if (blade_.points.empty()) throw ParameterError("blade", "expected a sampled blade");
}

void WheelClearance::check_wheel_in_blade(const Frame& wheel_in_blade, WheelContactReport& report) const {
  ++report.poses;
  const Mat3& R = wheel_in_blade.linear();
  const Vec3 o = wheel_in_blade.translation();
  const Vec3 x = R.col(0), y = R.col(1), z = R.col(2);
  // The box (blade frame) of a station-frame box [a, b].
  const auto box = [&](const Vec3& a, const Vec3& b, Vec3& lo, Vec3& hi) {
    const Vec3 c = o + R * (0.5 * (a + b)), h = R.cwiseAbs() * (0.5 * (b - a));
    lo = c - h;
    hi = c + h;
  };
  double deepest = 0;
  std::string what;
  const auto hit = [&](int k, double depth, const Vec3& d, const char* body) {
    if (depth <= std::max(deepest, kTouchMm)) return;
    deepest = depth;
    const Vec3& p = blade_.points[static_cast<size_t>(k)];
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  "%s face point (%.3f, %.3f, %.3f) %.3f mm inside the %s (%.2f mm along the wheel axis, %.2f mm "
                  "across, %.2f mm behind the contact)",
                  blade_.face_names[static_cast<size_t>(blade_.face[static_cast<size_t>(k)])].c_str(), p.x(), p.y(),
                  p.z(), depth, body, d.dot(x), d.dot(y), -d.dot(z));
    what = buf;
  };
  Vec3 lo, hi;
  box(Vec3(-half_w_, -r_, -2 * r_), Vec3(half_w_, r_, 0), lo, hi);
  index_.for_each_in_box(lo, hi, [&](int k) {
    const Vec3 d = blade_.points[static_cast<size_t>(k)] - o;
    const double px = d.dot(x);
    if (std::abs(px) > half_w_) return;
    const double py = d.dot(y), pz = d.dot(z);
    const double rho = std::hypot(py, pz + r_);
    if (rho >= r_) return;
    const double depth = r_ - rho;
    if (pz >= -cap_) {
      report.max_conformity_mm = std::max(report.max_conformity_mm, depth);
    } else {
      hit(k, std::min(depth, half_w_ - std::abs(px)), d, "wheel, beyond its compliance");
    }
  });
  if (belt_run_ > 0) {
    box(Vec3(-half_w_, -r_, -r_ - belt_run_), Vec3(half_w_, r_, -r_), lo, hi);
    index_.for_each_in_box(lo, hi, [&](int k) {
      const Vec3 d = blade_.points[static_cast<size_t>(k)] - o;
      const double px = d.dot(x), py = d.dot(y), pz = d.dot(z);
      if (std::abs(px) > half_w_ || std::abs(py) >= r_ || pz > -r_ || pz < -r_ - belt_run_) return;
      hit(k, std::min({half_w_ - std::abs(px), r_ - std::abs(py)}), d, "belt behind the wheel");
    });
  }
  if (deepest > 0) {
    if (report.collisions == 0) report.first_collision = what;
    ++report.collisions;
    report.max_collision_depth_mm = std::max(report.max_collision_depth_mm, deepest);
  }
}

void WheelClearance::check_pose(const Frame& blade_in_station, WheelContactReport& report) const {
  check_wheel_in_blade(blade_in_station.inverse(), report);
}

void WheelClearance::check_motion(const Frame& from, const Frame& to, WheelContactReport& report) const {
  // With an external TCP the controller moves the wheel's frame on a
  // straight line in the part's frame and turns it by slerp (LIN).
  const Frame a = from.inverse(), b = to.inverse();
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  const double travel = (b.translation() - a.translation()).norm();
  const double turn = rad_to_deg(qa.angularDistance(qb));
  const int n = std::max(1, static_cast<int>(std::ceil(std::max(travel / options_.step_mm, turn / options_.step_deg))));
  for (int k = 1; k <= n; ++k) {
    const double s = static_cast<double>(k) / n;
    Frame w = Frame::Identity();
    w.linear() = qa.slerp(s, qb).toRotationMatrix();
    w.translation() = (1 - s) * a.translation() + s * b.translation();
    check_wheel_in_blade(w, report);
  }
}

Frame blade_in_station(const RobotCell& cell, const BeltStation& station, const RobotMove& move) {
  return blade_in_station(cell, station, move.joints);
}

Frame blade_in_station(const RobotCell& cell, const BeltStation& station, const JointAngles& joints) {
  return station.contact.inverse() * robot_forward(cell.arm, joints) * cell.grip;
}

}  // namespace bliskrun
