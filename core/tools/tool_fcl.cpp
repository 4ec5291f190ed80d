#include "core/tools/tool_fcl.h"

#include <algorithm>
#include <cmath>

#include <fcl/fcl.h>

#include "core/common/error.h"

namespace bliskrun {

RevolvedPolytope circumscribed_polytope(const Profile& profile, double tol_mm) {
  if (!(tol_mm > 0) || !std::isfinite(tol_mm)) {
    throw ParameterError("tol_mm", "tessellation tolerance must be a positive length");
  }
  const std::vector<Vec2> polyline = profile.circumscribed_polyline(tol_mm);
  double r_max = 0;
  for (const Vec2& p : polyline) r_max = std::max(r_max, p.x());
  // N-gon whose inscribed circle is the ring: corners at r / cos(pi/N).
  const double half_step = std::acos(1.0 / (1.0 + tol_mm / r_max));
  const int n = std::max(8, static_cast<int>(std::ceil(kPi / half_step)));
  const double scale = 1.0 / std::cos(kPi / n);
  // Long straight sides (a 96 mm shank) would give sliver faces a few
  // hundredths wide and 100 mm long, which bound badly in FCL's hierarchy
  // and make every query near the part slow: cut them into pieces at most
  // eight ring edges long (same solid, more but well-shaped faces).
  const double max_piece = 8 * 2 * kPi * r_max / n;
  std::vector<Vec2> meridian;
  for (size_t i = 0; i < polyline.size(); ++i) {
    if (i > 0) {
      const Vec2 a = polyline[i - 1], b = polyline[i];
      const int pieces = std::min(1000, static_cast<int>(std::ceil((b - a).norm() / max_piece)));
      for (int k = 1; k < pieces; ++k) meridian.push_back(a + (b - a) * (static_cast<double>(k) / pieces));
    }
    meridian.push_back(polyline[i]);
  }

  RevolvedPolytope poly;
  poly.overestimate_mm = tol_mm + (r_max * scale - r_max);
  std::vector<int> ring_start;  // first vertex of each ring; an apex is one vertex
  std::vector<bool> apex;
  for (const Vec2& p : meridian) {
    ring_start.push_back(static_cast<int>(poly.vertices.size()));
    const bool on_axis = p.x() < 1e-12;
    apex.push_back(on_axis);
    if (on_axis) {
      poly.vertices.emplace_back(0, 0, p.y());
      continue;
    }
    for (int j = 0; j < n; ++j) {
      const double a = 2 * kPi * j / n;
      poly.vertices.emplace_back(p.x() * scale * std::cos(a), p.x() * scale * std::sin(a), p.y());
    }
  }
  auto vid = [&](size_t ring, int j) { return apex[ring] ? ring_start[ring] : ring_start[ring] + (j % n); };
  for (size_t i = 0; i + 1 < meridian.size(); ++i) {
    for (int j = 0; j < n; ++j) {
      // The chain runs up the outside and j runs counter-clockwise about z,
      // so (i,j) (i,j+1) (i+1,j+1) (i+1,j) is counter-clockwise from outside.
      const int a = vid(i, j), b = vid(i, j + 1), c = vid(i + 1, j + 1), d = vid(i + 1, j);
      if (apex[i] && apex[i + 1]) continue;
      if (apex[i]) {
        poly.faces.push_back({a, c, d});
      } else if (apex[i + 1]) {
        poly.faces.push_back({a, b, c});
      } else {
        poly.faces.push_back({a, b, c, d});
      }
    }
  }
  return poly;
}

constexpr double kShankTolMm = 0.02;

namespace {

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> bvh_of(const RevolvedPolytope& poly) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel();
  for (const auto& f : poly.faces) {
    for (size_t k = 1; k + 1 < f.size(); ++k) {
      model->addTriangle(poly.vertices[f[0]], poly.vertices[f[k]], poly.vertices[f[k + 1]]);
    }
  }
  model->endModel();
  model->computeLocalAABB();
  return model;
}

FclPiece fcl_piece(const Profile& profile, double tol_mm, double& overestimate_mm) {
  const RevolvedPolytope poly = circumscribed_polytope(profile, tol_mm);
  overestimate_mm = std::max(overestimate_mm, poly.overestimate_mm);
  FclPiece piece;
  piece.z_max = profile.z_max();
  piece.overestimate_mm = poly.overestimate_mm;
  piece.geometry = bvh_of(poly);
  if (tol_mm < kCoarsePieceTolMm) {
    // The reach below stays the fine body's: a motion proof bounds how fast
    // the part's points move, and any body enclosing the part gives a lower
    // bound of its distance.
    const RevolvedPolytope coarse = circumscribed_polytope(profile, kCoarsePieceTolMm);
    piece.coarse = bvh_of(coarse);
    piece.coarse_overestimate_mm = coarse.overestimate_mm;
  }
  for (const Vec3& v : poly.vertices) piece.reach_mm = std::max(piece.reach_mm, v.norm());
  piece.cover = sphere_cover(profile, kCoverExcessMm, tol_mm);
  return piece;
}

}  // namespace

double FclToolPart::overestimate_at(double z) const {
  for (const FclPiece& piece : pieces)
    if (z <= piece.z_max) return piece.overestimate_mm;
  return pieces.empty() ? overestimate_mm : pieces.back().overestimate_mm;
}

std::vector<FclToolPart> fcl_parts(const Tool& tool, double tol_mm) {
  std::vector<FclToolPart> parts;
  for (int i = 0; i < kToolPartCount; ++i) {
    const auto id = static_cast<ToolPartId>(i);
    if (!tool.has(id)) continue;
    // The shank and holder keep clearances of tenths of a millimetre: a
    // coarser body (at most 0.02 mm larger) keeps their queries cheap where
    // they run close along a blade.
    const double part_tol = id == ToolPartId::Cutter ? tol_mm : std::max(tol_mm, kShankTolMm);
    const Profile& profile = tool.profile(id);
    FclToolPart part;
    part.id = id;
    const double height = profile.z_max() - profile.z_min();
    if (id == ToolPartId::Cutter && height > 4 * profile.max_radius()) {
      const auto [bottom, top] = profile.split_at(profile.z_min() + 2 * profile.max_radius());
      part.pieces.push_back(fcl_piece(bottom, part_tol, part.overestimate_mm));
      // The top piece is meshed coarser (kFluteTopTolMm): it runs along
      // faces with stock or neighbours, never along a surface a check lets
      // it touch to the micrometre, and a long finely meshed flute parallel
      // to a blade face made each query the impeller job's largest cost
      // (planning the right channel and one face: 21-22 s CPU at 1 um,
      // 10-12 s at 0.05 mm).
      part.pieces.push_back(fcl_piece(top, std::max(part_tol, kFluteTopTolMm), part.overestimate_mm));
    } else {
      part.pieces.push_back(fcl_piece(profile, part_tol, part.overestimate_mm));
    }
    for (const FclPiece& piece : part.pieces) part.reach_mm = std::max(part.reach_mm, piece.reach_mm);
    parts.push_back(std::move(part));
  }
  return parts;
}

}  // namespace bliskrun
