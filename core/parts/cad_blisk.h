#pragma once
// A blisk from CAD (issue 36 item 3): one blade's two flanks, a hub and a
// casing of revolution and a blade count. Blade k is blade 0 turned by the
// pitch 2 pi k / N about +Z, exactly: its flanks are blade 0's evaluated and
// rotated (RotatedSurface), not copies or fits. What the blisk operations
// read (blisk_part.h) comes from these: flank grids sampled on the flanks,
// hub and casing meridians sampled on their surfaces, the narrowest passage
// between blade 0's suction flank and blade 1's pressure flank.
#include <memory>
#include <string>
#include <vector>

#include "core/parts/blisk_part.h"
#include "core/parts/cad_blade.h"

namespace bliskrun {

// A blade from its two flank faces as a CAD file gives them (any
// parametrisation: span along u or v, either direction; `frame` maps the
// file's coordinates to bliskrun's as for cad_blade): each face turned so
// that u runs hub -> tip (radius increasing) and pu x pv points away from
// the other face (out of the material), by swapping and reversing its
// parameters exactly (ReorientedSurface); the convex one is the suction
// flank. `le`/`te` are not set (no closed airfoil). Throws ParameterError
// when a face is missing or the two do not face each other as a blade's
// flanks (one face's middle not over the other).
CadBlade cad_blade_from_flanks(std::shared_ptr<const Surface> a, std::shared_ptr<const Surface> b,
                               const CadBladeOptions& frame = {});

struct CadBliskOptions {
  int grid_rows = 100;  // flank_grid: points along u (span), as the built-in blisk's
  int grid_cols = 500;  // and along v (chord)
  std::string source;   // where the blade came from, for description()
};

class CadBlisk : public BliskPart {
 public:
  // `pressure` and `suction` are blade 0's flanks in bliskrun's frame and
  // orientation (blisk_part.h: u hub -> tip, the pressure flank's v leading
  // -> trailing edge, the suction flank's trailing -> leading, pu x pv out of
  // the material, the suction flank facing +theta): cad_blade's or
  // cad_blade_from_flanks' result. Throws ParameterError naming what is
  // wrong: "blade_count" outside [2, 400], "grid_rows"/"grid_cols" below 4,
  // "hub"/"casing" missing or not cutting every chordwise line of both
  // flanks (a hub that does not meet the blade; the flank must reach past
  // both), "pressure"/"suction" oriented otherwise (a blade whose suction
  // flank faces -theta turns the other way: the blisk operations' edge and
  // neighbour conventions assume +theta).
  CadBlisk(std::shared_ptr<const Surface> pressure, std::shared_ptr<const Surface> suction,
           std::shared_ptr<const SurfaceOfRevolution> hub, std::shared_ptr<const SurfaceOfRevolution> casing,
           int blade_count, CadBliskOptions options = {});

  int blade_count() const override { return n_; }
  std::shared_ptr<const Surface> flank_surface(int blade, FlankSide side) const override;
  PointGrid flank_grid(int blade, FlankSide side) const override;
  std::vector<Vec2> hub_meridian() const override { return hub_m_; }
  std::vector<Vec2> casing_meridian() const override { return casing_m_; }
  double hub_radius_at(double z_mm) const override { return hub_->radius_at(z_mm); }
  double casing_radius_at(double z_mm) const override { return casing_->radius_at(z_mm); }
  std::shared_ptr<const SurfaceOfRevolution> hub() const override { return hub_; }
  std::shared_ptr<const SurfaceOfRevolution> casing() const override { return casing_; }
  double narrowest_passage_mm() const override;
  std::string description() const override;

 private:
  std::shared_ptr<const Surface> flanks_[2];  // blade 0: pressure, suction
  std::shared_ptr<const SurfaceOfRevolution> hub_, casing_;
  int n_;
  CadBliskOptions options_;
  std::vector<Vec2> hub_m_, casing_m_;
};

// The (z, r) profile of a surface of revolution about Z, `samples` points
// along its meridian (its v = 0 line), axial position increasing.
std::vector<Vec2> meridian_of(const SurfaceOfRevolution& s, int samples = 200);

}  // namespace bliskrun
