#pragma once
// What the blisk operations read from a blisk, whoever built it: the
// built-in parametric blisk (builtin_blisk.h) or one from CAD (cad_blisk.h).
// The Lua Blisk (bliskrun.blisk{}, bliskrun.cad_blisk{}) is this interface,
// and scripts/lib/blisk_world.lua, blisk_finish.lua and job/blisk_ops.lua
// read nothing else: blade count, the flanks of blade k (surface and grid),
// hub and casing, the narrowest passage.
//
// Frame: Z the rotor axis; blade k (0-based) is blade 0 turned by
// 2 pi k / N about +Z. Flanks: u hub -> tip (past both), v along the chord,
// the pressure flank leading -> trailing edge, the suction flank trailing ->
// leading edge, pu x pv out of the material on both; the suction flank faces
// +theta, towards blade k + 1's pressure flank.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/point_grid.h"
#include "core/geometry/revolution.h"
#include "core/geometry/surface.h"

namespace bliskrun {

enum class FlankSide { kPressure, kSuction };

class BliskPart {
 public:
  virtual ~BliskPart() = default;

  virtual int blade_count() const = 0;
  // Blade index 0..N-1; throws ParameterError ("blade") outside.
  virtual std::shared_ptr<const Surface> flank_surface(int blade, FlankSide side) const = 0;
  // The flank sampled on its grid (rows along u, cols along v, at
  // u = i/(rows-1), v = j/(cols-1)), as a CAM user extracts it.
  virtual PointGrid flank_grid(int blade, FlankSide side) const = 0;
  // Meridian lines (z, r), axial position increasing.
  virtual std::vector<Vec2> hub_meridian() const = 0;
  virtual std::vector<Vec2> casing_meridian() const = 0;
  virtual double hub_radius_at(double z_mm) const = 0;
  virtual double casing_radius_at(double z_mm) const = 0;
  // Hub and casing as surfaces of revolution about Z.
  virtual std::shared_ptr<const SurfaceOfRevolution> hub() const = 0;
  virtual std::shared_ptr<const SurfaceOfRevolution> casing() const = 0;
  // Minimum distance between blade 0's suction flank and blade 1's pressure
  // flank between hub and casing (narrowest_span_passage).
  virtual double narrowest_passage_mm() const = 0;
  // One line for tostring and reports.
  virtual std::string description() const = 0;
};

// Minimum distance between a suction flank and the facing pressure flank
// over the points of both between hub and casing. Each flank is
// reparametrised over the span as (w, v) in [0, 1]^2 (w = 0 where the iso-v
// line meets the hub, 1 where it meets the casing: each iso-v line of both
// flanks must cross both, hub below casing), sampled 40 x 160; the closest
// sample pairs (brute force) are refined by alternating constrained point
// inversion until the distance stops decreasing (1e-12 mm). `suction` and
// `pressure` evaluate the flanks' points (u, v) -> mm.
using FlankPoint = std::function<Vec3(double u, double v)>;
using MeridianRadius = std::function<double(double z_mm)>;
double narrowest_span_passage(const FlankPoint& suction, const FlankPoint& pressure, const MeridianRadius& hub,
                              const MeridianRadius& casing);

}  // namespace bliskrun
