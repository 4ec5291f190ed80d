#include "core/machine/machine_picture.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/analysis/part_picture.h"
#include "core/common/atomic_file.h"
#include "core/common/error.h"

namespace bliskrun {
// Named, not anonymous: unity builds put part_picture.cpp beside this.
namespace machine_picture_detail {

constexpr Rgb kBackground = {255, 255, 255};
constexpr Rgb kFirst = {215, 40, 35};     // the pair's first body
constexpr Rgb kSecond = {245, 150, 20};   // its second
constexpr Rgb kMachine = {150, 155, 165};
constexpr Rgb kFixture = {150, 110, 70};
constexpr Rgb kStock = {225, 205, 160};
constexpr Rgb kPart = {70, 110, 170};
constexpr Rgb kTool = {60, 60, 60};

std::string num(double x) {
  std::ostringstream s;
  s.precision(9);
  s << x;
  return s.str();
}

Rgb colour_of(const PlacedBody& b, const BodyApproach& at) {
  if (b.highlighted) return b.name == at.a ? kFirst : kSecond;
  switch (b.role) {
    case PlacedBody::Fixture: return kFixture;
    case PlacedBody::Stock: return kStock;
    case PlacedBody::Part: return kPart;
    case PlacedBody::Tool: return kTool;
    default: return kMachine;
  }
}

// Points on a body's outline, machine frame (framing and depth).
void outline_points(const PlacedBody& b, std::vector<Vec3>& out) {
  if (b.shape == BodyShape::Mesh) {
    for (const auto& m : b.meshes)
      for (const Vec3& v : m->vertices) out.push_back(b.pose * v);
    return;
  }
  if (b.shape == BodyShape::Box) {
    for (int k = 0; k < 8; ++k)
      out.push_back(b.pose * Vec3((k & 1 ? 0.5 : -0.5) * b.size_mm.x(), (k & 2 ? 0.5 : -0.5) * b.size_mm.y(),
                                  (k & 4 ? 0.5 : -0.5) * b.size_mm.z()));
    return;
  }
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * kPi * k / 16;
    for (double z : {-0.5 * b.length_mm, 0.5 * b.length_mm})
      out.push_back(b.pose * Vec3(b.radius_mm * std::cos(a), b.radius_mm * std::sin(a), z));
  }
}

struct View {
  Vec3 right, up, look;
  Vec3 to_scene(const Vec3& x) const { return Vec3(x.dot(right), x.dot(up), x.dot(look)); }
};

View view_of(const MachinePictureOptions& o) {
  const Vec3 look = (o.view ? *o.view : Vec3(0.45, 1.0, -0.55)).normalized();
  Vec3 up = Vec3::UnitZ() - Vec3::UnitZ().dot(look) * look;
  if (up.norm() < 1e-9) up = look.unitOrthogonal();
  up.normalize();
  // Right-handed world, left-handed POV-Ray camera: right = look x up keeps
  // the picture unmirrored (as part_picture.cpp).
  return {look.cross(up).normalized(), up, look};
}

// POV-Ray's `matrix` of scene-from-body: the columns of the linear part,
// then the translation.
std::string matrix_of(const View& v, const Eigen::Isometry3d& pose) {
  Eigen::Matrix3d rows;
  rows.row(0) = v.right.transpose();
  rows.row(1) = v.up.transpose();
  rows.row(2) = v.look.transpose();
  const Eigen::Matrix3d m = rows * pose.linear();
  const Vec3 t = rows * pose.translation();
  std::ostringstream s;
  s << "matrix <";
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) s << num(m(r, c)) << ", ";
  s << num(t.x()) << ", " << num(t.y()) << ", " << num(t.z()) << ">";
  return s.str();
}

std::string texture_of(Rgb c, double transmit) {
  auto lin = [](std::uint8_t x) { return num(std::pow(x / 255.0, 2.2)); };
  std::ostringstream s;
  s << "texture { pigment { rgbt <" << lin(c[0]) << ", " << lin(c[1]) << ", " << lin(c[2]) << ", " << num(transmit)
    << "> } finish { ambient 0.3 diffuse 0.7 specular 0.1 } }";
  return s.str();
}

