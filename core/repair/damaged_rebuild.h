#pragma once
// A damaged blade rebuilt from its measured sections and its design (repair
// paper §1.4): the blade as it is — twisted, bent — made complete where
// material is missing, for the damaged region (damaged_region.h) and the
// repair toolpaths.
//
// Every section is ordered (section_points.h). A section with gaps (edge
// damage, or a stretch the probe could not reach) is completed from the
// design: the design's plane section at its height is registered to the
// section's measured points by 2-D ICP in the plane (register_section,
// point-to-line), and the registered design's arc across each gap is put in
// the gap. The paper (§1.4.1) registers the section of a first loft through
// the complete sections instead; the design is used here because the
// missing stretch — a nicked leading edge — is where a loft between distant
// complete sections is least like the blade, and the registered design is
// the blade there when the damage is a rigid in-plane motion of the section
// (twist, bend), as the test asserts.
// Where the probe found no surface (a gap), the damage's edges are taken
// half a probe step beyond the gap's two measured ends along the design arc:
// the probe's next point, the first it found no surface at, lay a step on,
// so the edge lies between on average half way (taking the ends themselves
// put every nick's floor half a step too deep: +4.5 % on a 1.2 mm nick
// probed every 0.08 mm, issue 43). A point the ordering rejected beside a
// gap's end (with neighbours on one side only its stray test doubts it)
// that lies on the registered design within three times the registration's
// RMS (the noise; a stray stands off by more) is surface, and the end moves
// over it first.
// A dent — damage whose floor the probe followed, so the section has no gap
// — is found against the design registered to every section: a run of
// measured points lying inside it deeper than `dent_depth` (over at least
// `min_dent` of the profile, extended both ways to where the points come
// back within three times the registration's RMS, the noise) is the dent's
// floor. Those points are taken out of the section, which is completed
// across them as across a gap, and kept as the floor for the damaged region
// (damaged_region.h). The depth must stand above the blade's own difference
// from its design (form tolerance, wear) for this to hold; 0 turns it off.
// A broken tip (the heights above the last measured section up to the
// design's tip) is extended by design sections moved by the in-plane motion
// extrapolated from the registrations of the top measured sections: a
// least-squares quadratic in height of the angle and shift over the top six
// (a line over fewer than four). The paper extends its first loft and
// registers the design section to that extension (§1.4.2); extrapolating the
// registrations is the same with the extrapolation made explicit, and exact
// for a deformation quadratic in height.
// Then all sections — measured, completed, extended — are oriented, smoothed,
// start-aligned and lofted as rebuild_blade does (rebuild.h), and the kept
// measured points are measured against the loft.
//
// The rebuild checks itself between the sections (issue 43). The measured
// points' deviation is taken at the sections, where the loft passes through
// them by construction, so it cannot see a loft that is wrong between them —
// which is what a wrong start alignment makes: a section whose start jumped
// along its profile shears the loft on both sides of it (seen: 1.6 um mean
// deviation at the sections, 366 um off the truth between them). So midway
// between every two neighbouring loft sections the loft's plane section is
// compared with the design's plane section at that height registered to it
// (in-plane ICP, as above): where the blade is the design moved in its planes
// (twist, bend) the two agree to the loft's interpolation error, a few um,
// and a sheared loft does not. The largest distance of the loft's section
// from the registered design is the "between-section deviation". Above the
// tolerance, the rebuild is tried again with every section started where the
// registered design's v = 0 lands on it (the design fixes the correspondence
// the curvature profiles could not); if that too is above the tolerance the
// rebuild is returned marked untrusted with a message saying where and by how
// much, for the caller to fail the run after its report. The check assumes
// the blade is the design moved in its planes except where damaged: a blade
// worn all over differs from its design by the wear, and the tolerance must
// then allow for it.
#include <limits>
#include <string>
#include <vector>

