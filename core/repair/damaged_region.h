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
//  - a completed section (a gap, an edge nick): in its plane, the line
//    through the gap's two measured ends, the missing material on the side of
//    the design arc that filled it (a nick's floor, exact for a straight cut,
//    the chord of a rounded one). Between completed sections the ends move
//    linearly with height; beyond the first and last the nick is taken to
//    end at the neighbouring complete section, its cut area falling linearly
//    to zero there (no measured section tells where it ends). A gap the
//    probe left on an intact flank (an unseen stretch) reads as a nick of
//    the thickness of the flank's sagitta over the gap: negligible, but
//    inside the region.
//
// Thickness at a point S(u, v) of the rebuilt surface: its distance beyond the
// damage face (normal to the break plane; in the section plane from the gap
// line), 0 outside the region. Volume: the rebuilt sections' area beyond the
// damage face integrated over height (midpoint rule over `slices` slices
// through the broken tip; the nick's cut areas by the trapezoid rule over the
// sections), each area by clipping the rebuilt loft's plane section
// (plane_section) with the half-plane beyond the face.
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
  double tip_volume_mm3 = 0;
  // Edge damage: the completed sections' gaps.
  int nicked_sections = 0;
  double edge_volume_mm3 = 0;
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

// The damage face as the region uses it, for thickness at any (u, v).
class DamageFace {
 public:
  DamageFace(const DamagedRebuild& rebuilt, const SectionMeasurement& measurement, double min_gap_mm = 0.3);
  // Distance of p beyond the damage face, 0 where nothing is missing.
  double thickness(const Vec3& p) const;
  const DamagedRebuild& rebuilt() const { return rebuilt_; }

 private:
  friend DamagedRegion damaged_region(const DamagedRebuild&, const SectionMeasurement&, const DamagedRegionOptions&);
  // A measured section's damage line: ends a, b, unit normal n towards the
  // missing material, depth the rebuilt section's furthest point beyond it.
  struct Section {
    double h = 0;
    bool gap = false;
    Vec2 a = Vec2::Zero(), n = Vec2::Zero();
    double depth = 0;
  };
  const DamagedRebuild& rebuilt_;
  bool tip_ = false;
  Vec3 normal_ = Vec3::Zero();
  double offset_ = 0;
  int face_points_ = 0;
  double face_rms_ = 0;
  std::vector<Section> sections_;  // the measured sections by height, each with its largest gap
  double edge_thickness(double h, const Vec2& xy) const;
};

// Throws ParameterError naming the option out of range.
DamagedRegion damaged_region(const DamagedRebuild& rebuilt, const SectionMeasurement& measurement,
                             const DamagedRegionOptions& options = {});

// Area of the closed polygon on the side of the line n . p + c > 0 (exact, by
// clipping and the shoelace formula).
double clipped_area(const std::vector<Vec2>& polygon, const Vec2& n, double c);

}  // namespace bliskrun
