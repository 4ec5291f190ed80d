#include "core/planning/links.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "core/common/error.h"

namespace bliskrun {

const char* link_leg_name(LinkLeg leg) {
  switch (leg) {
    case LinkLeg::Retract: return "retract";
    case LinkLeg::Traverse: return "traverse";
    case LinkLeg::Approach: return "approach";
  }
  return "?";
}

namespace {

struct Attempt {
  bool clear = true;
  double deepest_cut_mm = 0;
  std::string reason;
};

// One motion from -> to, proved against the world and the guard; `name`
// names it in the reason. include_from/include_to: whether the end poses'
// own cut counts (not for a pose that belongs to a cutting pass).
bool prove_motion(const ToolPose& from, const ToolPose& to, const LinkChecks& checks, double allowed_mm,
                  bool include_from, bool include_to, const std::string& name, Attempt& out,
                  const CollisionWorld* also = nullptr) {
  std::ostringstream why;
  for (const CollisionWorld* world : {checks.world, also}) {
    if (!world) continue;
    const MotionCheck mc = world->check_motion(*checks.body, from, to, checks.clearances, checks.motion_tol_mm);
    if (mc.clear) continue;
    why << name << " not clear at t = " << mc.t << (mc.undecided ? " (undecided)" : "") << ", margin "
        << mc.min_margin_mm << " mm";
    if (mc.at.worst >= 0) {
      const PartClearance& pc = mc.at.parts[mc.at.worst];
      why << " (" << to_string(pc.part);
      if (pc.object >= 0) why << " vs " << world->name(pc.object);
      why << ")";
    }
    out.clear = false;
    out.reason = why.str();
    return false;
  }
  std::vector<LinkChecks::Guard> guards;
  if (checks.guard) guards.push_back({checks.guard, checks.guard_margin_mm});
  guards.insert(guards.end(), checks.more_guards.begin(), checks.more_guards.end());
  for (const LinkChecks::Guard& g : guards) {
    // Each guard takes off the allowance what its samples can miss.
    const double allowed = std::max(0.0, allowed_mm - g.margin_mm);
    const GougeGuard::Cut cut =
        g.guard->deepest_cut(checks.body->tool(), from, to, allowed, include_from, include_to);
    out.deepest_cut_mm = std::min(out.deepest_cut_mm, cut.depth_mm);
    if (cut.depth_mm < 0) {
      why << name << " cuts " << -cut.depth_mm * 1000 << " um below the finished surface at t = " << cut.t
          << " (allowed " << allowed * 1000 << " um)";
      out.clear = false;
      out.reason = why.str();
      return false;
    }
  }
  return true;
}

// Proves the chain of poses a, via..., b segment by segment. `b_cuts`: b
// is a cutting pose (the next pass's first), whose own cut is its pass's.
Attempt prove(const ToolPose& a, const std::vector<ToolPose>& via, const std::vector<LinkLeg>& legs,
              const ToolPose& b, const LinkChecks& checks, double allowed_mm, bool b_cuts = true) {
  Attempt out;
  std::vector<const ToolPose*> chain{&a};
  for (const ToolPose& p : via) chain.push_back(&p);
  chain.push_back(&b);
  for (size_t s = 0; s + 1 < chain.size(); ++s) {
    const LinkLeg leg = s < legs.size() ? legs[s] : LinkLeg::Approach;
    // The link leaves the cutting pose a and reaches the cutting pose b:
    // their own cut belongs to their passes.
    if (!prove_motion(*chain[s], *chain[s + 1], checks, allowed_mm, s > 0, s + 2 < chain.size() || !b_cuts,
                      link_leg_name(leg), out, leg == LinkLeg::Traverse ? checks.traverse_world.get() : nullptr))
      return out;
  }
  return out;
}

void check_options(const LinkChecks& checks, const LinkOptions& o) {
  if (!checks.world) throw ParameterError("world", "a collision world is required for links");
  if (!checks.body) throw ParameterError("body", "the tool body is required for links");
  if (!(o.retract_mm > 0)) throw ParameterError("retract_mm", "must be > 0");
  if (!(o.min_retract_mm > 0 && o.min_retract_mm <= o.retract_mm))
    throw ParameterError("min_retract_mm", "must be in (0, retract_mm]");
  if (!(o.axis_retract_mm >= 0)) throw ParameterError("axis_retract_mm", "must be >= 0");
  if (!(o.allowed_overcut_mm >= 0)) throw ParameterError("allowed_overcut_mm", "must be >= 0");
}

// The allowed overcut; each guard takes its own margin off it (prove).
double allowance(const LinkChecks&, const LinkOptions& o) { return o.allowed_overcut_mm; }

// Directions tried, in order: the normal itself, then turned towards the
// tool axis by 30 and 60 degrees — where leaving straight along the normal
// runs into a neighbouring surface (e.g. the hub under a first row planned at
// its hub clearance), leaving along the normal *and* up the axis clears it
// while still lifting off the finished surface at once (the gouge guard
// proves that, as for every leg).
constexpr double kTurnsRad[] = {0.0, kPi / 6, kPi / 3};

Vec3 away_from(const LinkEnd& e, const LinkOptions& o, double turn_rad) {
  if (o.direction == RetractDirection::ToolAxis) return unit_axis(e.pose.axis, "axis");
  const Vec3 n = unit_axis(e.normal, "normal");
  if (turn_rad == 0) return n;
  Vec3 up = unit_axis(e.pose.axis) - unit_axis(e.pose.axis).dot(n) * n;
  if (up.norm() < 1e-9) return n;  // the axis is along the normal already
  return std::cos(turn_rad) * n + std::sin(turn_rad) * up.normalized();
}

// The (direction turn, offset) pairs a link or lead tries, in order of
// preference: straight along the normal from the largest offset down, then
// each turn up the axis likewise.
struct Candidate {
  double turn_rad, offset_mm;
};
std::vector<Candidate> candidates(const LinkOptions& o) {
  std::vector<Candidate> out;
  const int turns = o.direction == RetractDirection::ToolAxis ? 1 : 3;
  for (int k = 0; k < turns; ++k)
    for (double d = o.retract_mm; d >= o.min_retract_mm * (1 - 1e-12); d *= 0.5) out.push_back({kTurnsRad[k], d});
  return out;
}

// "offset d mm [turned x deg up the axis]: reason", kept for the largest
// offset of each direction (the smaller ones add little).
void add_reason(std::string& reasons, const Candidate& c, const LinkOptions& o, const std::string& why) {
  if (c.offset_mm != o.retract_mm) return;
  std::ostringstream os;
  os << "offset " << c.offset_mm << " mm";
  if (c.turn_rad > 0) os << " turned " << c.turn_rad * 180 / kPi << " deg up the axis";
  os << ": " << why;
  reasons += (reasons.empty() ? "" : "; ") + os.str();
}

// The angle between a unit axis and the pole's line (either way along it).
double off_pole(const Vec3& unit, const Vec3& pole) { return std::acos(std::min(1.0, std::abs(unit.dot(pole)))); }

// Inserts around_pole's poses into every leg of a -> via... -> b that
// turns its axis past the pole, each of the leg's kind.
void keep_off_pole(const ToolPose& a, std::vector<ToolPose>& via, std::vector<LinkLeg>& legs, const ToolPose& b,
                   const LinkOptions& o) {
  if (o.pole.isZero() || !(o.pole_clearance_rad > 0)) return;
  std::vector<ToolPose> out_via;
  std::vector<LinkLeg> out_legs;
  for (size_t s = 0; s <= via.size(); ++s) {
    const ToolPose& from = s == 0 ? a : via[s - 1];
    const ToolPose& to = s < via.size() ? via[s] : b;
    const LinkLeg leg = s < legs.size() ? legs[s] : LinkLeg::Approach;
    for (ToolPose& p : around_pole(from, to, o.pole.normalized(), o.pole_clearance_rad)) {
      out_via.push_back(std::move(p));
      out_legs.push_back(leg);
    }
    out_legs.push_back(leg);
    if (s < via.size()) out_via.push_back(to);
  }
  via = std::move(out_via);
  legs = std::move(out_legs);
}

}  // namespace

double angle_off_pole(const Vec3& a_in, const Vec3& b_in, const Vec3& pole) {
  const Vec3 a = a_in.normalized(), b = b_in.normalized();
  double least = std::min(off_pole(a, pole), off_pole(b, pole));
  const Vec3 n = a.cross(b);
  if (n.norm() < 1e-12) return least;  // no turn (or half a turn: PoseMotion's own choice)
  const Vec3 nn = n.normalized();
  // The great circle's points nearest the pole's line: the pole projected
  // onto its plane, either way; inside the arc from a to b?
  const Vec3 q = pole - pole.dot(nn) * nn;
  if (q.norm() < 1e-12) return least;  // the circle is the pole's equator
  for (const Vec3& c : {Vec3(q.normalized()), Vec3(-q.normalized())})
    if (a.cross(c).dot(nn) >= 0 && c.cross(b).dot(nn) >= 0) least = std::min(least, off_pole(c, pole));
  return least;
}

std::vector<ToolPose> around_pole(const ToolPose& a, const ToolPose& b, const Vec3& pole, double clearance_rad) {
  const Vec3 ua = unit_axis(a.axis), ub = unit_axis(b.axis);
  const double end_off = std::min(off_pole(ua, pole), off_pole(ub, pole));
  if (end_off < clearance_rad || angle_off_pole(ua, ub, pole) >= clearance_rad) return {};
  // Spherical coordinates about the pole the leg passes (the one nearer
  // the axis half-way): polar angle theta off it, azimuth phi round it.
  const PoseMotion motion(a, b);
  const Vec3 p = motion.pose_at(0.5).axis.dot(pole) >= 0 ? pole : Vec3(-pole);
  const Vec3 e1 = (std::abs(p.x()) < 0.9 ? Vec3(Vec3::UnitX()) : Vec3(Vec3::UnitY())).cross(p).normalized();
  const Vec3 e2 = p.cross(e1);
  auto polar = [&](const Vec3& v) { return std::acos(std::clamp(v.dot(p), -1.0, 1.0)); };
  auto azimuth = [&](const Vec3& v) { return std::atan2(v.dot(e2), v.dot(e1)); };
  // The azimuth the great circle turns through, the way it passes.
  constexpr int kSamples = 256;
  double turn = 0, last = azimuth(ua);
  for (int i = 1; i <= kSamples; ++i) {
    const double phi = azimuth(unit_axis(motion.pose_at(static_cast<double>(i) / kSamples).axis));
    turn += std::remainder(phi - last, 2 * kPi);
    last = phi;
  }
  // Steps of at most 22.5 deg round the pole: a great circle between two
  // axes theta off it and that far apart keeps within 2 % of theta.
  const int pieces = std::max(2, static_cast<int>(std::ceil(std::abs(turn) / (kPi / 8))));
  const double theta_a = polar(ua), theta_b = polar(ub), phi_a = azimuth(ua);
  std::vector<ToolPose> out;
  for (int k = 1; k < pieces; ++k) {
    const double t = static_cast<double>(k) / pieces;
    const double theta = std::max((1 - t) * theta_a + t * theta_b, 2 * clearance_rad);
    const double phi = phi_a + t * turn;
    ToolPose q;
    q.tip = (1 - t) * a.tip + t * b.tip;
    q.axis = std::cos(theta) * p + std::sin(theta) * (std::cos(phi) * e1 + std::sin(phi) * e2);
    out.push_back(q);
  }
  return out;
}

PlannedDeparture plan_departure(const LinkEnd& at, const LinkChecks& checks, const LinkOptions& o) {
  check_options(checks, o);
  const double allowed = allowance(checks, o);
  PlannedDeparture out;
  for (const Candidate& c : candidates(o)) {
    ToolPose away = at.pose;
    away.tip += c.offset_mm * away_from(at, o, c.turn_rad);
    const Attempt a = prove(at.pose, {}, {LinkLeg::Retract}, away, checks, allowed, false);
    if (a.clear) {
      out.clear = true;
      out.away = away;
      out.offset_mm = c.offset_mm;
      out.turn_rad = c.turn_rad;
      out.deepest_cut_mm = a.deepest_cut_mm;
      out.reason.clear();
      return out;
    }
    add_reason(out.reason, c, o, a.reason);
  }
  return out;
}

PlannedLink plan_link(const LinkEnd& from, const LinkEnd& to, const LinkChecks& checks, const LinkOptions& o,
                      const std::vector<ToolPose>& traverse_via) {
  check_options(checks, o);
  const double allowed = allowance(checks, o);
  PlannedLink best;
  for (const Candidate& c : candidates(o)) {
    ToolPose up_a = from.pose, up_b = to.pose;
    up_a.tip += c.offset_mm * away_from(from, o, c.turn_rad);
    up_b.tip += c.offset_mm * away_from(to, o, c.turn_rad);
    std::vector<ToolPose> via{up_a};
    std::vector<LinkLeg> legs{LinkLeg::Retract};
    if (o.axis_retract_mm > 0) {
      ToolPose high_a = up_a, high_b = up_b;
      high_a.tip += o.axis_retract_mm * unit_axis(up_a.axis);
      high_b.tip += o.axis_retract_mm * unit_axis(up_b.axis);
      via.insert(via.end(), {high_a, high_b});
      legs.insert(legs.end(), {LinkLeg::Retract, LinkLeg::Traverse, LinkLeg::Approach});  // .. high_b -> up_b
    } else {
      legs.push_back(LinkLeg::Traverse);  // up_a -> up_b
    }
    // Through the caller's waypoints: up_a [-> high_a] -> via... -> [high_b ->] up_b.
    const size_t insert_at = o.axis_retract_mm > 0 ? 2 : 1;
    via.insert(via.begin() + static_cast<long>(insert_at), traverse_via.begin(), traverse_via.end());
    legs.insert(legs.begin() + static_cast<long>(insert_at), traverse_via.size(), LinkLeg::Traverse);
    via.push_back(up_b);
    legs.push_back(LinkLeg::Approach);  // up_b -> b
    keep_off_pole(from.pose, via, legs, to.pose, o);
    const Attempt at = prove(from.pose, via, legs, to.pose, checks, allowed);
    if (at.clear) {
      best.clear = true;
      best.via = std::move(via);
      best.legs = std::move(legs);
      best.offset_mm = c.offset_mm;
      best.turn_rad = c.turn_rad;
      best.deepest_cut_mm = at.deepest_cut_mm;
      best.reason.clear();
      return best;
    }
    add_reason(best.reason, c, o, at.reason);
  }
  return best;
}

ChainProof prove_chain(const std::vector<ToolPose>& chain, const LinkChecks& checks, double allowed_mm,
                       bool first_cuts, bool last_cuts) {
  if (!checks.world) throw ParameterError("world", "a collision world is required");
  if (!checks.body) throw ParameterError("body", "the tool body is required");
  ChainProof out;
  Attempt a;
  for (size_t s = 0; s + 1 < chain.size(); ++s) {
    if (!prove_motion(chain[s], chain[s + 1], checks, allowed_mm, s > 0 || !first_cuts,
                      s + 2 < chain.size() || !last_cuts, "motion " + std::to_string(s + 1), a)) {
      out.clear = false;
      out.segment = static_cast<int>(s);
      break;
    }
  }
  out.deepest_cut_mm = a.deepest_cut_mm;
  out.reason = a.reason;
  return out;
}

}  // namespace bliskrun