std::string scene_text(const MachineScene& scene, const MachinePictureOptions& o) {
  if (scene.bodies.empty()) throw ParameterError("scene", "expected at least one body to draw");
  const View v = view_of(o);
  // Framed: the highlighted pair, the part and the tool; the depth range
  // from every body, so the camera stands in front of all of them.
  std::vector<Vec3> framed, all;
  for (const PlacedBody& b : scene.bodies) {
    std::vector<Vec3> pts;
    outline_points(b, pts);
    if (b.highlighted || b.role == PlacedBody::Part || b.role == PlacedBody::Tool)
      framed.insert(framed.end(), pts.begin(), pts.end());
    all.insert(all.end(), pts.begin(), pts.end());
  }
  if (framed.empty()) framed = all;
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  for (const Vec3& x : framed) {
    const Vec3 s = v.to_scene(x);
    lo = lo.cwiseMin(s), hi = hi.cwiseMax(s);
  }
  double z_lo = kInf, z_hi = -kInf;
  for (const Vec3& x : all) {
    const double z = x.dot(v.look);
    z_lo = std::min(z_lo, z);
    z_hi = std::max(z_hi, z);
  }
  const double aspect = double(o.width_px) / o.height_px;
  const Vec3 centre = (lo + hi) / 2;
  double w = std::max(hi.x() - lo.x(), 1.0) * 1.15, h = std::max(hi.y() - lo.y(), 1.0) * 1.15;
  if (w / h > aspect) h = w / aspect; else w = h * aspect;
  const double depth = z_hi - z_lo;

  std::ostringstream s;
  s << "// bliskrun machine picture (core/machine/machine_picture.cpp)\n"
    << "#version 3.7;\nglobal_settings { assumed_gamma 1.0 ambient_light rgb <1, 1, 1> }\n"
    << "background { rgb <1, 1, 1> }\n"
    << "camera { orthographic location <" << num(centre.x()) << ", " << num(centre.y()) << ", "
    << num(z_lo - depth - 10) << "> direction <0, 0, 1> right <" << num(w) << ", 0, 0> up <0, " << num(h)
    << ", 0> }\n"
    << "light_source { <" << num(centre.x() - 2 * w) << ", " << num(centre.y() + 2 * h) << ", "
    << num(z_lo - 3 * (w + h)) << "> rgb <0.75, 0.75, 0.75> parallel point_at <" << num(centre.x()) << ", "
    << num(centre.y()) << ", " << num(centre.z()) << "> }\n"
    << "light_source { <" << num(centre.x() + 3 * w) << ", " << num(centre.y()) << ", " << num(z_lo - (w + h))
    << "> rgb <0.3, 0.3, 0.3> parallel point_at <" << num(centre.x()) << ", " << num(centre.y()) << ", "
    << num(centre.z()) << "> }\n";
  for (const PlacedBody& b : scene.bodies) {
    // The pair and the part opaque; the rest lets them show through.
    const double transmit = b.highlighted || b.role == PlacedBody::Part ? 0.0 : b.role == PlacedBody::Tool ? 0.3 : 0.6;
    const std::string texture = texture_of(colour_of(b, scene.at), transmit);
    s << "// " << b.name << "\n";
    switch (b.shape) {
      case BodyShape::Box:
        s << "box { <" << num(-0.5 * b.size_mm.x()) << ", " << num(-0.5 * b.size_mm.y()) << ", "
          << num(-0.5 * b.size_mm.z()) << ">, <" << num(0.5 * b.size_mm.x()) << ", " << num(0.5 * b.size_mm.y()) << ", "
          << num(0.5 * b.size_mm.z()) << "> ";
        break;
      case BodyShape::Cylinder:
        s << "cylinder { <0, 0, " << num(-0.5 * b.length_mm) << ">, <0, 0, " << num(0.5 * b.length_mm) << ">, "
          << num(b.radius_mm) << " ";
        break;
      case BodyShape::Cone:
        s << "cone { <0, 0, " << num(-0.5 * b.length_mm) << ">, " << num(b.radius_mm) << ", <0, 0, "
          << num(0.5 * b.length_mm) << ">, 0 ";
        break;
      case BodyShape::Mesh: {
        size_t nv = 0, nt = 0;
        for (const auto& m : b.meshes) nv += m->vertices.size(), nt += m->triangles.size();
        s << "mesh2 {\n  vertex_vectors { " << nv;
        for (const auto& m : b.meshes)
          for (const Vec3& x : m->vertices) s << ", <" << num(x.x()) << "," << num(x.y()) << "," << num(x.z()) << ">";
        s << " }\n  face_indices { " << nt;
        size_t base = 0;
        for (const auto& m : b.meshes) {
          for (const Eigen::Vector3i& t : m->triangles)
            s << ", <" << base + t[0] << "," << base + t[1] << "," << base + t[2] << ">";
          base += m->vertices.size();
        }
        s << " }\n  ";
        break;
      }
    }
    // A see-through body casts no shadow: its shadow only muddies what it is
    // drawn see-through to show, and shadow rays through transparent bodies
    // were half of the render's time (7.7 -> 3.5 s CPU on the blisk job).
    s << texture << (transmit > 0 ? " no_shadow " : " ") << matrix_of(v, b.pose) << " }\n";
  }
  // The nearest points and the line between them.
  const Vec3 a = v.to_scene(scene.nearest_a), b = v.to_scene(scene.nearest_b);
  const double dot = 0.006 * std::max(w, h);
  s << "sphere { <" << num(a.x()) << ", " << num(a.y()) << ", " << num(a.z()) << ">, " << num(dot) << " "
    << texture_of({0, 0, 0}, 0) << " no_shadow }\n";
  s << "sphere { <" << num(b.x()) << ", " << num(b.y()) << ", " << num(b.z()) << ">, " << num(dot) << " "
    << texture_of({0, 0, 0}, 0) << " no_shadow }\n";
  if ((a - b).norm() > 1e-6)
    s << "cylinder { <" << num(a.x()) << ", " << num(a.y()) << ", " << num(a.z()) << ">, <" << num(b.x()) << ", "
      << num(b.y()) << ", " << num(b.z()) << ">, " << num(0.4 * dot) << " " << texture_of({0, 0, 0}, 0)
      << " no_shadow }\n";
  return s.str();
}

