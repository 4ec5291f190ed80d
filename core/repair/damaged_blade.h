#pragma once
// A damaged blade and its simulated measurement (repair paper §3, Fig. 20:
// the CAD blade twisted, an edge region removed, sections cut and noise
// added), so the repair chain runs and is tested without a worn part.
//
// It lives in core/repair, not core/parts: it is the repair's fixture, built
// from the repair's own loft (section_loft.h), and core/parts does not depend
// on core/repair.
//
// The design blade is a closed loft through the design's section loops (the
// built-in blisk's section_loop, or a real blade's loops, BladeSections). Its
// stacking axis runs from the centroid of the first loop to that of the last;
// heights h are measured along it from the first centroid, and "span" s is h
// over the height range in which every plane normal to the axis cuts the loft
// in a complete loop, [0, 1] over [h_lo, h_hi]. In-plane coordinates (x, y)
// are along e1 (the rotor axis Z made normal to the stacking axis: chordwise,
// flow direction) and e2 = axis x e1.
//
// Damage, all in the plane of each section so that a plane section of the
// damaged blade is exact:
//  - deformation: each section above span `deform_from` turned in its plane
//    about the stacking axis by twist * w² and moved along e2 by bend * w²
//    (w: 0 at deform_from, 1 at the tip): the paper's twist, and a bend that
//    is the small-angle form of the upper span turning about an axis along
//    e1 (keeping sections in their planes, so the measurement planes cut the
//    bent blade where the design was cut);
//  - tip broken off: the material beyond the plane through the axis point at
//    span `tip_span`, its normal the axis tilted towards e1 by `tip_tilt`;
//  - leading-edge nick: over spans (edge_from, edge_to), the material within
//    depth d(s) = edge_depth sin(π (s - edge_from) / (edge_to - edge_from))
//    of the leading edge, measured along the chord (the line from the
//    section's upstream extreme, least x, to its downstream one): erosion to
//    a smooth depth profile, the nick's floor a straight line in each plane;
//  - trailing-edge nick: the same from the section's downstream extreme (most
//    x) back along the chord, over its own spans and depth;
//  - spherical nick (a dent in a flank): the material inside a sphere of
//    radius R whose surface reaches `dent_depth` below the flank — its centre
//    on the flank's outward normal, R - depth outside it, at the point of the
//    section at span `dent_span` a fraction `dent_chord` of the way from the
//    upstream extreme to the downstream one (in x), on the side of +e2
//    (`dent_side` 1) or -e2 (-1). On a flat flank it removes the spherical cap
//    π t² (3R - t) / 3 (t the depth), the region's closed form.
//
// Measurement: N planes at equal steps of span; on each, points at even steps
// of arc length along the damaged section's profile (a scanning probe), each
// moved along the profile by up to a quarter step at random, none where material
// is missing (the probe finds no surface there: a broken tip, a nick, whose
// floor the simulation leaves unmeasured so that the region must take it from
// the gap's ends) except in a dent, whose floor the probe follows as it
// follows the flank (points on the sphere's arc inside the section at the same
// steps, the noise along its radius), nor in an optional unseen
// arc (a stretch the probe cannot reach), each moved along the profile's
// normal by Gaussian noise σ; a fraction of outliers moved by 10σ (at least
// 20 um) plus up to 0.3 mm, either way; shuffled. A section left with less than half its points is not
// reported (the probe finds no section above a broken tip). Points on the
// fracture face of a broken tip ("face" points: a CMM touches it to find the
// break) are sampled on a grid inside the damaged section just below the
// break. Deterministic from the seed.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/common/types.h"
#include "core/io/blade_sections.h"
#include "core/geometry/section_loft.h"

namespace bliskrun {

class BuiltinBlisk;

// The stacking frame: a point at height h and in-plane (x, y) is
// origin + h axis + x e1 + y e2.
struct BladeFrame {
  Vec3 origin = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
  Vec3 e1 = Vec3::UnitX(), e2 = Vec3::UnitY();

