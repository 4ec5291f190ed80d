// A row's contacts into passes: each contact tilted until clear by the
// interference loop (core/collision/tilt.h), the pose checked against the
// design surfaces by the gouge guards (the ball and 2 r of cone) and the
// flute above against both blades; refusals and dipping motions split the
// row. All rows on the workers.
#include <algorithm>
#include <sstream>

#include "core/common/parallel.h"
#include "core/planning/hub_finish/internal.h"

namespace bliskrun::hub_detail {

std::string Planner::gouge(const ToolPose& p) const {
  const struct {
    const GougeGuard* g;
    const char* name;
  } all[] = {{guards.blade.get(), "blade k"}, {guards.next.get(), "blade k+1"}, {guards.hub.get(), "the hub"}};
  for (const auto& a : all) {
    if (!a.g) continue;
    const GougeGuard::Cut c = a.g->deepest_cut(short_tool, p, p, pose_allowed, true, true);
    if (c.depth_mm < 0) {
      std::ostringstream os;
      os << "the cutter cuts " << -c.depth_mm * 1000 << " um into " << a.name << " at (" << c.point.x() << ", "
         << c.point.y() << ", " << c.point.z() << ")";
      return os.str();
    }
  }
  if (!flute_body) return "";
  const PoseCheck fc = flute_world.check(*flute_body, flute_pose(p), flute_clearance, 0);
  if (!fc.clear) return "the flute above the ball: " + describe(fc, flute_world);
  return "";
}

double Planner::flute_margin(const ToolPose& p) const {
  return flute_body ? flute_world.check(*flute_body, flute_pose(p), flute_clearance, 1.0).min_margin_mm : 1e300;
}

bool Planner::motion_dips(const ToolPose& a, double margin_a, const ToolPose& b, double margin_b) const {
  const PoseMotion motion(a, b);
  if (motion.angle_rad() > kSweepTurnRad)
    for (const GougeGuard* g : {guards.blade.get(), guards.next.get(), guards.hub.get()})
      if (g && g->deepest_cut(short_tool, a, b, pose_allowed, false, false, kCutSweepMm).depth_mm < 0) return true;
  if (!flute_body || std::min(margin_a, margin_b) > motion.max_point_speed(flute_top_mm)) return false;
  return !flute_world.check_motion(*flute_body, flute_pose(a), flute_pose(b), flute_clearance, rq.motion_tol_mm).clear;
}

void Planner::plan_row(HubFinishOp op, int row, double level, bool reversed, const std::vector<Contact>& contacts,
                       double max_dev, std::vector<HubFinishPass>& out, std::vector<HubFinishRefusal>& refusals,
                       int& gouge_splits, Progress& progress, const ToolPose* start_previous) const {
  HubFinishPass cur;
  cur.op = op;
  cur.row = row;
  cur.level = level;
  cur.reversed = reversed;
  cur.max_deviation_mm = max_dev;
  auto close = [&] {
    if (!cur.poses.empty()) out.push_back(cur);
    cur.poses.clear();
  };
  double prev_margin = 0;
  for (size_t i = 0; i < contacts.size(); ++i) {
    progress.check();
    const Contact& c = contacts[i];
    const ToolPose* prev = !cur.poses.empty() ? &cur.poses.back().pose : i == 0 ? start_previous : nullptr;
    TiltOutcome o = tilt_until_clear(world, body, c.frame, static_cast<int>(i), c.tilt, prev);
    if (!o.accepted && c.has_second) {
      const TiltOutcome o2 = tilt_until_clear(world, body, c.frame, static_cast<int>(i), c.second, prev);
      if (o2.accepted) o = o2;
      else o.refusal.reason += "; and leaning further: " + o2.refusal.reason;
    }
    if (!o.accepted) {
      refusals.push_back({op, row, c.frame.point, o.refusal.reason});
      close();
      continue;
    }
    HubFinishPose hp;
    hp.pose = o.pose.pose;
    hp.contact = c.frame.point;
    hp.normal = c.frame.normal;
    hp.centre = c.centre;
    hp.t = c.t;
    hp.tilted = o.pose.tries > 1;
    const double margin = flute_margin(hp.pose);
    if (prev && motion_dips(*prev, prev_margin, hp.pose, margin)) {
      ++gouge_splits;
      refusals.push_back({op, row, c.frame.point,
                          "the cutting motion from the previous contact dips below the design: row split"});
      close();
    }
    cur.poses.push_back(hp);
    prev_margin = margin;
  }
  close();
}

namespace {

// Per row planned (root rows first, then floor rows): its passes, its
// refusals, its motion splits and its chord deviation.
struct RowsPlanned {
  std::vector<std::vector<HubFinishPass>> pieces;
  std::vector<std::vector<HubFinishRefusal>> refusals;
  std::vector<int> splits;
  std::vector<double> devs;
};

// Part `part` from rows first .. first + count.
void fill_part(RowsPlanned& rows, HubFinishResult& res, HubFinishPart& part, HubFinishOp op, size_t first,
               size_t count) {
  std::vector<std::vector<HubFinishPass>>& pieces = rows.pieces;
  std::vector<std::vector<HubFinishRefusal>>& refusals = rows.refusals;
  const std::vector<int>& splits = rows.splits;
  const std::vector<double>& devs = rows.devs;
  part.op = op;
  part.rows = static_cast<int>(count);
  for (size_t k = first; k < first + count; ++k) {
    for (HubFinishPass& p : pieces[k]) part.passes.push_back(std::move(p));
    for (HubFinishRefusal& f : refusals[k]) res.refusals.push_back(std::move(f)), ++part.refusals;
    part.gouge_splits += splits[k];
    part.max_deviation_mm = std::max(part.max_deviation_mm, devs[k]);
  }
  for (const HubFinishPass& p : part.passes) {
    part.poses += static_cast<int>(p.poses.size());
    for (const HubFinishPose& hp : p.poses) part.tilted += hp.tilted;
  }
  if (part.step_min_mm > 1e299) part.step_min_mm = 0;
}

}  // namespace

double plan_passes(const Planner& planner, const TiltSettings& base, const RootGeometry& root,
                   const std::vector<RootRow>& root_rows, const FloorGeometry* floor,
                   const std::vector<FloorRow>& floor_rows, HubFinishResult& res, Progress& progress) {
  const HubFinishRequest& rq = planner.rq;
  const size_t n_root = root_rows.size(), n_floor = floor_rows.size();
  RowsPlanned planned;
  std::vector<std::vector<HubFinishPass>>& pieces = planned.pieces;
  std::vector<std::vector<HubFinishRefusal>>& refusals = planned.refusals;
  std::vector<int>& splits = planned.splits;
  std::vector<double>& devs = planned.devs;
  pieces.resize(n_root + n_floor);
  refusals.resize(n_root + n_floor);
  splits.assign(n_root + n_floor, 0);
  devs.assign(n_root + n_floor, 0.0);
  auto t_rows = SteadyClock::now();
  run_parallel(n_root + n_floor, rq.threads, progress, "hub finish rows", [&](size_t k, Progress& own) {
    std::vector<Planner::Contact> contacts;
    double dev = 0;
    if (k < n_root) {
      const RootRow& row = root_rows[k];
      contacts = root_contacts(root, row, base, dev);
      planner.plan_row(HubFinishOp::Root, static_cast<int>(k), row.level, false, contacts, dev, pieces[k],
                       refusals[k], splits[k], own);
    } else {
      const size_t j = k - n_root;
      const FloorRow& fr = floor_rows[j];
      if (!(fr.theta1 > fr.theta0)) {
        refusals[k].push_back({HubFinishOp::Channel, static_cast<int>(j), Vec3(0, 0, fr.z),
                               "the ball does not fit between the blades at this z"});
        return;
      }
      contacts = floor_contacts(*floor, fr, j, base, dev);
      const bool reversed = j % 2 == 1;
      planner.plan_row(HubFinishOp::Channel, static_cast<int>(j), fr.z, reversed, contacts, dev, pieces[k],
                       refusals[k], splits[k], own);
    }
    devs[k] = dev;
  });
  // The root rows are closed loops, each planned on its own from its
  // start: where one row's last pose and the next row's first differ so
  // much that the move between them is not clear (Rotor 67's: the axis
  // turns 29-39 deg there, and the shank swings into its clearance of blade
  // k+1, so neither a step nor any link proved), the next row is planned
  // again entered from that last pose — its first axis then one the tilt
  // loop proved the move to — and taken where it refuses no more contacts.
  // In row order: a row planned again ends elsewhere.
  for (size_t k = 1; k < n_root; ++k) {
    if (pieces[k - 1].empty() || pieces[k].empty()) continue;
    const ToolPose& last = pieces[k - 1].back().poses.back().pose;
    const ToolPose& first = pieces[k].front().poses.front().pose;
    if (planner.world.check_motion(planner.body, last, first, base.clearances, base.motion_tol_mm).clear) continue;
    double dev = 0;
    const std::vector<Planner::Contact> contacts = root_contacts(root, root_rows[k], base, dev);
    std::vector<HubFinishPass> again;
    std::vector<HubFinishRefusal> again_refused;
    int again_splits = 0;
    planner.plan_row(HubFinishOp::Root, static_cast<int>(k), root_rows[k].level, false, contacts, dev, again,
                     again_refused, again_splits, progress, &last);
    if (again.empty() || again_refused.size() > refusals[k].size()) continue;
    pieces[k] = std::move(again);
    refusals[k] = std::move(again_refused);
    splits[k] = again_splits;
    ++res.root.entered_rows;
  }
  fill_part(planned, res, res.root, HubFinishOp::Root, 0, n_root);
  fill_part(planned, res, res.channel, HubFinishOp::Channel, n_root, n_floor);
  return seconds_since(t_rows);
}

}  // namespace bliskrun::hub_detail
