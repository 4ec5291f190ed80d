#include "core/machine/robot_cell.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "core/common/error.h"
#include "core/machine/wheel_clearance.h"

namespace bliskrun {

namespace {

bool orthonormal(const Mat3& r) {
  return (r.transpose() * r - Mat3::Identity()).norm() < 1e-9 && r.determinant() > 0;
}

// Blade-frame basis at a contact: tangent, normal x tangent, normal.
Mat3 contact_basis(const BladeContact& c, bool turned) {
  const Vec3 n = c.normal.normalized();
  Vec3 t = (c.tangent - c.tangent.dot(n) * n).normalized();
  if (turned) t = -t;
  Mat3 b;
  b.col(0) = t;
  b.col(1) = n.cross(t);
  b.col(2) = n;
  return b;
}

}  // namespace

void RobotCell::validate() const {
  arm.validate();
  if (!orthonormal(grip.linear())) throw ParameterError("grip", "expected a rotation (orthonormal, right-handed)");
  for (int i = 0; i < 6; ++i)
    if (home[i] < arm.joints[i].min_rad || home[i] > arm.joints[i].max_rad)
      throw ParameterError("home[" + std::to_string(i + 1) + "]", "expected a joint value within the limits");
  if (stations.empty()) throw ParameterError("stations", "expected at least one belt station");
  for (const BeltStation& s : stations) {
    const std::string key = "stations." + s.name;
    if (!orthonormal(s.contact.linear()))
      throw ParameterError(key + ".frame", "expected the wheel axis and normal at right angles");
    if (!(s.wheel_radius_mm > 0)) throw ParameterError(key + ".wheel.radius", "expected a radius > 0 in mm");
    if (!(s.wheel_width_mm > 0)) throw ParameterError(key + ".wheel.width", "expected a width > 0 in mm");
  }
}

const BeltStation& RobotCell::station(const std::string& station_name) const {
  std::string known;
  for (const BeltStation& s : stations) {
    if (s.name == station_name) return s;
    known += (known.empty() ? "" : ", ") + s.name;
  }
  throw ParameterError("station", "no station '" + station_name + "' in " + name + " (it has " + known + ")");
}

Frame flange_for_contact(const RobotCell& cell, const BeltStation& station, const BladeContact& c, bool turned) {
  // The station's basis at the contact: wheel axis, (-N) x axis, -N — the
  // part's normal points into the wheel.
  const Vec3 axis = station.contact.linear().col(0), out = station.contact.linear().col(2);
  Mat3 s;
  s.col(0) = axis;
  s.col(1) = (-out).cross(axis);
  s.col(2) = -out;
  Frame blade_in_base = Frame::Identity();  // base <- blade
  blade_in_base.linear() = s * contact_basis(c, turned).transpose();
  blade_in_base.translation() = station.contact.translation() - blade_in_base.linear() * c.point;
  return blade_in_base * cell.grip.inverse();
}

BladeContact contact_in_base(const RobotCell& cell, const Frame& flange, const BladeContact& c) {
  const Frame blade_in_base = flange * cell.grip;
  return {blade_in_base * c.point, blade_in_base.linear() * c.normal, blade_in_base.linear() * c.tangent};
}

Vec3 programmed_point(const RobotMove& m) { return m.contact.point + m.offset_mm * m.contact.normal.normalized(); }

double joint_speed_ratio(const RobotArm& arm, const RobotMove& from, const RobotMove& to) {
  const double dt = std::max((programmed_point(to) - programmed_point(from)).norm(), 1e-3) / to.feed_mm_s;
  double ratio = 0;
  for (int j = 0; j < 6; ++j)
    ratio = std::max(ratio, std::abs(to.joints[j] - from.joints[j]) / dt / arm.joints[j].max_speed_rad_s);
  return ratio;
}

namespace {

struct Trial {
  std::vector<RobotMove> moves;  // traverse back along the last path, approach, grinding moves, lift-off
  size_t traverse = 0;           // how many of the moves are the traverse
  bool turned = false;
  int branch_changes = 0;
  double seconds = 0;
  bool ok = true;
  std::string reason;
};

// One move: the flange for the contact offset `offset` away from the wheel,
// solved from the previous joints.
bool solve_move(const RobotCell& cell, const BeltStation& station, const BladeContact& c, double offset, bool turned,
                JointAngles& q, int& branch, Trial& trial, RobotMove& move) {
  BladeContact at = c;
  // The point `offset` out of the material along the normal is put on the
  // wheel, so the contact itself lies `offset` off the wheel, along its normal.
  at.point = c.point + offset * c.normal.normalized();
  const Frame flange = flange_for_contact(cell, station, at, turned);
  RobotIkOptions ik;
  ik.previous = q;
  const auto solutions = robot_inverse(cell.arm, flange, ik);
  const auto chosen = robot_choose(cell.arm, solutions, q, branch);
  if (!chosen) {
    trial.ok = false;
    if (solutions.empty()) {
      trial.reason = "out of the arm's reach";
    } else {
      const RobotSolution& s = solutions.front();
      trial.reason = "joint " + std::to_string(s.violated_joint + 1) + " would need " +
                     std::to_string(rad_to_deg(s.violated_value_rad)) + " deg, beyond its limits";
    }
    return false;
  }
  if (branch >= 0 && chosen->branch != branch) ++trial.branch_changes;
  trial.seconds += robot_joint_move_time(cell.arm, q, chosen->joints);
  move.joints = chosen->joints;
  move.branch = chosen->branch;
  move.wrist_singular = chosen->wrist_singular;
  move.turned = turned;
  move.contact = c;
  move.offset_mm = offset;
  q = chosen->joints;
  branch = chosen->branch;
  return true;
}

// A joint move (PTP, MoveJ, MoveAbsJ: the controller interpolates the
// joints linearly) from `a` to `b`, checked against the wheel: joint-linear
// samples 0.25° of the largest joint's travel apart, each step between
// samples as the wheel check's LIN (its own 1 mm / 1° subdivision). Between
// two samples the joint-linear path leaves that chord by at most
// R (1 - cos(0.125°)) = 2.4e-6 R: 5 µm for a point 2 m from the axis.
void check_joint_move(const RobotCell& cell, const BeltStation& station, const WheelClearance& wheel,
                      const JointAngles& a, const JointAngles& b, WheelContactReport& report) {
  double travel = 0;
  for (int j = 0; j < 6; ++j) travel = std::max(travel, std::abs(b[j] - a[j]));
  const int n = std::max(1, static_cast<int>(std::ceil(rad_to_deg(travel) / 0.25)));
  auto blade_at = [&](double s) {
    JointAngles q;
    for (int j = 0; j < 6; ++j) q[j] = a[j] + s * (b[j] - a[j]);
    return blade_in_station(cell, station, q);
  };
  Frame from = blade_at(0);
  wheel.check_pose(from, report);
  for (int k = 1; k <= n; ++k) {
    const Frame to = blade_at(static_cast<double>(k) / n);
    wheel.check_motion(from, to, report);
    from = to;
  }
}

// stage_home_moves (see plan_robot_grinding): for one end of the plan.
// `first`: home -> [staging ->] first move; else last move [-> staging] ->
// home. Inserts the staging move where one is needed; a refusal when no
// staging distance clears.
void stage_home_end(const RobotCell& cell, const BeltStation& station, const WheelClearance& wheel,
                    const RobotGrindingOptions& o, RobotGrindingPlan& plan, bool first) {
  const RobotMove end = first ? plan.moves.front() : plan.moves.back();
  WheelContactReport direct;
  direct.checked = true;
  check_joint_move(cell, station, wheel, first ? o.start : end.joints, first ? end.joints : o.start, direct);
  plan.wheel.poses += direct.poses;
  if (direct.collisions == 0) return;
  for (const double out : {50.0, 100.0, 200.0, 400.0}) {
    Trial scratch;
    JointAngles q = end.joints;
    int branch = end.branch;
    RobotMove staging = end;
    if (!solve_move(cell, station, end.contact, end.offset_mm + out, end.turned, q, branch, scratch, staging)) continue;
    staging.link = true;
    staging.path = -1;
    staging.feed_mm_s = o.link_feed_mm_s;
    WheelContactReport r;
    r.checked = true;
    check_joint_move(cell, station, wheel, first ? o.start : staging.joints, first ? staging.joints : o.start, r);
    if (first)
      wheel.check_motion(blade_in_station(cell, station, staging), blade_in_station(cell, station, end), r);
    else
      wheel.check_motion(blade_in_station(cell, station, end), blade_in_station(cell, station, staging), r);
    plan.wheel.poses += r.poses;
    if (r.collisions > 0) continue;
    // The straight link's joint speed at the link feed (as the plan rates
    // every move into a move).
    const RobotMove& from = first ? staging : end;
    RobotMove& into = first ? plan.moves.front() : staging;
    into.joint_speed_ratio = std::max(into.joint_speed_ratio, joint_speed_ratio(cell.arm, from, into));
    if (first) {
      plan.max_link_joint_speed_ratio = std::max(plan.max_link_joint_speed_ratio, into.joint_speed_ratio);
      plan.moves.insert(plan.moves.begin(), staging);
    } else {
      plan.max_link_joint_speed_ratio = std::max(plan.max_link_joint_speed_ratio, staging.joint_speed_ratio);
      plan.moves.push_back(staging);
    }
    return;
  }
  plan.wheel.collisions += direct.collisions;
  plan.wheel.max_collision_depth_mm = std::max(plan.wheel.max_collision_depth_mm, direct.max_collision_depth_mm);
  if (plan.wheel.first_collision.empty()) plan.wheel.first_collision = direct.first_collision;
  plan.refusals.push_back(std::string(first ? "the joint move from home to the first approach"
                                            : "the joint move from the last lift-off back home") +
                          ": the blade meets the wheel or belt (" + direct.first_collision +
                          "), and no staging pose up to 400 mm out along the contact's normal clears it");
}

void stage_home_moves(const RobotCell& cell, const BeltStation& station, const WheelClearance& wheel,
                      const RobotGrindingOptions& o, RobotGrindingPlan& plan) {
  stage_home_end(cell, station, wheel, o, plan, true);
  stage_home_end(cell, station, wheel, o, plan, false);
}

}  // namespace

RobotGrindingPlan plan_robot_grinding(const RobotCell& cell, const BeltStation& station,
                                      const std::vector<std::vector<BladeContact>>& paths,
                                      const RobotGrindingOptions& o) {
  if (!(o.feed_mm_s > 0)) throw ParameterError("feed", "expected a contact speed > 0 in mm/s");
  if (!(o.link_feed_mm_s > 0)) throw ParameterError("link_feed", "expected a speed > 0 in mm/s");
  if (!(o.retract_mm > 0)) throw ParameterError("retract", "expected a lift-off > 0 in mm");
  if (!(o.traverse_step_mm > 0)) throw ParameterError("traverse_step", "expected a step > 0 in mm");
  RobotGrindingPlan plan;
  std::unique_ptr<WheelClearance> wheel;
  if (o.blade) {
    wheel = std::make_unique<WheelClearance>(*o.blade, station);
    plan.wheel.checked = true;
  }
  JointAngles q = o.start;
  int branch = -1;
  const std::vector<BladeContact>* previous = nullptr;  // the last path emitted
  bool previous_turned = false;
  for (size_t k = 0; k < paths.size(); ++k) {
    const std::vector<BladeContact>& path = paths[k];
    if (path.empty()) continue;
    Trial trials[2];
    std::string reasons;
    for (bool turned : {false, true}) {
      Trial& trial = trials[turned ? 1 : 0];
      trial.turned = turned;
      JointAngles tq = q;
      int tb = branch;
      // Back from the previous path's lift-off: along that path, `retract`
      // off it, at most traverse_step apart (a straight traverse across a
      // convex face at the retract height would cut through the blade).
      if (previous) {
        const std::vector<BladeContact>& back = *previous;
        double since = 0;
        for (size_t i = back.size() - 1; i-- > 0 && trial.ok;) {
          since += (back[i + 1].point - back[i].point).norm();
          if (since < o.traverse_step_mm && i > 0) continue;
          since = 0;
          RobotMove m;
          if (!solve_move(cell, station, back[i], o.retract_mm, previous_turned, tq, tb, trial, m)) break;
          m.link = true;
          m.path = static_cast<int>(k);
          m.feed_mm_s = o.link_feed_mm_s;
          trial.moves.push_back(m);
        }
      }
      trial.traverse = trial.moves.size();
      // Approach the first point from off the wheel, grind, lift off.
      for (size_t i = 0; i <= path.size() + 1 && trial.ok; ++i) {
        const bool approach = i == 0, lift = i == path.size() + 1;
        const BladeContact& c = path[approach ? 0 : lift ? path.size() - 1 : i - 1];
        RobotMove m;
        if (!solve_move(cell, station, c, approach || lift ? o.retract_mm : 0.0, turned, tq, tb, trial, m)) break;
        m.link = approach || lift;
        m.path = static_cast<int>(k);
        m.feed_mm_s = m.link ? o.link_feed_mm_s : o.feed_mm_s;
        trial.moves.push_back(m);
      }
      if (!trial.ok)
        reasons += std::string(reasons.empty() ? "" : "; ") + (turned ? "turned: " : "as is: ") + trial.reason;
    }
    // Keep the previous path's turn unless it cannot grind this path: a turn
    // between paths swings the whole blade about the normal while it is only
    // `retract` off the wheel. Then fewer branch changes, then less time.
    const auto keeps_turn = [&](const Trial& t) {
      return plan.moves.empty() || plan.moves.back().turned == t.turned;
    };
    const auto prefer = [&](const Trial& a, const Trial& b) {
      if (keeps_turn(a) != keeps_turn(b)) return keeps_turn(a);
      if (a.branch_changes != b.branch_changes) return a.branch_changes < b.branch_changes;
      return a.seconds < b.seconds;
    };
    Trial* chosen = nullptr;
    for (;;) {
      chosen = nullptr;
      for (Trial& t : trials)
        if (t.ok && (!chosen || prefer(t, *chosen))) chosen = &t;
      if (!chosen || !wheel) break;
      // The wheel and belt against the whole blade: the link into the path
      // (from the last lift-off), every move and the motion between them.
      WheelContactReport r;
      Frame prev = blade_in_station(cell, station, plan.moves.empty() ? chosen->moves.front() : plan.moves.back());
      if (plan.moves.empty()) wheel->check_pose(prev, r);
      std::string where = "at the first approach";
      for (size_t i = 0; i < chosen->moves.size() && r.collisions == 0; ++i) {
        const Frame next = blade_in_station(cell, station, chosen->moves[i]);
        wheel->check_motion(prev, next, r);
        prev = next;
        const size_t a = chosen->traverse;  // the approach
        where = i < a    ? "traversing back along path " + std::to_string(k)
                : i == a ? "on the way to the approach"
                : i + 1 == chosen->moves.size() ? "lifting off"
                                                : "at point " + std::to_string(i - a);
      }
      if (r.collisions > 0) r.first_collision = where + ": " + r.first_collision;
      plan.wheel.poses += r.poses;
      if (r.collisions == 0) {
        plan.wheel.max_conformity_mm = std::max(plan.wheel.max_conformity_mm, r.max_conformity_mm);
        break;
      }
      chosen->ok = false;
      reasons += std::string(reasons.empty() ? "" : "; ") + (chosen->turned ? "turned: " : "as is: ") +
                 r.first_collision;
      ++plan.wheel.collisions;
      plan.wheel.max_collision_depth_mm = std::max(plan.wheel.max_collision_depth_mm, r.max_collision_depth_mm);
      if (plan.wheel.first_collision.empty())
        plan.wheel.first_collision = "path " + std::to_string(k + 1) + ": " + r.first_collision;
    }
    if (!chosen) {
      plan.refusals.push_back("path " + std::to_string(k + 1) + ": " + reasons);
      continue;
    }
    Trial& best = *chosen;
    ++plan.paths;
    if (best.turned) ++plan.turned_paths;
    if (!plan.moves.empty() && plan.moves.back().turned != best.turned) ++plan.turn_changes;
    for (RobotMove& m : best.moves) {
      // Joint speed for the move into m at its feed (contact distance over
      // the feed; the approach comes from wherever the last path ended).
      if (!plan.moves.empty()) {
        const RobotMove& p = plan.moves.back();
        m.joint_speed_ratio = std::max(m.joint_speed_ratio, joint_speed_ratio(cell.arm, p, m));
        if (m.branch != p.branch) ++plan.branch_changes;
      }
      double& worst = m.link ? plan.max_link_joint_speed_ratio : plan.max_joint_speed_ratio;
      worst = std::max(worst, m.joint_speed_ratio);
      if (m.wrist_singular) ++plan.singular_moves;
      plan.moves.push_back(m);
    }
    q = plan.moves.back().joints;
    branch = plan.moves.back().branch;
    previous = &path;
    previous_turned = plan.moves.back().turned;
  }
  // The program's first and last motions: a joint move from the start
  // (home) to the first approach and from the last lift-off back home, as
  // the posts write them. Swung in by the joints, the blade can pass
  // through the wheel or its belt (found on the built-in blade's fine
  // station); then a staging pose further out along the first contact's
  // normal (50, 100, 200, 400 mm) is reached by the joint move and left in
  // a straight line, and the same on the way out. Every such motion is
  // checked; if none clears, nothing of this plan may be posted (refused).
  if (wheel && !plan.moves.empty()) stage_home_moves(cell, station, *wheel, o, plan);
  return plan;
}

}  // namespace bliskrun
