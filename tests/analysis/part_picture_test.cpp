// The part picture: the scene POV-Ray is given (every grid point a vertex,
// two triangles a cell, one texture per colour) and, where POV-Ray is
// installed (CI installs it), the rendered picture: a plate painted red on
// its -x half and blue on its +x half, seen face-on, shows red on the left
// and blue on the right (not mirrored), with the plain part between.
#include "core/analysis/part_picture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/analysis/heat_map.h"
#include "core/common/error.h"

namespace bliskrun {
namespace {

// A 60 x 40 mm plate in the xy plane, normal +z (cols along x, rows along
// y), values +10 on x < -10, -10 on x > 10, NaN (not painted) between.
PaintedPiece plate() {
  PaintedPiece p;
  p.name = "plate";
  p.rows = 21;
  p.cols = 31;
  for (int i = 0; i < p.rows; ++i)
    for (int j = 0; j < p.cols; ++j) {
      const double x = -30 + 2.0 * j, y = -20 + 2.0 * i;
      p.points.emplace_back(x, y, 0);
      p.values.push_back(x < -10 ? 10 : x > 10 ? -10 : std::numeric_limits<double>::quiet_NaN());
    }
  return p;
}

size_t occurrences(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(PartPicture, TheSceneHasEveryPointAndTwoTrianglesACell) {
  const std::string scene = part_picture_scene({plate()}, PartPictureOptions{});
  EXPECT_NE(scene.find("vertex_vectors { 651,"), std::string::npos);
  EXPECT_NE(scene.find("normal_vectors { 651,"), std::string::npos);
  EXPECT_NE(scene.find("face_indices { 1200,"), std::string::npos);
  // Three colours: the scale's two ends and the plain part.
  EXPECT_NE(scene.find("texture_list { 3,"), std::string::npos);
  EXPECT_EQ(occurrences(scene, "texture {"), 3u);
  EXPECT_NE(scene.find("orthographic"), std::string::npos);
}

TEST(PartPicture, RefusesAMisSizedPiece) {
  PaintedPiece p = plate();
  p.values.pop_back();
  EXPECT_THROW(part_picture_scene({p}, PartPictureOptions{}), ParameterError);
  EXPECT_THROW(part_picture_scene({}, PartPictureOptions{}), ParameterError);
}

TEST(PartPicture, ARenderedPlateShowsItsValuesWhereTheyAreUnmirrored) {
  if (!part_renderer_available()) GTEST_SKIP() << "POV-Ray not installed (apt-get install povray): render skipped";
  PartPictureOptions o;
  o.title = "plate";
  o.width_px = 300;
  o.height_px = 200;
  o.scale_max = 10;
  o.up = Vec3::UnitY();  // (by default "up" is the longest extent across the view: x here)
  const RgbImage img = render_part_picture({plate()}, o);
  // The part sits at (margin 10, title 24) in the picture; the plate
  // (60 x 40 with 6 % margin) fills the 300 x 200 view: x = -20 at 1/6 of
  // the width from the left of the plate, x = +20 at 5/6.
  const int x0 = 10, y0 = 10 + 24;
  const double plate_w = 300 / 1.06, left = x0 + (300 - plate_w) / 2;
  const Rgb l = img.at(static_cast<int>(left + plate_w / 6), y0 + 100);
  const Rgb c = img.at(static_cast<int>(left + plate_w / 2), y0 + 100);
  const Rgb r = img.at(static_cast<int>(left + 5 * plate_w / 6), y0 + 100);
  EXPECT_GT(l[0], l[2] + 40) << "left should be red: " << int(l[0]) << "," << int(l[1]) << "," << int(l[2]);
  EXPECT_GT(r[2], r[0] + 40) << "right should be blue: " << int(r[0]) << "," << int(r[1]) << "," << int(r[2]);
  EXPECT_LT(std::abs(int(c[0]) - int(c[2])), 20) << "middle should be the plain part";
  // Turned round (behind), the plate's -x half is on the right.
  o.behind = true;
  const RgbImage back = render_part_picture({plate()}, o);
  const Rgb bl = back.at(static_cast<int>(left + plate_w / 6), y0 + 100);
  EXPECT_GT(bl[2], bl[0] + 40) << "seen from behind, the left is the blue half";
  // Outside the plate: the white background.
  const Rgb corner = img.at(x0 + 2, y0 + 2);
  EXPECT_EQ(corner, (Rgb{255, 255, 255}));
}

TEST(PartPicture, AMissingRendererIsAClearError) {
  PartPictureOptions o;
  o.povray = "/nonexistent/povray";
  EXPECT_FALSE(part_renderer_available(o.povray));
  try {
    render_part_picture({plate()}, o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("apt-get install povray"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bliskrun
