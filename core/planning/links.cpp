#include "core/planning/links.h"

#include <sstream>

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

// Proves the chain of poses a, via..., b segment by segment.
Attempt prove(const ToolPose& a, const std::vector<ToolPose>& via, const std::vector<LinkLeg>& legs,
              const ToolPose& b, const LinkChecks& checks, double allowed_mm) {
  Attempt out;
  std::vector<const ToolPose*> chain{&a};
  for (const ToolPose& p : via) chain.push_back(&p);
  chain.push_back(&b);
  for (size_t s = 0; s + 1 < chain.size(); ++s) {
    const LinkLeg leg = s < legs.size() ? legs[s] : LinkLeg::Approach;
    std::ostringstream why;
    const MotionCheck mc =
        checks.world->check_motion(*checks.body, *chain[s], *chain[s + 1], checks.clearances, checks.motion_tol_mm);
    if (!mc.clear) {
      why << link_leg_name(leg) << " not clear at t = " << mc.t << (mc.undecided ? " (undecided)" : "")
          << ", margin " << mc.min_margin_mm << " mm";
      out.clear = false;
      out.reason = why.str();
      return out;
    }
    if (checks.guard) {
      // The link leaves the cutting pose a and reaches the cutting pose b:
      // their own cut belongs to their passes.
      const GougeGuard::Cut cut = checks.guard->deepest_cut(checks.body->tool(), *chain[s], *chain[s + 1],
                                                            allowed_mm, s > 0, s + 2 < chain.size());
      out.deepest_cut_mm = std::min(out.deepest_cut_mm, cut.depth_mm);
      if (cut.depth_mm < 0) {
        why << link_leg_name(leg) << " cuts " << -cut.depth_mm * 1000 << " um below the finished surface at t = "
            << cut.t << " (allowed " << allowed_mm * 1000 << " um)";
        out.clear = false;
        out.reason = why.str();
        return out;
      }
    }
  }
  return out;
}

}  // namespace

PlannedLink plan_link(const LinkEnd& from, const LinkEnd& to, const LinkChecks& checks, const LinkOptions& o) {
  if (!checks.world) throw ParameterError("world", "a collision world is required for links");
  if (!checks.body) throw ParameterError("body", "the tool body is required for links");
  if (!(o.retract_mm > 0)) throw ParameterError("retract_mm", "must be > 0");
  if (!(o.min_retract_mm > 0 && o.min_retract_mm <= o.retract_mm))
    throw ParameterError("min_retract_mm", "must be in (0, retract_mm]");
  if (!(o.axis_retract_mm >= 0)) throw ParameterError("axis_retract_mm", "must be >= 0");
  if (!(o.allowed_overcut_mm >= 0)) throw ParameterError("allowed_overcut_mm", "must be >= 0");
  const double allowed = std::max(0.0, o.allowed_overcut_mm - checks.guard_margin_mm);

  auto away = [&](const LinkEnd& e) {
    return o.direction == RetractDirection::SurfaceNormal ? unit_axis(e.normal, "normal")
                                                          : unit_axis(e.pose.axis, "axis");
  };
  const Vec3 ea = away(from), eb = away(to);
  PlannedLink best;
  std::string first_reason;
  for (double d = o.retract_mm; d >= o.min_retract_mm * (1 - 1e-12); d *= 0.5) {
    std::vector<ToolPose> via;
    std::vector<LinkLeg> legs;
    ToolPose up_a = from.pose, up_b = to.pose;
    up_a.tip += d * ea;
    up_b.tip += d * eb;
    via.push_back(up_a);
    legs.push_back(LinkLeg::Retract);
    if (o.axis_retract_mm > 0) {
      ToolPose high_a = up_a, high_b = up_b;
      high_a.tip += o.axis_retract_mm * unit_axis(up_a.axis);
      high_b.tip += o.axis_retract_mm * unit_axis(up_b.axis);
      via.push_back(high_a);
      legs.push_back(LinkLeg::Retract);
      via.push_back(high_b);
      legs.push_back(LinkLeg::Traverse);
      legs.push_back(LinkLeg::Approach);  // high_b -> up_b
    } else {
      legs.push_back(LinkLeg::Traverse);  // up_a -> up_b
    }
    via.push_back(up_b);
    legs.push_back(LinkLeg::Approach);  // up_b -> b
    const Attempt at = prove(from.pose, via, legs, to.pose, checks, allowed);
    if (at.clear) {
      best.clear = true;
      best.via = std::move(via);
      best.legs = std::move(legs);
      best.offset_mm = d;
      best.deepest_cut_mm = at.deepest_cut_mm;
      return best;
    }
    std::ostringstream why;
    why << "offset " << d << " mm: " << at.reason;
    if (first_reason.empty()) first_reason = why.str();
    best.reason = first_reason + (d == o.retract_mm ? "" : "; " + why.str());
  }
  return best;
}

}  // namespace bliskrun