  Vec3 point(double h, const Vec2& xy) const { return origin + h * axis + xy.x() * e1 + xy.y() * e2; }
  double height(const Vec3& p) const { return (p - origin).dot(axis); }
  Vec2 in_plane(const Vec3& p) const { return Vec2((p - origin).dot(e1), (p - origin).dot(e2)); }
};

// The frame for a stacking axis: e1 the rotor axis Z made normal to it (or X
// when the axis is along Z). Throws ParameterError ("axis") for a zero axis.
BladeFrame blade_frame(const Vec3& origin, const Vec3& axis);

// A closed blade surface with its stacking frame.
struct DesignBlade {
  SectionLoft loft;  // u from the first loop to the last, v around
  BladeFrame frame;
  double h_lo = 0, h_hi = 0;  // heights between which every plane cuts a complete loop
  double span_height(double s) const { return h_lo + s * (h_hi - h_lo); }
};

// The loft through closed section loops (hub -> tip, first point not
// repeated): oriented as orient_sections does, lofted at `samples` per
// section. Throws ParameterError ("loops") for fewer than 2 loops or
// sections that do not stack (no height range cut completely).
DesignBlade design_blade(const std::vector<std::vector<Vec3>>& loops, int samples = 512);
// Blade `blade` of the built-in blisk, lofted through `sections` loops at
// radii from its grid's lowest to its highest.
DesignBlade builtin_design_blade(const BuiltinBlisk& blisk, int blade = 0, int sections = 25);
// A real blade's loops (Rotor 37, 67: core/io readers).
DesignBlade design_blade(const BladeSections& blade, int samples = 512);

// The closed section of a blade loft by the plane at height h: `samples`
// points in plane coordinates, one per v = j / samples (so they follow the
// loft's v direction), by Newton on u along each v line. Throws
// ParameterError ("height") outside the loft's height range at some v.
std::vector<Vec2> plane_section(const SectionLoft& loft, const BladeFrame& frame, double h, int samples = 1024);
// The same, clamped at the loft's end rows: where the plane passes beyond the
// first or last row at some v (a loft's end section is a measured one, its
// points not exactly in one plane, so the plane at its mean height leaves it
// here and there by the noise), that row's point at v instead. For the
// damaged region at the end sections (issue 43); never throws for height.
std::vector<Vec2> clamped_plane_section(const SectionLoft& loft, const BladeFrame& frame, double h, int samples = 1024);

struct BladeDamage {
  double deform_from = 0.3;    // span where the deformation starts
  double twist_rad = 0;        // at the tip
  double bend_mm = 0;          // at the tip, along e2
  bool tip = false;
  double tip_span = 0.85;
  double tip_tilt_rad = 0;
  bool edge = false;
  double edge_from = 0.4, edge_to = 0.65;  // spans
  double edge_depth_mm = 1.0;
  bool te_edge = false;                    // trailing-edge nick
  double te_from = 0.4, te_to = 0.65;
  double te_depth_mm = 1.0;
  bool dent = false;                       // spherical nick in a flank
  double dent_span = 0.5, dent_chord = 0.5;
  int dent_side = 1;                       // +1: the flank on the side of +e2; -1: of -e2
  double dent_radius_mm = 3, dent_depth_mm = 0.5;
};

// What is missing from the damaged blade in the plane at one height (the
// nicks judged against the deformed section there): made once per plane,
// asked per point.
class MissingInPlane {
 public:
  // Beyond the tip's break or in a nick: material the probe finds no surface of.
  bool unseen(const Vec2& xy) const;
  // Inside the dent's sphere: material whose floor the probe measures.
  bool in_dent(const Vec2& xy) const { return dent_radius > 0 && (xy - dent_centre).squaredNorm() < dent_radius * dent_radius; }
  bool removed(const Vec2& xy) const { return unseen(xy) || in_dent(xy); }

  // The break plane at this height, n . xy + c > 0 beyond it (tip damage).
  bool tip = false;
  Vec2 tip_n = Vec2::Zero();
  double tip_c = 0;
  // Nicks: within `depth` of the `from` extreme along the unit `along` (a
  // negative depth: no nick at this height).
  Vec2 le = Vec2::Zero(), le_along = Vec2::Zero();
  double le_depth = -1;
  Vec2 te = Vec2::Zero(), te_along = Vec2::Zero();
  double te_depth = -1;
  // The dent's circle in this plane (radius 0: the sphere does not reach it).
  Vec2 dent_centre = Vec2::Zero();
  double dent_radius = 0;
};

// The design blade with its damage: plane sections of the damaged blade,
// and what is missing from them.
class DamagedBlade {
 public:
  // Throws ParameterError naming the damage parameter out of range.
  DamagedBlade(DesignBlade design, const BladeDamage& damage);

