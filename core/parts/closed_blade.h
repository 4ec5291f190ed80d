#pragma once
// A blade's whole side surface, closed around its section: the pressure and
// suction flank faces joined by their edge rounds and lofted as one surface
// periodic around the section (repair paper §2.2 plans the tip's spiral on
// such a surface: its tool path goes once around the blade per turn).
//
// The flank faces are the ones a CAD user extracts (the built-in blisk's,
// core/parts/builtin_blisk.h; a blade model's): u along the span, v along
// the chord, the pressure face LE -> TE and the suction face TE -> LE, both
// normals pu x pv out of the material. Where the faces leave the edge
// circles out, each section u is closed by a half circle at either edge
// through the two faces' end points, in the plane of their chord and the
// faces' mean end tangent: where the faces' thickness has zero slope at
// their ends (G1 with a circle of the edge radius centred between them, as
// the built-in blisk's) the closed section is tangent-continuous. The
// built-in blisk's edge circles lie on the cylinder of the section's
// radius; the plane half circle departs from that by at most r_e^2 / (2 r)
// (1.3 um for r_e = 0.4 mm at r = 63 mm). A measured blade's faces cut off
// short of its edges (a blade model's edge_margin > 0) still converge
// there: the half circle then meets them at an angle (edge_kink_deg), and
// the closed surface is not the blade near its edges. Faces that meet at
// their edge points (edge_margin 0: they carry the data's own rounds) are
// joined there directly, with no half circle.
//
// The sections are lofted by loft_sections (core/geometry/section_loft.h):
// closed C2 around (no seam), u from the first section to the last, v once
// around starting at the trailing edge's apex, pu x pv out of the material.
#include <memory>

#include "core/geometry/surface.h"
#include "core/geometry/section_loft.h"

namespace bliskrun {

struct ClosedBladeOptions {
  double u0 = 0, u1 = 1;   // span window of the faces to close (their u)
  int sections = 31;       // sections lofted, equally spaced in u
  int face_samples = 300;  // points per face per section
  int edge_samples = 24;   // points per half circle (ends excluded)
  SectionLoftOptions loft; // samples around
};

struct ClosedBlade {
  SectionLoft loft;
  // v of the leading and trailing edge apex on the middle section (the
  // apex moves by a few 1e-4 in v along the span as the faces' lengths do).
  double le_v = 0, te_v = 0;
  double perimeter_mm = 0;  // of the middle section
  // The largest turn of the section's tangent where an edge meets a face,
  // over every section (degrees): ~0 for the built-in blisk's faces and for
  // faces that meet at their edges; tens of degrees for a measured blade's
  // faces cut off short of its edges (see above).
  double edge_kink_deg = 0;
};

// Throws ParameterError ("u0"/"u1") for a window outside [0, 1] or empty,
// ("sections") for fewer than 2, ("face_samples") for fewer than 8,
// ("edge_samples") for fewer than 3, and Error where a half circle has no
// direction to bulge in (the faces' end tangents along the edge's chord).
ClosedBlade close_blade(const Surface& pressure, const Surface& suction, const ClosedBladeOptions& options = {});

}  // namespace bliskrun