#include "core/common/types.h"
#include "core/repair/damaged_blade.h"
#include "core/repair/rebuild.h"

namespace bliskrun {

// In-plane rigid motion p -> R(angle) p + shift.
struct Rigid2 {
  double angle_rad = 0;
  Vec2 shift = Vec2::Zero();
  Vec2 apply(const Vec2& p) const;
};

struct SectionRegistrationOptions {
  int max_iterations = 60;
  double initial_reach_mm = 2;  // pairs farther apart are ignored at first
  double outlier_factor = 3;    // later: this times the median pair distance...
  double min_reach_mm = 0.02;   // ... but never below this
  double converged_mm = 1e-8;   // stop when an update moves no point more than this
};

struct SectionRegistration {
  Rigid2 motion;         // model -> measured
  int iterations = 0;
  bool converged = false;
  int inliers = 0;
  double rms_mm = 0;     // point-to-line distance of the inliers
};

// Registers a closed model polygon (dense, in order) to measured points in
// the same plane: the motion of the model that minimises the sum of squared
// distances of the measured points from the moved model's lines (each point
// paired with its nearest model vertex, the line through it along the
// polygon), pairs beyond the reach dropped as in register_points
// (core/geometry/registration.h, whose 6-DOF problem a planar section leaves
// singular). Throws ParameterError ("model") for fewer than 8 model points,
// ("points") for fewer than 3, Error if no pair is within reach or the pairs
// do not fix the rotation.
SectionRegistration register_section(const std::vector<Vec2>& points, const std::vector<Vec2>& model,
                                     const SectionRegistrationOptions& options = {}, const Rigid2& initial = {});

struct DamagedRebuildOptions {
  RebuildOptions rebuild;  // ordering, smoothing, start alignment, loft (its axis is ignored: the design's)
  int design_samples = 1024;  // points of a design plane section
  SectionRegistrationOptions registration;
  // The largest between-section deviation (above) of a trusted rebuild, mm.
  double between_tolerance_mm = 0.010;
  // A wrong start put in on purpose (tests: a rebuild made wrong must fail,
  // or be repaired by the retry): after the first `forced_start_attempts`
  // alignments, the section at this loft index (bottom = 0) is re-started
  // this far along its profile. -1: none.
  int forced_start_section = -1;
  double forced_start_shift_mm = 0;
  int forced_start_attempts = 2;
  // Dents (header): measured points this far inside the registered design,
  // over at least min_dent of the profile (0: no dents looked for).
  double dent_depth_mm = 0.05;
  double min_dent_mm = 0.3;
  // The measurement plan's highest section, mm along the axis, when the
  // measurement does not state it (SectionMeasurement::planned_top_mm, which
  // wins). NaN: not stated (the tip's state is then judged by the margins).
  double planned_top_mm = std::numeric_limits<double>::quiet_NaN();
};

enum class SectionSource { measured, completed, extended };

struct DamagedSection {
  double height_mm = 0;
  SectionSource source = SectionSource::measured;
  int index = 0;           // the measurement's section number (0 for an extended one)
  int thinned = 0;         // measured points the thinning dropped (RebuildOptions::thin_above)
  int kept = 0;            // measured points used
  int rejected = 0;
  int gaps = 0;
  double gap_mm = 0;       // total length of the gaps
  int dents = 0;           // dents found (header), their floors taken out
  bool registered = false; // the design was registered here (or, extended, moved by the extrapolation)
  Rigid2 motion;           // design -> as-is
  double registration_rms_mm = 0;
  double smoothing_shift_mm = 0;
  double start_correlation = 0;
};

// A gap or a dent of a completed section: its two ends (measured points)
// and the middle of the design arc put in, in the plane's coordinates. A
// gap's floor is the line through its edges (half a probe step beyond the
// ends, header), the material beyond it on the arc's side what the damage
// took; a dent's floor is its measured points (damaged_region.h).
struct SectionGapFill {
  double height_mm = 0;
  Vec2 end_a = Vec2::Zero(), end_b = Vec2::Zero(), arc_middle = Vec2::Zero();
  Vec2 edge_a = Vec2::Zero(), edge_b = Vec2::Zero();  // the damage's edges (a dent: its ends)
  std::vector<Vec2> floor;   // a dent's floor as measured, from end_a's side to end_b's; empty for a gap
  double length_mm = 0;      // of the gap, or of the dent along its floor
  double sagitta_mm = 0;     // largest distance of the arc put in from the line through the ends
  double spacing_mm = 0;     // the section's probe spacing
  double dent_depth_mm = 0;  // a dent's deepest point inside the registered design
  int confirmed = 0;         // points the ordering rejected inside the gap that lie on the design (header)
  // Every stretch the probe left unseen between those points (and the
  // gap's ends) has a design arc standing off its chord by less than a probe
  // step: surface measured all across, only doubted by the ordering. Not
  // damage; the region skips it (issue 43, 800 points a section: 10 and 24
  // doubted points at an intact edge made "nicks" of 143 and 2.8 mm3).
  bool bridged = false;
};

// Midway between two neighbouring loft sections: the loft's plane section
// against the design's registered to it.
struct BetweenSectionCheck {
  double height_mm = 0;
  double max_mm = 0;  // largest distance of the loft's section from the registered design
  double rms_mm = 0;
};

struct RebuildQuality {
  bool trusted = false;
  std::string start_method;  // of the rebuild returned: "curvature" (§1.3) or "design" (the retry)
  int attempts = 0;
  double tolerance_mm = 0;
  double between_max_mm = 0;  // the worst check of the rebuild returned...
  double between_at_mm = 0;   // ... and its height
  double least_correlation = 1;  // least start correlation of the curvature alignment (non-extended sections)
  std::vector<double> attempt_max_mm;  // between_max_mm of each attempt, in order
  std::vector<BetweenSectionCheck> between;  // of the rebuild returned, bottom to top
  std::string message;  // why it is not trusted (empty when it is)
};

struct DamagedRebuild {
  SectionLoft loft;
  BladeFrame frame;
  LoftDeviation deviation;  // of the kept measured points
  std::vector<PointDeviation> point_deviations;  // each of them, in section order
  std::vector<DamagedSection> sections;  // bottom to top, one per loft section
  std::vector<SectionGapFill> fills;
  double top_measured_mm = 0;  // height of the highest measured section
  // Broken tip or not (issue 43): the design is extended above the highest
  // measured section only when the measurement shows material missing there —
  //  - the plan's top stated: the highest measured section lies more than
  //    half a section step below it (sections of the plan found nothing);
  //  - not stated: the band left above the highest section is wider than
  //    the one below the lowest by more than 1.5 section steps (a plan's
  //    margins taken as alike at both ends; a break smaller than that cannot
  //    be told from sections alone — state the plan to be sure).
  // A fixed multiple of the section step alone read a dense measurement's
  // ordinary margin (3 % of span at 100 sections) as a broken tip.
  bool tip_extended = false;
  std::string tip_basis;  // the reason, in words, with the heights
  RebuildQuality quality;
};

// The check midway between sections (header): the loft's plane section at
// height h (`samples` points) against the design's registered to it. Throws
// what plane_section and register_section throw.
BetweenSectionCheck check_between(const SectionLoft& loft, const DesignBlade& design, double h, int samples,
                                  const SectionRegistrationOptions& registration = {});

// Throws ParameterError ("sections") for fewer than 2 measured sections or
// one outside the design's height range, and what the stages throw. A rebuild
// that fails its own check is returned with quality.trusted false, not thrown:
// the caller reports it, then fails.
DamagedRebuild rebuild_damaged(const SectionMeasurement& measurement, const DesignBlade& design,
                               const DamagedRebuildOptions& options = {});

}  // namespace bliskrun
