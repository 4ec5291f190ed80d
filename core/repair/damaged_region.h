#pragma once
// The damaged region (repair paper §1.5): the material the damage took, which
// the repair deposits and then machines back to the rebuilt blade
// (damaged_rebuild.h) — its extent on the rebuilt surface, its volume, its
// thickness at each (u, v), and offset layers of the surface over it.
//
// The damage face — the surface the damage left, on which material is
// deposited — is taken from the measurement:
//  - a broken tip: the plane fitted (least squares) to the points probed on
//    the fracture face; without them the plane normal to the stacking axis
//    through the highest measured section (the paper: the surface above the
//    highest measured section);
//  - a completed section's gaps (edge nicks, several per section if so): in
//    its plane, for each gap the line through the damage's two edges (half a
//    probe step beyond the gap's measured ends, damaged_rebuild.h), the
//    missing material everything beyond it on the side of the design arc
//    that filled it (a nick's floor, exact for a straight cut, the chord of a
//    rounded one);
//  - a completed section's dents (damage whose floor the probe measured,
//    damaged_rebuild.h): the measured floor itself, the missing material
//    between it and the rebuilt section outwards (the strip from the floor
//    out along the normal of the line through its ends).
// Every gap and dent is kept. Damage of neighbouring sections is paired when
// the stretches of the rebuilt section (v intervals) it spans overlap — two
// nicks at one height stay two — and between a pair its floor moves with
// height along a cubic through the pair and their partners below and above
// (Catmull-Rom, each floor resampled at the same fractions of its length;
// linear towards a chain's end): a nick's depth, a dent's width curve with
// height, and a line between sections took 1 % off either (issue 43).
// Damage with no partner on one side ends between its section and the
// neighbouring one: where its depth, extrapolated linearly from its partner
// on the other side, reaches zero (a nick's depth runs out to its end so,
// issue 43), or at the neighbour when it has no partner or the line does not
// reach zero before it; its floor moves out along the normal by its depth on
// the way, so the cut area falls to zero there.
//  - a gap whose design arc stands off the line through its ends by less
//    than the section's probe spacing is not damage: an intact stretch the
//    probe skipped (an unseen arc on a flank) bridges by its sagitta g²/8R,
//    microns, while a nick's arc goes round the edge it took. (Without this
//    a skipped stretch of a concave flank, whose arc's side is the blade's
//    inside, made a region of the whole blade, issue 43.)
//
// The missing material at a height is the part of the rebuilt section on
// the missing side of any of these (the tip's plane cuts each section in a
// half-plane; each gap a half-plane, each dent a polygon): tip and edge
// damage where they meet are one region, counted once.
//
// Thickness at a point S of the rebuilt surface: the length of missing
// material along the surface's inward normal from S — to where the ray
// leaves every cut it started in, or the blade's other side, which comes
// first (in the plane of S's section: the deposit a repair builds up at S).
// Volume: the missing area of the rebuilt sections integrated over height,
// by the midpoint rule over `slices` slices spread over the heights where
// anything is missing; each area is the rebuilt loft's plane section
// (clamped at the loft's end rows) inside the union of the cuts, exact for
// the polygons (Green's theorem over the pieces of each boundary inside the
// others).
//
// Offset layers: the rebuilt surface moved outwards along its normal by k
// layer thicknesses, k = 1..layers, at the samples inside the region — the
// stock the toolpaths of §2 remove, roughing outside, finishing inside.
#include <vector>

#include "core/common/types.h"
#include "core/repair/damaged_rebuild.h"