RgbImage render(const MachineScene& scene, const MachinePictureOptions& o) {
  if (o.width_px < 50 || o.height_px < 50 || o.width_px > 8000 || o.height_px > 8000)
    throw ParameterError("width/height", "expected 50..8000 pixels");
  const RgbImage rendered = render_povray_scene(scene_text(scene, o), o.width_px, o.height_px, o.povray);
  // Title above; below, the key: the pair, the others, the nearest points.
  const int margin = 10, title_h = o.title.empty() ? 0 : 24, footer_h = o.footer.empty() ? 0 : 16, key_h = 34;
  RgbImage img(rendered.width + 2 * margin, title_h + rendered.height + footer_h + key_h + 2 * margin, kBackground);
  if (!o.title.empty()) img.text(margin, margin, o.title, {0, 0, 0}, 2);
  const int top = margin + title_h;
  for (int y = 0; y < rendered.height; ++y)
    for (int x = 0; x < rendered.width; ++x) img.set(margin + x, top + y, rendered.at(x, y));
  int y = top + rendered.height + 4;
  if (!o.footer.empty()) {
    img.text(margin, y, o.footer, {60, 60, 60});
    y += footer_h;
  }
  int x = margin;
  auto key = [&](Rgb c, const std::string& label) {
    img.fill(x, y, x + 14, y + 10, c);
    img.frame(x, y, x + 14, y + 10, {0, 0, 0});
    img.text(x + 20, y + 2, label, {0, 0, 0});
    x += 20 + text_width(label) + 20;
  };
  key(kFirst, scene.at.a);
  key(kSecond, scene.at.b);
  key(kPart, "part");
  key(kTool, "tool");
  key(kFixture, "fixture");
  key(kStock, "stock");
  key(kMachine, "machine (see-through)");
  return img;
}

}  // namespace machine_picture_detail

std::string machine_picture_scene(const MachineScene& scene, const MachinePictureOptions& options) {
  return machine_picture_detail::scene_text(scene, options);
}

RgbImage render_machine_picture(const MachineScene& scene, const MachinePictureOptions& options) {
  return machine_picture_detail::render(scene, options);
}

void write_machine_picture_png(const MachineScene& scene, const std::string& path, const MachinePictureOptions& options) {
  write_file_atomic(path, encode_png(machine_picture_detail::render(scene, options)));
}

}  // namespace bliskrun
