// The links between passes, in cutting order: the shared link builder
// (core/planning/links.h), up the tool axis — a bottom-cutting tool leaves
// along its axis — every leg proved against the world with the whole tool
// and, by the gouge guards, against the edge region and both flanks within
// e1 (less what the guards' samples can miss); other routes where that one
// is refused, and (zigzag) rows cut the other way or in the other order
// where that proves a refused link.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>

#include "core/common/exact_point.h"
#include "core/common/parallel.h"
#include "core/geometry/projection.h"
#include "core/planning/edge_finish/internal.h"

namespace bliskrun::edge_detail {
namespace {

// The traverse's waypoint round the edge's front, for a link between passes
// whose axes turn by more than 90 degrees (one-way rows: the passes lie on
// either side of the edge): the mean of the two normals points off the
// edge; the tool goes there at the retract distance plus its radius. None
// otherwise.
std::vector<ToolPose> round_the_front(const EdgeFinishRequest& rq, const EdgeFinishPose& a, const EdgeFinishPose& b) {
  if (a.pose.axis.dot(b.pose.axis) >= 0) return {};
  Vec3 front = a.normal + b.normal;
  if (front.norm() < 1e-6) front = a.normal.cross(b.contact - a.contact).cross(a.normal);
  front.normalize();
  return {{0.5 * (a.contact + b.contact) + (rq.retract_mm + flat_end_of(*rq.tool).radius_mm) * front, front}};
}

// Waypoints in front of the edge between two passes: the round's middle
// (u = 0.5) at the passes' mean span, out along its normal by the retract
// distance plus the tool's diameter, with the first pass's axis and then
// the second's (the axis turns there, clear of the blades).
std::vector<ToolPose> in_front(const EdgeFinishRequest& rq, const EdgeFinishPose& a, const EdgeFinishPose& b,
                               double retract_mm) {
  const EdgeFrame f = edge_frame(rq.edge->eval(0.5, 0.5 * (a.v + b.v)));
  const Vec3 at = f.point + (retract_mm + 2 * flat_end_of(*rq.tool).radius_mm) * f.z;
  return {{at, a.pose.axis}, {at, b.pose.axis}};
}

// The row cut the other way: its poses and passes in reverse.
EdgeFinishRow reversed_row(EdgeFinishRow row) {
  if (row.poses.empty()) return row;
  const int last = row.poses.back().segment;
  reverse_poses(row.poses);
  for (EdgeFinishPose& p : row.poses) p.segment = last - p.segment;
  row.reversed = !row.reversed;
  return row;
}

// The links between consecutive passes of rows[0 .. n) — standing at row
// indices r0 .. in the cutting order — the first from `prev` (the last
// pose before them, in row prev_row; null: none). prev / prev_row end at
// the rows' last pose.
struct LinkEnds {
  const EdgeFinishPose *from, *to;
  int from_row, to_row;
};
std::vector<LinkEnds> pass_links(const EdgeFinishRow* rows, size_t n, int r0, const EdgeFinishPose*& prev,
                                 int& prev_row) {
  std::vector<LinkEnds> out;
  for (size_t j = 0; j < n; ++j) {
    const std::vector<EdgeFinishPose>& poses = rows[j].poses;
    const int r = r0 + static_cast<int>(j);
    for (size_t i = 0; i < poses.size(); ++i) {
      const bool starts_pass = i == 0 || poses[i].segment != poses[i - 1].segment;
      if (starts_pass && prev) out.push_back({prev, &poses[i], prev_row, r});
      prev = &poses[i];
      prev_row = r;
    }
  }
  return out;
}

// The link builder's checks and options for the edge, and the routes it
// tries.
struct EdgeLinker {
  const EdgeFinishRequest& rq;
  const DesignGuards& guards;
  LinkChecks checks;
  LinkOptions options;

