#pragma once
// CAD geometry in (IGES, STEP) and out (STEP), through OpenCASCADE. The OCCT
// types stay in this folder's .cpp files: the rest of bliskrun sees only the
// kernel's NurbsSurface and NurbsCurve, exact copies of the file's B-splines
// (analytic faces are converted to NURBS by OCCT, exactly, not fitted).
// Lengths are in mm whatever the file's unit.
#include <memory>
#include <string>
#include <vector>

#include "core/common/types.h"
#include "core/geometry/nurbs.h"

namespace bliskrun {

// One face of the file: its untrimmed carrier surface, reparametrised to
// [0, 1]^2, and the face's outer boundary in that parameter square and in 3-D
// (planners may stay inside it; they trim on their own as on any surface).
struct CadFace {
  std::string name;    // the file's name for it, else "face_<k>" (1-based)
  std::string entity;  // where in the file: "IGES D17 (type 128)", "STEP #123"
  std::shared_ptr<const NurbsSurface> surface;
  // Outer wire as a closed polyline (first point repeated at the end),
  // sampled along each edge; empty when the face has no wire (an untrimmed
  // IGES 128 surface is bounded by its own parameter square).
  std::vector<Vec2> boundary_uv;
  std::vector<Vec3> boundary_mm;
  // Parameter box of the outer boundary, in [0, 1].
  double u_min = 0, u_max = 1, v_min = 0, v_max = 1;
};

// One curve of the file that bounds no face (IGES 126, a STEP wire).
struct CadCurve {
  std::string name;    // the file's name, else "curve_<k>"
  std::string entity;  // as CadFace::entity
  std::shared_ptr<const NurbsCurve> curve;
};

struct CadModel {
  std::string path;
  std::string format;      // "IGES" or "STEP"
  std::string file_units;  // the file's length unit as it names it ("INCH", "mm", ...)
  std::vector<CadFace> faces;
  std::vector<CadCurve> curves;
};

// Reads an IGES (.igs, .iges) or STEP (.stp, .step; AP203/AP214/AP242) file.
// Throws DataError naming the file (and the entity, "D<n>" for IGES or
// "#<n>" for STEP) when the file is missing, truncated or corrupt, holds no
// surface and no curve, holds an entity OCCT cannot convert, a surface of
// degree > 7 or a degenerate surface (an edge of its parameter square
// collapsed to a point, or no area at all).
CadModel read_cad(const std::string& path);

// Writes the surfaces (each as a B-spline face bounded by its parameter
// square) and curves to a STEP file in mm, atomically, in OCCT's schema
// `schema` ("AP203", "AP214IS", "AP242DIS"). For tests and fixtures that
// need a file a CAD system would write.
void write_step(const std::string& path, const std::vector<const NurbsSurface*>& surfaces,
                const std::vector<const NurbsCurve*>& curves = {},
                const std::string& schema = "AP214IS");

}  // namespace bliskrun
