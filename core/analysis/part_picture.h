#pragma once
// The part itself with a value painted on it — "the blade with the
// material left on it" (issue 37 item 2) — where a (u, v) map makes the
// reader translate parameters back into places.
//
// Drawing a shaded, coloured mesh is a renderer's job, so the picture is
// rendered by POV-Ray (Debian package `povray`, a ray tracer kept since
// 1991): the pieces become one scene (mesh2 with a colour per vertex,
// interpolated over each triangle; an orthographic camera; a key light from
// the viewer's upper left and a fill light), POV-Ray writes the PNG, and the
// colour bar and title — the same fixed symmetric µm scale and colours as
// the run's maps (heat_map.h) — are drawn beside it with raster.h.
//
// The view: looking along -n, n the area-weighted mean normal of the first
// piece (a flank seen face-on), with "up" the pieces' longest extent across
// the view (the blade's span), unless the options give both.
#include <optional>
#include <string>
#include <vector>

#include "core/common/raster.h"
#include "core/common/types.h"

namespace bliskrun {

// A grid of surface points, rows x cols, row-major, with one value per
// point in the picture's unit: finite, +-infinity ("never reached": grey)
// or NaN ("not part of this picture": drawn in the part's plain colour).
struct PaintedPiece {
  std::string name;
  int rows = 0, cols = 0;
  std::vector<Vec3> points;
  std::vector<double> values;
};

struct PartPictureOptions {
  std::string title;
  std::string value_label = "µm";
  std::string footer;
  double scale_max = 0;  // > 0: colour scale [-scale_max, scale_max]; 0: the largest |finite value|
  int levels = 64;
  int width_px = 900;    // the rendered part; the colour bar is added to the right
  int height_px = 600;
  std::optional<Vec3> view;  // direction the viewer looks along (into the part)
  std::optional<Vec3> up;
  bool behind = false;       // the default view turned round: the first piece's back (a blade's other side)
  std::string povray = "povray";  // the renderer's executable (found on PATH)
};

// True when the renderer can be run (the executable is on PATH).
bool part_renderer_available(const std::string& povray = "povray");

// A POV-Ray scene (its text) rendered to a picture width x height pixels
// (antialiased), in a temporary folder removed after. Throws Error when the
// renderer cannot be run or fails (its last output lines in the message).
// Shared with the machine's picture (machine_picture.h).
RgbImage render_povray_scene(const std::string& scene, int width_px, int height_px,
                             const std::string& povray = "povray");

// The scene POV-Ray renders (exposed for tests: it is plain text).
std::string part_picture_scene(const std::vector<PaintedPiece>& pieces, const PartPictureOptions& options);

// Renders the pieces and composes the picture. Throws ParameterError for
// empty or mis-sized pieces, Error when the renderer cannot be run or fails
// (its last output lines in the message).
RgbImage render_part_picture(const std::vector<PaintedPiece>& pieces, const PartPictureOptions& options);

// encode_png(render_part_picture(...)) written with write_file_atomic.
void write_part_picture_png(const std::vector<PaintedPiece>& pieces, const std::string& path,
                            const PartPictureOptions& options);

}  // namespace bliskrun