  // A link tried up the axes (round the front where the axis turns past
  // 90 deg), then out in front of the edge, then retracted three times as
  // far in front, then (with a hub) radially out.
  EdgeFinishLink link(const EdgeFinishPose& from, const EdgeFinishPose& to, int from_row, int to_row) const;
  PlannedLink radially_out(const EdgeFinishPose& from, const EdgeFinishPose& to, PlannedLink pl) const;
};

// A guard's window for own_blade_beyond_guards: its parameter rectangle
// less two sample spacings on each side inside the surface's domain (a side
// on the domain's border — a flank's edge end, the edge region's ends round
// the edge — stays), and boxes round it that a point must lie in to be
// tried: the rectangle cut in kStrips strips along u, each in kTiles tiles
// along v, each tile's box that of 5 x 5 of its points 0.1 mm wider each
// way (between them the patch bulges by microns, round Rotor 67's edge by
// ~30 um). Only a filter: a point in no box is taken as not on the patch,
// which keeps its triangles. on_mm: how near the surface a corner must lie
// to be a point of it.
struct GuardedPatch {
  static constexpr int kStrips = 64, kTiles = 16;
  const Surface* surface = nullptr;
  double u0 = 0, u1 = 1, v0 = 0, v1 = 1;
  double on_mm = 0;
  Eigen::AlignedBox3d box;                        // the strips'
  std::vector<Eigen::AlignedBox3d> strips, tiles;  // tiles[i * kTiles + j]: strip i's j-th
};

GuardedPatch guarded_patch(const DesignGuards::Window& w, double on_mm) {
  const UndercutOptions& o = w.sampling;
  const double du = 2 * (o.u1 - o.u0) / (o.samples_u - 1), dv = 2 * (o.v1 - o.v0) / (o.samples_v - 1);
  GuardedPatch g;
  g.surface = w.surface;
  g.u0 = o.u0 > 0 ? o.u0 + du : 0.0;
  g.u1 = o.u1 < 1 ? o.u1 - du : 1.0;
  g.v0 = o.v0 > 0 ? o.v0 + dv : 0.0;
  g.v1 = o.v1 < 1 ? o.v1 - dv : 1.0;
  g.on_mm = on_mm;
  const Vec3 wider = Vec3::Constant(0.1);
  for (int i = 0; i < GuardedPatch::kStrips; ++i) {
    Eigen::AlignedBox3d strip;
    for (int j = 0; j < GuardedPatch::kTiles; ++j) {
      Eigen::AlignedBox3d tile;
      for (int a = 0; a <= 4; ++a)
        for (int b = 0; b <= 4; ++b)
          tile.extend(w.surface->point(g.u0 + (g.u1 - g.u0) * (i + a / 4.0) / GuardedPatch::kStrips,
                                       g.v0 + (g.v1 - g.v0) * (j + b / 4.0) / GuardedPatch::kTiles));
      tile.min() -= wider;
      tile.max() += wider;
      g.tiles.push_back(tile);
      strip.extend(tile);
    }
    g.strips.push_back(strip);
    g.box.extend(strip);
  }
  return g;
}

// Whether p is a point of the patch: its foot on the surface, by Newton
// from the middle of the first tile whose box holds it (where Newton fails
// there, from the next), within on_mm of it and inside the patch's
// rectangle. Anything else is not the patch, and a foot Newton misses only
// keeps triangles.
bool on_patch(const GuardedPatch& g, const Vec3& p) {
  if (!g.box.contains(p)) return false;
  for (int i = 0; i < GuardedPatch::kStrips; ++i) {
    if (!g.strips[i].contains(p)) continue;
    for (int j = 0; j < GuardedPatch::kTiles; ++j) {
      if (!g.tiles[i * GuardedPatch::kTiles + j].contains(p)) continue;
      ProjectionOptions o;
      o.seed = Eigen::Vector2d(g.u0 + (g.u1 - g.u0) * (i + 0.5) / GuardedPatch::kStrips,
                               g.v0 + (g.v1 - g.v0) * (j + 0.5) / GuardedPatch::kTiles);
      o.seed_samples_u = o.seed_samples_v = 2;  // where Newton fails from the tile, no search of the whole surface
      const SurfaceProjection f = project_to_surface(*g.surface, p, o);
      if (f.ok) return f.distance <= g.on_mm && f.u >= g.u0 && f.u <= g.u1 && f.v >= g.v0 && f.v <= g.v1;
    }
  }
  return false;
}

// A flank mesh's corner is a point of its flank (tessellate: s.point(u,
// v)): within 1 nm.
constexpr double kOnFlankMm = 1e-6;
// An edge round's mesh is not a mesh of the edge region the guard samples:
// the world's round (blisk_world.edge_round: no overlap, its span up to the
// casing) and the region (the request's: the overlap onto the flanks, its
// own span) are two B-splines through one construction — at each span the
// same circle tangent to both flank ends (core/parts/edge_region.h) —
// sampled at other points. On the built-in blade the round's points lie
// within 6.9 nm of the LE's region and 7.6 nm of the TE's (41 000 points
// each), each spline within its fit deviation of the circles (the region
// 10 nm, ringing where the round meets the overlap; the round 0.7 nm). A
// corner within 0.1 um is a point of the round the guard samples; a farther
// one keeps its triangles.
constexpr double kOnRegionMm = 1e-4;

}  // namespace

// The traverse legs are proved against the cutter's own blade (the world's
// unchecked pairs) less the triangles of its meshes the design guards
// sample: beside the edge a short lift's traverse runs ~0.15 mm off the
// flank mesh the whole way, and its proof took steps of microns (Rotor 67's
// TE: 812 proofs, ~8 s of a 37 s plan); the machined edge's own round (a
// world with the rounds, blisk_world's) is what the cutter cuts, inside
// the margin of its mesh everywhere. Built once per plan.
//
// Why every point of the own blade the cutter can reach is still covered.
// Every leg of a link is swept by the design guards too (LinkChecks::guard,
// more_guards): a guard samples its surface — a flank, or the edge region
// — over its parameter window W on a grid that reaches W's sides, and
// refuses a motion that cuts below the surface anywhere in W by more than
// e1 (its samples' miss taken off the allowance) — the proof every cutting
// motion gets, and what the cutter is held to there. A triangle is dropped
// only if its three corners are points of a guarded surface (a flank
// within 1 nm; the edge region within kOnRegionMm, above) whose parameters
// lie in W less two sample spacings on each side inside the surface's
// domain: it is a chord of the patch spanned by its corners, and that patch
// lies inside the rectangle (convex), so inside W. Every point of a mesh
// outside the shrunk rectangle lies in a triangle with a corner outside it,
// which is kept — with its mesh's margin, as before. So the kept mesh and
// the windows overlap by two sample spacings, and there is no gap at W's
// borders. A traverse starts off the blade (its start is proved by the leg
// before it), so the cutter can only reach the blade's solid by crossing
// its surface: outside the shrunk windows the kept mesh refuses the motion
// before it comes within its margin; inside them the guard's samples, which
// lie on the surface, see the crossing where it begins — a guard traces its
// normal lines only search_below_mm deep, but a crossing starts at the
// surface, not below it. On the edge round the cutter is so held within e1
// of the region, within e1 + kOnRegionMm of the world's round. Every other
// triangle (the rest of the flanks, the round beyond the edge guard's span,
// the other edge's round, any other surface of the unchecked pairs) is
// kept, so a link leaving the windows (up the span, radially out near the
// hub) meets the kept mesh as it met the whole one.
std::shared_ptr<const CollisionWorld> own_blade_beyond_guards(const EdgeFinishRequest& rq,
                                                              const DesignGuards& guards) {
  const std::shared_ptr<const CollisionWorld> own = rq.world->unchecked_pairs();
  if (!own) return nullptr;
  std::vector<GuardedPatch> patches;
  if (guards.edge_window.surface) patches.push_back(guarded_patch(guards.edge_window, kOnRegionMm));
  for (const DesignGuards::Window& w : guards.flank_windows) patches.push_back(guarded_patch(w, kOnFlankMm));
  // Each corner is shared by ~6 triangles: tried once per patch.
  std::vector<std::unordered_map<Vec3, bool, ExactPointHash, ExactPointEqual>> known(patches.size());
  auto on = [&](size_t k, const Vec3& p) {
    const auto it = known[k].find(p);
    if (it != known[k].end()) return it->second;
    return known[k][p] = on_patch(patches[k], p);
  };
  return own->without_triangles([&](const Vec3& a, const Vec3& b, const Vec3& c) {
    for (size_t k = 0; k < patches.size(); ++k)
      if (on(k, a) && on(k, b) && on(k, c)) return true;
    return false;
  });
}

namespace {

EdgeLinker edge_linker(const EdgeFinishRequest& rq, const ToolBody& body, const DesignGuards& guards) {
  EdgeLinker linker{rq, guards, {}, {}};
  LinkChecks& link_checks = linker.checks;
  link_checks.world = rq.world;
  link_checks.body = &body;
  link_checks.clearances = rq.clearances;
  link_checks.motion_tol_mm = rq.motion_tol_mm;
  link_checks.guard = guards.edge.get();
  link_checks.guard_margin_mm = guards.miss_mm;
  for (const auto& g : guards.flanks) link_checks.more_guards.push_back({g.get(), guards.miss_mm});
  // A traverse out in front of the edge or up the span leaves the guards'
  // reach: proved against the blade beyond them with the cutter too (a
  // route radially out, tried for Rotor 67's TE near the hub, was found by
  // the recipe's simulation cutting 0.1 mm into a flank the guards did not
  // sample).
  link_checks.traverse_world = own_blade_beyond_guards(rq, guards);
  LinkOptions& link_options = linker.options;
  link_options.direction = RetractDirection::ToolAxis;
  link_options.retract_mm = rq.retract_mm;
  link_options.min_retract_mm = std::min(0.1, rq.retract_mm);
  link_options.allowed_overcut_mm = -rq.band.e1_mm;
  link_options.pole = rq.reach_axis;  // zero without a reach: no pole
  link_options.pole_clearance_rad = rq.pole_clearance_rad;
  return linker;
}

// The next pass reached straight from the last, cutting (issue 38 item 5:
// the built-in LE had 346 passes, 129 of one move, 1038 mm of plunges and
// 1574 mm of links against 634 mm of cutting): where the two ends are near
// (within the tool's radius), their axes within 30 degrees, the motion clear
// of the world with the whole tool, every axis on it within the machine's
// reach, and the design guards find it cutting nowhere beyond their
// allowance (e1 less their samples' miss) — the proof a cutting motion
// within a pass gets.
bool direct_link(const EdgeFinishRequest& rq, const ToolBody& body, const DesignGuards& guards,
                 const EdgeFinishPose& from, const EdgeFinishPose& to) {
  if ((to.pose.tip - from.pose.tip).norm() > flat_end_of(*rq.tool).radius_mm) return false;
  if (from.pose.axis.normalized().dot(to.pose.axis.normalized()) < std::cos(deg_to_rad(30.0))) return false;
  const PoseMotion motion(from.pose, to.pose);
  for (double t : {0.25, 0.5, 0.75})
    if (!within_reach(rq, motion.pose_at(t))) return false;
  if (!rq.world->check_motion(body, from.pose, to.pose, rq.clearances, rq.motion_tol_mm).clear) return false;
  return guards.deepest(*rq.tool, from.pose, to.pose, false) >= 0;
}

EdgeFinishLink EdgeLinker::link(const EdgeFinishPose& from, const EdgeFinishPose& to, int from_row, int to_row) const {
  const LinkChecks& link_checks = checks;
  const LinkOptions& link_options = options;
  if (direct_link(rq, *link_checks.body, guards, from, to)) {
    EdgeFinishLink link;
    link.from_row = from_row;
    link.to_row = to_row;
    link.clear = link.direct = true;
    return link;
  }
  // Near passes no cutting motion joins (a gouge break within a row, a
  // bottom <-> corner switch, the next row's start 3-5 mm from this row's
  // end with the axis turned): a short lift up both axes, across and down,
  // proved as any link is, fed — one pass (issue 38 item 5: the built-in
  // TE's 107 passes were mostly joined by 3 mm retracts, traverses and
  // plunges). The traverse is asked of the design guards first, as
  // plan_link would ask it after its world checks: on the built-in LE half
  // the lifts tried (axes turned ~60 deg) cut the round there.
  if (rq.short_lift_mm > 0 && (to.pose.tip - from.pose.tip).norm() <= 2 * flat_end_of(*rq.tool).radius_mm &&
      from.pose.axis.normalized().dot(to.pose.axis.normalized()) >= std::cos(deg_to_rad(45.0))) {
    ToolPose up_a = from.pose, up_b = to.pose;
    up_a.tip += rq.short_lift_mm * unit_axis(from.pose.axis);
    up_b.tip += rq.short_lift_mm * unit_axis(to.pose.axis);
    if (guards.deepest(*rq.tool, up_a, up_b, true) >= 0) {
      LinkOptions lift = link_options;
      lift.retract_mm = lift.min_retract_mm = rq.short_lift_mm;
      const PlannedLink pl = plan_link({from.pose, from.normal}, {to.pose, to.normal}, link_checks, lift, {});
      if (pl.clear) {
        EdgeFinishLink link;
        link.from_row = from_row;
        link.to_row = to_row;
        link.clear = link.lifted = true;
        link.moves = pl.via;
        link.legs = pl.legs;
        link.offset_mm = pl.offset_mm;
        return link;
      }
    }
  }
  PlannedLink pl = plan_link({from.pose, from.normal}, {to.pose, to.normal}, link_checks, link_options,
                             round_the_front(rq, from, to));
  if (!pl.clear) {
    // Beside the neighbouring blade a traverse between two retracted
    // poses can graze it (their shanks are both at the clearance): out in
    // front of the edge instead, turning the axis there, away from both.
    const PlannedLink out_front = plan_link({from.pose, from.normal}, {to.pose, to.normal}, link_checks,
                                            link_options, in_front(rq, from, to, rq.retract_mm));
    if (out_front.clear) pl = out_front;
    else pl.reason += "; in front of the edge: " + out_front.reason;
  }
  if (!pl.clear) {
    // Near the hub a holder turning with the axis between two retracted
    // poses can graze it by nanometres (Rotor 67's TE, 2 of 300 links):
    // retracted three times as far, in front of the edge.
    LinkOptions farther = link_options;
    farther.retract_mm = 3 * link_options.retract_mm;
    const PlannedLink far_out = plan_link({from.pose, from.normal}, {to.pose, to.normal}, link_checks, farther,
                                          in_front(rq, from, to, farther.retract_mm));
    if (far_out.clear) pl = far_out;
    else pl.reason += "; retracted " + std::to_string(farther.retract_mm) + " mm: " + far_out.reason;
  }
  if (!pl.clear && rq.hub) pl = radially_out(from, to, std::move(pl));
  EdgeFinishLink link;
  link.from_row = from_row;
  link.to_row = to_row;
  link.clear = pl.clear;
  link.moves = pl.via;
  link.legs = pl.legs;
  link.offset_mm = pl.offset_mm;
  if (!pl.clear)
    link.reason = "link from row " + std::to_string(from_row) + " to row " + std::to_string(to_row) + ": " + pl.reason;
  return link;
}

// Where an axis leans towards the blisk's axis (Rotor 67's TE near the hub:
// 0.4 of it radial inwards) the holder sits at its clearance of the hub at
// the pose, and any turn of the axis near there sweeps it inside: up the
// span first, radially out from both retracted poses, turning the axis out
// there, and back in (2 of Rotor 67's TE links). The traverse passes the
// blade beyond the guards' samples: proved by the traverse world, which
// refuses it where the cutter would touch the blade (it cut 0.1 mm into a
// flank before that proof). `pl`: the refused link, returned with the
// reasons added if no radial route proves either.
PlannedLink EdgeLinker::radially_out(const EdgeFinishPose& from, const EdgeFinishPose& to, PlannedLink pl) const {
  const LinkChecks& link_checks = checks;
  const LinkOptions& link_options = options;
  const Vec3 mid = 0.5 * (from.contact + to.contact);
  const Vec3 out_dir = Vec3(mid.x(), mid.y(), 0).normalized();
  const Vec3 up_a = from.pose.tip + rq.retract_mm * from.pose.axis.normalized();
  const Vec3 up_b = to.pose.tip + rq.retract_mm * to.pose.axis.normalized();
  for (double s : {5.0, 20.0}) {
    const PlannedLink radial =
        plan_link({from.pose, from.normal}, {to.pose, to.normal}, link_checks, link_options,
                  {{up_a + s * out_dir, from.pose.axis}, {up_b + s * out_dir, to.pose.axis}});
    if (radial.clear) {
      pl = radial;
      break;
    }
    char buf[48];
    std::snprintf(buf, sizeof buf, "; %.0f mm radially out: ", s);
    pl.reason += buf + radial.reason;
  }
  return pl;
}

// A link no route proves — into a row reached across the round near Rotor
// 67's hub, the axis turning 70-165 deg, the holder 120 mm up the tool
// sweeping inside its clearance on every route — may be provable with the
// rows either side cut the other way, or in the other order: the finished
// surface is the envelope of every pass whatever the order (each pass's
// cuts are proved on their own), and a row cut the other way makes the same
// motions reversed. `rows` put at r0 .. in place of out.rows there, kept
// (with their links, and `ends` updated) where fewer of the links touching
// them are refused.
bool rearrange_rows(const EdgeLinker& linker, std::vector<LinkEnds>& ends, EdgeFinishResult& out, size_t r0,
                    std::vector<EdgeFinishRow> rows) {
  const size_t r1 = r0 + rows.size();
  auto in_range = [&](int row) { return static_cast<size_t>(row) >= r0 && static_cast<size_t>(row) < r1; };
  size_t k0 = 0;
  while (k0 < ends.size() && !in_range(ends[k0].from_row) && !in_range(ends[k0].to_row)) ++k0;
  size_t k1 = k0;
  while (k1 < ends.size() && (in_range(ends[k1].from_row) || in_range(ends[k1].to_row))) ++k1;
  if (k0 == k1) return false;
  // The range's links in cutting order over rows rs[0 .. n) standing at
  // r0 ..: from the pass before the range, between every two passes, to
  // the pass after it.
  auto range_ends = [&](const EdgeFinishRow* rs) {
    const EdgeFinishPose* prev = in_range(ends[k0].from_row) ? nullptr : ends[k0].from;
    int prev_row = ends[k0].from_row;
    std::vector<LinkEnds> es = pass_links(rs, r1 - r0, static_cast<int>(r0), prev, prev_row);
    if (!in_range(ends[k1 - 1].to_row)) es.push_back({prev, ends[k1 - 1].to, prev_row, ends[k1 - 1].to_row});
    return es;
  };
  const std::vector<LinkEnds> tried = range_ends(rows.data());
  if (tried.size() != k1 - k0) return false;
  std::vector<EdgeFinishLink> relinked;
  for (const LinkEnds& e : tried) relinked.push_back(linker.link(*e.from, *e.to, e.from_row, e.to_row));
  auto refused = [](auto first, auto last) {
    return std::count_if(first, last, [](const EdgeFinishLink& l) { return !l.clear; });
  };
  const auto was = refused(out.links.begin() + static_cast<long>(k0), out.links.begin() + static_cast<long>(k1));
  if (refused(relinked.begin(), relinked.end()) >= was) return false;
  for (size_t j = 0; j < rows.size(); ++j) out.rows[r0 + j] = std::move(rows[j]);
  const std::vector<LinkEnds> placed = range_ends(&out.rows[r0]);  // the same ends, pointing into out.rows
  for (size_t k = k0; k < k1; ++k) {
    ends[k] = placed[k - k0];
    out.links[k] = std::move(relinked[k - k0]);
  }
  return true;
}

// Zigzag only (one-way keeps its cutting direction): for each refused link
// between two rows, either row the other way; then the two in the other
// order, each either way. Returns how many were rearranged.
int rearrange_refused(const EdgeLinker& linker, std::vector<LinkEnds>& ends, EdgeFinishResult& out) {
  int count = 0;
  auto rearranged = [&](size_t r0, std::vector<EdgeFinishRow> rows) {
    return rearrange_rows(linker, ends, out, r0, std::move(rows));
  };
  for (size_t k = 0; k < out.links.size(); ++k) {
    if (out.links[k].clear || ends[k].from_row == ends[k].to_row) continue;
    const size_t a = static_cast<size_t>(ends[k].from_row), b = static_cast<size_t>(ends[k].to_row);
    const EdgeFinishRow &ra = out.rows[a], &rb = out.rows[b];
    const bool done =
        rearranged(b, {reversed_row(rb)}) || rearranged(a, {reversed_row(ra)}) ||
        (b == a + 1 && (rearranged(a, {rb, ra}) || rearranged(a, {reversed_row(rb), ra}) ||
                        rearranged(a, {rb, reversed_row(ra)}) || rearranged(a, {reversed_row(rb), reversed_row(ra)})));
    count += done ? 1 : 0;
  }
  return count;
}

}  // namespace

// Poses in the other cutting order. A break belongs to the pair it
// separates: it moves to the pose that now comes second.
void reverse_poses(std::vector<EdgeFinishPose>& ps) {
  const size_t n = ps.size();
  std::vector<bool> breaks(n);
  for (size_t i = 0; i < n; ++i) breaks[i] = ps[i].break_before;
  std::reverse(ps.begin(), ps.end());
  for (size_t j = 0; j < n; ++j) ps[j].break_before = j > 0 && breaks[n - j];
}

void link_passes(const EdgeFinishRequest& rq, const ToolBody& body, const DesignGuards& guards, EdgeFinishResult& out,
                 Progress& progress) {
  const EdgeLinker linker = edge_linker(rq, body, guards);
  // The passes' ends in cutting order, then every link on rq.threads
  // workers: each is proved on its own (the world and the guards are
  // read-only), so the plan does not depend on the thread count.
  const EdgeFinishPose* before_first = nullptr;
  int before_row = -1;
  std::vector<LinkEnds> ends = pass_links(out.rows.data(), out.rows.size(), 0, before_first, before_row);
  out.links.resize(ends.size());
  run_parallel(ends.size(), rq.threads, progress, "edge finish links", [&](size_t k, Progress&) {
    out.links[k] = linker.link(*ends[k].from, *ends[k].to, ends[k].from_row, ends[k].to_row);
  });
  if (rq.zigzag) out.rearranged_rows += rearrange_refused(linker, ends, out);
  for (const EdgeFinishLink& link : out.links) out.refused_links += link.clear ? 0 : 1;
  const EdgeFinishPose* first = nullptr;
  const EdgeFinishPose* last = nullptr;
  for (const EdgeFinishRow& row : out.rows)
    if (!row.poses.empty()) {
      if (!first) first = &row.poses.front();
      last = &row.poses.back();
    }
  if (first) {
    auto departure = [&](const EdgeFinishPose& p, const char* what) {
      PlannedDeparture d = plan_departure({p.pose, p.normal}, linker.checks, linker.options);
      if (!d.clear) {
        d.reason = std::string(what) + ": " + d.reason;
        ++out.refused_links;
      }
      return d;
    };
    out.lead_in = departure(*first, "lead-in");
    out.lead_out = departure(*last, "lead-out");
  }
}

}  // namespace bliskrun::edge_detail
