#pragma once
// The machine at one pose of a program — where the machine simulation found
// two bodies closest (machine_sim.h machine_scene) — as a picture for the
// run's report: every body of the machine, the fixture, the stock, the part
// and the tool in the spindle, the two closest highlighted (red and
// orange, opaque) with the line between their nearest points, the others
// half transparent so the pair shows through whatever stands in front.
// Rendered by POV-Ray as the painted part is (part_picture.h): the scene
// is plain text, the picture composed with a title and a key.
//
// The view: orthographic, from the front, left and above (looking along
// +0.45 X, +1 Y, -0.55 Z of the machine frame, Z up) unless the options
// give one, framed on the highlighted pair, the part and the tool.
#include <optional>
#include <string>

#include "core/common/raster.h"
#include "core/machine/machine_sim.h"

namespace bliskrun {

struct MachinePictureOptions {
  std::string title;
  std::string footer;
  int width_px = 900;
  int height_px = 600;
  std::optional<Vec3> view;       // direction the viewer looks along (machine frame)
  std::string povray = "povray";  // the renderer's executable (found on PATH)
};

// The scene POV-Ray renders (exposed for tests: it is plain text).
std::string machine_picture_scene(const MachineScene& scene, const MachinePictureOptions& options);

// Renders the scene and composes the picture. Throws ParameterError for an
// empty scene or a size out of 50..8000 pixels, Error when the renderer
// cannot be run or fails.
RgbImage render_machine_picture(const MachineScene& scene, const MachinePictureOptions& options);

// encode_png(render_machine_picture(...)) written with write_file_atomic.
void write_machine_picture_png(const MachineScene& scene, const std::string& path, const MachinePictureOptions& options);

}  // namespace bliskrun