  const DesignBlade& design() const { return design_; }
  const BladeDamage& damage() const { return damage_; }

  // In-plane rigid motion of the section at height h (the deformation).
  Vec2 deform(double h, const Vec2& xy) const;
  // The deformed (undamaged) section at height h, in plane coordinates.
  std::vector<Vec2> deformed_section(double h, int samples = 1024) const;
  // Whether in-plane point xy at height h lies in removed material (beyond
  // the tip break, in a nick or in the dent); the nicks are judged against
  // the deformed section `section` at that height.
  bool removed(double h, const Vec2& xy, const std::vector<Vec2>& section) const;
  // The same for many points of one plane.
  MissingInPlane missing(double h, const std::vector<Vec2>& section) const;
  // The dent's sphere (damage().dent), in part coordinates.
  Vec3 dent_centre() const { return dent_centre_; }
  // The break plane (tip damage): points p with normal . p > offset are gone.
  Vec3 break_normal() const;
  double break_offset() const;

 private:
  DesignBlade design_;
  BladeDamage damage_;
  Vec3 dent_centre_ = Vec3::Zero();
};

struct MeasurementOptions {
  int sections = 30;
  double span_from = 0.03, span_to = 0.97;
  int points = 2000;               // per section, before the missing material and the unseen arc
  double noise_mm = 0.002;         // σ along the profile normal
  double outlier_fraction = 0.005;
  double unseen_arc_mm = 0;        // an arc the probe misses, centred at the section's extreme along -e2
  int face_points = 60;            // on the fracture face of a broken tip (0: none)
  std::uint64_t seed = 1;
};

struct MeasuredSection {
  int index = 0;        // 1-based section number of the measurement plan
  double height_mm = 0; // along the stacking axis
  std::vector<Vec3> points;
  int line = 0;         // read from a file: the line where the section starts (0: not read)
};

// A measurement of one blade: sections, points probed on the fracture face of
// a broken tip (possibly none), and the stacking frame.
struct SectionMeasurement {
  std::string file;  // read from a file: its name, for errors at file:line (empty: not read)
  std::string units = "mm";
  BladeFrame frame;
  bool has_frame = false;
  std::vector<MeasuredSection> sections;
  std::vector<Vec3> face;
  // The measurement plan's highest section, mm along the axis (NaN: not
  // stated). With it a broken tip is told from a plan that stops short of
  // the tip: sections of the plan missing at the top are a break, a margin
  // above the plan's top is not (damaged_rebuild.h, tip_basis).
  double planned_top_mm = std::numeric_limits<double>::quiet_NaN();
};

// Throws ParameterError naming the option out of range.
SectionMeasurement measure_sections(const DamagedBlade& blade, const MeasurementOptions& options = {});

// The measurement file (docs/architecture.md, "Section measurement files"):
//   # comments, blank lines ignored
//   units mm                       (mm or inch; inch points are converted)
//   axis ox oy oz ax ay az         (optional: the stacking frame's origin and axis)
//   section <k> <height>           then one "x y z" line per point
//   face                           then "x y z" points on a tip's fracture face
//   planned_top <height>           (optional: the plan's highest section, even
//                                   when the probe found nothing there)
// or a CMM CSV export: lines "x,y,z" or "x,y,z,section" (an optional header
// line of names first), points grouped by the section column, or — without
// one — by height along Z rounded to 1 um, which holds only for sections
// measured at constant Z (a blade stacked along Z): where that leaves sections
// of fewer than 10 points (a radially stacked blade's points each at their
// own Z), the file is refused with an error asking for the section column.
// Errors are DataError "<file>:<line>: ..." naming what was expected.
SectionMeasurement read_section_measurement(const std::string& path);
SectionMeasurement parse_section_measurement(const std::string& text, const std::string& file);
// Full precision (17 significant digits): reading it back gives the same numbers.
std::string format_section_measurement(const SectionMeasurement& m);
void write_section_measurement(const std::string& path, const SectionMeasurement& m);

}  // namespace bliskrun