namespace bliskrun {

struct DamagedRegionOptions {
  int samples_u = 150;       // thickness map over the rebuilt surface
  int samples_v = 1200;
  int slices = 200;          // through a broken tip, for the volume
  int section_samples = 1024;
  double layer_mm = 0.2;     // offset layer thickness
  int layers = 3;
  double min_gap_mm = 0.3;   // shorter gaps (a rejected stray's hole) are not damage
};

struct OffsetLayer {
  double offset_mm = 0;
  std::vector<Vec3> points;  // over the region's samples, row by row
  std::vector<Vec2> uv;      // their (u, v) on the rebuilt surface
};

struct DamagedRegion {
  bool empty = true;
  // Broken tip.
  bool tip = false;
  Vec3 break_normal = Vec3::Zero();
  double break_offset = 0;   // points p with break_normal . p > break_offset are missing
  int face_points = 0;       // fitted to (0: the plane through the highest section)
  double face_rms_mm = 0;
  double tip_volume_mm3 = 0;  // beyond the break plane alone
  // Edge damage: the completed sections' gaps and dents.
  int nicked_sections = 0;
  int nicks = 0;              // gaps and dents kept as damage, over all sections
  int dents = 0;              // of which dents
  int skipped_gaps = 0;       // gaps not damage: shorter than min_gap, or an intact stretch (sagitta below spacing)
  double edge_volume_mm3 = 0; // what the edge damage adds to the tip's (volume - tip_volume)
  // Extent on the rebuilt surface (v_from > v_to: the range wraps through v = 0).
  double u_from = 0, u_to = 0, v_from = 0, v_to = 0;
  double height_from_mm = 0, height_to_mm = 0;
  double volume_mm3 = 0;
  double max_thickness_mm = 0;
  double area_mm2 = 0;       // of the rebuilt surface inside the region
  // Thickness (mm) at u = i / (map_u - 1), v = j / map_v: map[i * map_v + j].
  std::vector<double> thickness_map;
  int map_u = 0, map_v = 0;
  std::vector<OffsetLayer> layers;
};

// The damage face as the region uses it (header), for the cuts at any height.
class DamageFace {
 public:
  DamageFace(const DamagedRebuild& rebuilt, const SectionMeasurement& measurement, double min_gap_mm = 0.3);
  // The missing side of the face at height h, in the section's plane: the
  // tip's half-plane tip_n . xy + tip_c > 0 (unit tip_n) when there is one,
  // and one closed polygon per edge damage reaching h (counter-clockwise;
  // a gap's half-plane as a quadrilateral reaching `reach_mm` beyond its
  // edges, a dent's strip as far out).
  struct Cuts {
    bool tip = false;
    Vec2 tip_n = Vec2::Zero();
    double tip_c = 0;
    std::vector<std::vector<Vec2>> polygons;
  };
  Cuts cuts(double h, double reach_mm = 1e3) const;
  const DamagedRebuild& rebuilt() const { return rebuilt_; }
  bool has_tip() const { return tip_; }
  Vec3 break_normal() const { return normal_; }
  double break_offset() const { return offset_; }

 private:
  friend DamagedRegion damaged_region(const DamagedRebuild&, const SectionMeasurement&, const DamagedRegionOptions&);
  // A gap's or dent's floor at one measured section: from the damage's edge
  // a to its edge b (a gap: those two), n the unit normal of the line a -> b
  // towards the missing material, depth how far the floor moves along n to
  // leave the rebuilt section, and the stretch of the rebuilt section it
  // spans (v from v0 forward to v1).
  struct Damage {
    std::vector<Vec2> floor;
    Vec2 n = Vec2::Zero();
    bool half_plane = true;  // a gap: everything beyond the line; a dent: the strip out from its floor
    double depth = 0;
    double v0 = 0, v1 = 0;
    int partner_up = -1;       // the damage of the section above it is paired with, or -1
    int partner_down = -1;     // ... of the section below
    double end_up = 0, end_down = 0;  // unpaired: the heights where it ends (header)
  };
  struct Section {
    double h = 0;
    std::vector<Damage> damages;
  };
  int skipped_ = 0;
  const DamagedRebuild& rebuilt_;
  bool tip_ = false;
  Vec3 normal_ = Vec3::Zero();
  double offset_ = 0;
  int face_points_ = 0;
  double face_rms_ = 0;
  std::vector<Section> sections_;  // the measured sections by height, with their damage
};

// The thickness at p of the rebuilt surface (outward unit normal `outward`)
// along the normal (header); `section` caches the rebuilt section at p's
// height for a row of samples (empty: computed here).
double normal_thickness(const DamageFace& face, const Vec3& p, const Vec3& outward, std::vector<Vec2>& section,
                        int section_samples = 1024);

// Throws ParameterError naming the option out of range.
DamagedRegion damaged_region(const DamagedRebuild& rebuilt, const SectionMeasurement& measurement,
                             const DamagedRegionOptions& options = {});

// Area of the closed polygon on the side of the line n . p + c > 0 (exact, by
// clipping and the shoelace formula).
double clipped_area(const std::vector<Vec2>& polygon, const Vec2& n, double c);

// Area of the part of the closed polygon `polygon` inside the union of the
// closed polygons `cuts` (each simple, either orientation; in general
// position: no edge of one lying along an edge of another): exact for
// polygons, by Green's theorem over the pieces of each boundary that lie
// inside the others (the region's volume, header).
double area_inside(const std::vector<Vec2>& polygon, const std::vector<std::vector<Vec2>>& cuts);

}  // namespace bliskrun
