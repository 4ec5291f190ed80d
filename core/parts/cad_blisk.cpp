#include "core/parts/cad_blisk.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/common/error.h"
#include "core/common/fixed_text.h"
#include "core/common/progress.h"
#include "core/geometry/differential.h"
#include "core/geometry/projection.h"
#include "core/geometry/reparametrised.h"

namespace bliskrun {

namespace {

double cad_blisk_axis_distance(const Vec3& p) { return std::hypot(p.x(), p.y()); }

// Unit vector of increasing theta at p (about Z).
Vec3 cad_blisk_theta_dir(const Vec3& p) { return Vec3(-p.y(), p.x(), 0).normalized(); }

// Chordwise bending of a flank (normal curvature along v, pu x pv as the
// normal) at mid-span: convex (the suction side) is the more negative.
double cad_flank_chordwise_bend(const Surface& s) {
  double bend = 0;
  for (double v : {0.3, 0.5, 0.7}) {
    const SurfaceDerivs e = s.eval(0.5, v);
    bend += normal_curvature(e, e.pv);
  }
  return bend;
}

std::string cad_blisk_mm(double x) { return short_text(x) + " mm"; }

}  // namespace

std::vector<Vec2> meridian_of(const SurfaceOfRevolution& s, int samples) {
  if (samples < 2) throw ParameterError("samples", "must be >= 2");
  const Curve& c = s.profile();
  std::vector<Vec2> zr;
  for (int k = 0; k < samples; ++k) {
    const Vec3 p = c.point(c.t_min() + (c.t_max() - c.t_min()) * k / (samples - 1));  // (z, r, 0)
    zr.emplace_back(p.x(), p.y());
  }
  if (zr.back().x() < zr.front().x()) std::reverse(zr.begin(), zr.end());
  return zr;
}

CadBlade cad_blade_from_flanks(std::shared_ptr<const Surface> a, std::shared_ptr<const Surface> b,
                               const CadBladeOptions& frame) {
  if (!a || !b) throw ParameterError("faces", "expected two flank faces, got " + std::string(a || b ? "one" : "none"));
  std::shared_ptr<const Surface> face[2] = {a, b};
  for (auto& f : face)
    if (frame.coordinates == CadCoordinates::kAxialRthetaR)
      f = std::make_shared<UnwrappedSurface>(f, frame.axial_origin_mm);
  // Span along the parameter that changes the radius most; hub -> tip.
  for (auto& f : face) {
    const double du = cad_blisk_axis_distance(f->point(1, 0.5)) - cad_blisk_axis_distance(f->point(0, 0.5));
    const double dv = cad_blisk_axis_distance(f->point(0.5, 1)) - cad_blisk_axis_distance(f->point(0.5, 0));
    const bool swap = std::abs(dv) > std::abs(du);
    f = std::make_shared<ReorientedSurface>(f, swap, (swap ? dv : du) < 0, false);
  }
  // Out of the material: away from the other face, seen from each face's
  // middle (its foot on the other face must be inside it: two flanks of one
  // blade face each other across its thickness).
  for (int k = 0; k < 2; ++k) {
    const SurfaceDerivs d = face[k]->eval(0.5, 0.5);
    const SurfaceProjection q = project_to_surface(*face[1 - k], d.p);
    if (!q.ok || q.on_boundary)
      throw ParameterError("faces", "face " + std::to_string(k + 1) + "'s middle has no foot inside face " +
                                        std::to_string(2 - k) +
                                        ": the two faces are not the flanks of one blade facing each other");
    if (d.pu.cross(d.pv).dot(q.point - d.p) > 0) face[k] = std::make_shared<ReorientedSurface>(face[k], false, false, true);
  }
  CadBlade out;
  const int suction = cad_flank_chordwise_bend(*face[0]) < cad_flank_chordwise_bend(*face[1]) ? 0 : 1;
  out.suction = face[suction];
  out.pressure = face[1 - suction];
  return out;
}

CadBlisk::CadBlisk(std::shared_ptr<const Surface> pressure, std::shared_ptr<const Surface> suction,
                   std::shared_ptr<const SurfaceOfRevolution> hub, std::shared_ptr<const SurfaceOfRevolution> casing,
                   int blade_count, CadBliskOptions options)
    : flanks_{std::move(pressure), std::move(suction)},
      hub_(std::move(hub)),
      casing_(std::move(casing)),
      n_(blade_count),
      options_(std::move(options)) {
  if (!flanks_[0]) throw ParameterError("pressure", "expected the blade's pressure flank, got none");
  if (!flanks_[1]) throw ParameterError("suction", "expected the blade's suction flank, got none");
  if (!hub_) throw ParameterError("hub", "expected the hub's meridian (a curve of revolution), got none");
  if (!casing_)
    throw ParameterError("casing", "expected the casing's meridian (the blade tip's line), got none: the blisk "
                                   "operations machine the flanks between hub and casing");
  if (n_ < 2 || n_ > 400) throw ParameterError("blade_count", "expected an integer in [2, 400], got " + std::to_string(n_));
  if (options_.grid_rows < 4) throw ParameterError("grid_rows", "expected at least 4");
  if (options_.grid_cols < 4) throw ParameterError("grid_cols", "expected at least 4");
  hub_m_ = meridian_of(*hub_);
  casing_m_ = meridian_of(*casing_);

  // Orientation (blisk_part.h): the pressure flank leading -> trailing edge
  // (z increasing along v), the suction flank back, pu x pv facing -theta on
  // the pressure flank and +theta on the suction flank.
  const char* names[2] = {"pressure", "suction"};
  for (int s = 0; s < 2; ++s) {
    const Surface& f = *flanks_[s];
    const SurfaceDerivs d = f.eval(0.5, 0.5);
    const double along = f.point(0.5, 1).z() - f.point(0.5, 0).z();
    const double facing = d.pu.cross(d.pv).normalized().dot(cad_blisk_theta_dir(d.p));
    const bool forward = s == 0 ? along > 0 : along < 0;
    const bool theta_ok = s == 0 ? facing < 0 : facing > 0;
    if (cad_blisk_axis_distance(f.point(1, 0.5)) <= cad_blisk_axis_distance(f.point(0, 0.5)))
      throw ParameterError(names[s], "expected u to run hub -> tip (radius increasing along u at mid-chord)");
    if (!forward)
      throw ParameterError(names[s], std::string("expected v to run ") +
                                         (s == 0 ? "leading -> trailing edge" : "trailing -> leading edge") +
                                         " (axial position " + (s == 0 ? "increasing" : "decreasing") +
                                         " along v at mid-span)");
    if (!theta_ok)
      throw ParameterError(names[s], std::string("its outward normal faces ") + (facing > 0 ? "+" : "-") +
                                         "theta at its middle; expected " + (s == 0 ? "-" : "+") +
                                         "theta (the suction flank facing blade 2's pressure flank at +theta: a "
                                         "blade turning the other way is not supported)");
  }
  // Hub and casing must cut every chordwise line of both flanks, the hub
  // below the casing: the operations trim each flank between them.
  for (int s = 0; s < 2; ++s)
    for (int j = 0; j <= 40; ++j) {
      const double v = j / 40.0;
      for (int which = 0; which < 2; ++which) {
        const SurfaceOfRevolution& rev = which == 0 ? *hub_ : *casing_;
        const char* name = which == 0 ? "hub" : "casing";
        double off[2];
        for (int e = 0; e < 2; ++e) {
          const Vec3 p = flanks_[s]->point(e, v);
          try {
            off[e] = cad_blisk_axis_distance(p) - rev.radius_at(p.z());
          } catch (const Error&) {
            throw ParameterError(name, "its meridian does not reach the blade's " + std::string(names[s]) +
                                           " flank at z = " + cad_blisk_mm(p.z()) + " (v = " + short_text(v) +
                                           ", u = " + std::to_string(e) + ")");
          }
        }
        if (!(off[0] < 0 && off[1] > 0))
          throw ParameterError(name, "does not meet the blade: the " + std::string(names[s]) + " flank's line v = " +
                                         short_text(v) + " runs from " + cad_blisk_mm(off[0]) + " to " + cad_blisk_mm(off[1]) +
                                         " radially off the " + name +
                                         "; expected it to start below and end above it (the flank reaching past "
                                         "hub and casing)");
      }
    }
}

std::shared_ptr<const Surface> CadBlisk::flank_surface(int blade, FlankSide side) const {
  if (blade < 0 || blade >= n_)
    throw ParameterError("blade", "expected an index in [0, " + std::to_string(n_ - 1) + "], got " + std::to_string(blade));
  const auto& f = flanks_[side == FlankSide::kPressure ? 0 : 1];
  if (blade == 0) return f;
  return std::make_shared<RotatedSurface>(f, 2 * kPi * blade / n_);
}

PointGrid CadBlisk::flank_grid(int blade, FlankSide side) const {
  const auto s = flank_surface(blade, side);
  PointGrid grid(options_.grid_rows, options_.grid_cols);
  for (int i = 0; i < grid.rows; ++i) {
    cancellation_point();
    for (int j = 0; j < grid.cols; ++j)
      grid.at(i, j) = s->point(static_cast<double>(i) / (grid.rows - 1), static_cast<double>(j) / (grid.cols - 1));
  }
  return grid;
}

double CadBlisk::narrowest_passage_mm() const {
  const Surface& suction = *flanks_[1];
  const auto next = flank_surface(1, FlankSide::kPressure);
  return narrowest_span_passage([&](double u, double v) { return suction.point(u, v); },
                                [&](double u, double v) { return next->point(u, v); },
                                [&](double z) { return hub_->radius_at(z); },
                                [&](double z) { return casing_->radius_at(z); });
}

std::string CadBlisk::description() const {
  std::ostringstream s;
  s << "bliskrun.Blisk(" << n_ << " blades from CAD" << (options_.source.empty() ? "" : " (" + options_.source + ")")
    << ", hub r " << short_text(hub_m_.front().y()) << "->" << short_text(hub_m_.back().y()) << " mm, casing r "
    << short_text(casing_m_.front().y()) << "->" << short_text(casing_m_.back().y()) << " mm, grid "
    << options_.grid_rows << "x" << options_.grid_cols << ")";
  return s.str();
}

}  // namespace bliskrun
