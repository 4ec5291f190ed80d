#include "core/analysis/part_picture.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "core/analysis/heat_map.h"
#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/common/fixed_text.h"

namespace fs = std::filesystem;

namespace bliskrun {
namespace {

constexpr Rgb kPlainPart = {205, 205, 200};  // "not part of this picture": the part's own colour
constexpr Rgb kBackground = {255, 255, 255};

void check_pieces(const std::vector<PaintedPiece>& pieces) {
  if (pieces.empty()) throw ParameterError("pieces", "expected at least one surface to paint");
  for (const PaintedPiece& p : pieces) {
    const std::string where = "pieces (" + p.name + ")";
    if (p.rows < 2 || p.cols < 2) throw ParameterError(where, "expected a grid of at least 2 x 2 points");
    const size_t n = static_cast<size_t>(p.rows) * p.cols;
    if (p.points.size() != n || p.values.size() != n)
      throw ParameterError(where, "expected rows x cols = " + std::to_string(n) + " points and values");
  }
}

double scale_of(const std::vector<PaintedPiece>& pieces, const PartPictureOptions& o) {
  if (o.scale_max > 0) return o.scale_max;
  double m = 0;
  for (const PaintedPiece& p : pieces)
    for (double v : p.values)
      if (std::isfinite(v)) m = std::max(m, std::abs(v));
  return m > 0 ? m : 1;
}

// The viewer's frame: right, up, and the direction looked along.
struct View {
  Vec3 right, up, look;
};

View view_of(const std::vector<PaintedPiece>& pieces, const PartPictureOptions& o) {
  Vec3 look = Vec3::Zero();
  if (o.view) {
    look = o.view->normalized();
  } else {
    // Area-weighted normal of the first piece: a flank seen face-on, from
    // the side its normals point to.
    const PaintedPiece& p = pieces.front();
    for (int i = 0; i + 1 < p.rows; ++i)
      for (int j = 0; j + 1 < p.cols; ++j) {
        const Vec3& a = p.points[static_cast<size_t>(i) * p.cols + j];
        const Vec3& b = p.points[static_cast<size_t>(i) * p.cols + j + 1];
        const Vec3& c = p.points[static_cast<size_t>(i + 1) * p.cols + j];
        look -= (b - a).cross(c - a);
      }
    if (look.norm() < 1e-12) look = -Vec3::UnitZ();
    look.normalize();
    if (o.behind) look = -look;
  }
  Vec3 up;
  if (o.up) {
    up = *o.up;
  } else {
    // The longest extent across the view (principal axis of the points
    // projected on the picture plane).
    Vec3 mean = Vec3::Zero();
    size_t n = 0;
    for (const PaintedPiece& p : pieces)
      for (const Vec3& x : p.points) mean += x, ++n;
    mean /= static_cast<double>(n);
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    for (const PaintedPiece& p : pieces)
      for (const Vec3& x : p.points) {
        const Vec3 d = (x - mean) - (x - mean).dot(look) * look;
        c += d * d.transpose();
      }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(c);
    up = eig.eigenvectors().col(2);
    // Point "up" away from the origin side of the part (a blade's tip
    // above its hub when the part's axis runs through the origin).
    if (up.dot(mean) < 0) up = -up;
  }
  up = (up - up.dot(look) * look);
  if (up.norm() < 1e-9) up = look.unitOrthogonal();
  up.normalize();
  // Right-handed world, left-handed POV-Ray camera (x right, y up, z into
  // the picture): right = look x up keeps the picture unmirrored.
  return {look.cross(up).normalized(), up, look};
}

std::string num(double x) {
  std::ostringstream s;
  s.precision(9);
  s << x;
  return s.str();
}

}  // namespace

bool part_renderer_available(const std::string& povray) {
  if (povray.find('/') != std::string::npos) return ::access(povray.c_str(), X_OK) == 0;
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/bin:/bin");
  for (std::string d; std::getline(dirs, d, ':');)
    if (!d.empty() && ::access((fs::path(d) / povray).c_str(), X_OK) == 0) return true;
  return false;
}

std::string part_picture_scene(const std::vector<PaintedPiece>& pieces, const PartPictureOptions& o) {
  check_pieces(pieces);
  const View v = view_of(pieces, o);
  const double m = scale_of(pieces, o);
  // Scene coordinates: (right, up, look) components; the picture's bounds.
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  auto to_scene = [&](const Vec3& x) { return Vec3(x.dot(v.right), x.dot(v.up), x.dot(v.look)); };
  for (const PaintedPiece& p : pieces)
    for (const Vec3& x : p.points) {
      const Vec3 s = to_scene(x);
      lo = lo.cwiseMin(s), hi = hi.cwiseMax(s);
    }
  const double aspect = double(o.width_px) / o.height_px;
  const Vec3 centre = (lo + hi) / 2;
  double w = (hi.x() - lo.x()) * 1.06, h = (hi.y() - lo.y()) * 1.06;
  if (w / h > aspect) h = w / aspect; else w = h * aspect;
  const double depth = hi.z() - lo.z();

  std::ostringstream s;
  s << "// bliskrun part picture (core/analysis/part_picture.cpp)\n"
    << "#version 3.7;\nglobal_settings { assumed_gamma 1.0 ambient_light rgb <1, 1, 1> }\n"
    << "background { rgb <1, 1, 1> }\n"
    << "camera { orthographic location <" << num(centre.x()) << ", " << num(centre.y()) << ", "
    << num(lo.z() - depth - 10) << "> direction <0, 0, 1> right <" << num(w) << ", 0, 0> up <0, " << num(h)
    << ", 0> }\n"
    // Key light over the viewer's left shoulder, a weaker fill from the right.
    << "light_source { <" << num(centre.x() - 2 * w) << ", " << num(centre.y() + 2 * h) << ", "
    << num(lo.z() - 3 * (w + h)) << "> rgb <0.75, 0.75, 0.75> parallel point_at <" << num(centre.x()) << ", "
    << num(centre.y()) << ", " << num(centre.z()) << "> }\n"
    << "light_source { <" << num(centre.x() + 3 * w) << ", " << num(centre.y()) << ", " << num(lo.z() - (w + h))
    << "> rgb <0.3, 0.3, 0.3> parallel point_at <" << num(centre.x()) << ", " << num(centre.y()) << ", "
    << num(centre.z()) << "> }\n";
  // One texture per colour the vertices use (quantised like the maps).
  std::map<Rgb, int> palette;
  auto colour_index = [&](double value) {
    const Rgb c = std::isnan(value) ? kPlainPart : heat_map_colour(value, m, o.levels);
    const auto it = palette.emplace(c, static_cast<int>(palette.size())).first;
    return it->second;
  };
  for (const PaintedPiece& p : pieces) {
    std::vector<int> tex(p.values.size());
    for (size_t k = 0; k < p.values.size(); ++k) tex[k] = colour_index(p.values[k]);
    // Vertex normals: the grid's neighbours' cross product (flipped to face
    // the viewer: both sides of a thin blade are lit alike).
    std::vector<Vec3> normals(p.points.size());
    for (int i = 0; i < p.rows; ++i)
      for (int j = 0; j < p.cols; ++j) {
        const auto at = [&](int a, int b) { return p.points[static_cast<size_t>(a) * p.cols + b]; };
        const Vec3 du = at(std::min(i + 1, p.rows - 1), j) - at(std::max(i - 1, 0), j);
        const Vec3 dv = at(i, std::min(j + 1, p.cols - 1)) - at(i, std::max(j - 1, 0));
        Vec3 n = du.cross(dv);
        if (n.norm() < 1e-15) n = -v.look;
        n.normalize();
        if (n.dot(v.look) > 0) n = -n;
        normals[static_cast<size_t>(i) * p.cols + j] = to_scene(n);
      }
    s << "// " << p.name << "\nmesh2 {\n  vertex_vectors { " << p.points.size();
    for (const Vec3& x : p.points) {
      const Vec3 q = to_scene(x);
      s << ", <" << num(q.x()) << "," << num(q.y()) << "," << num(q.z()) << ">";
    }
    s << " }\n  normal_vectors { " << normals.size();
    for (const Vec3& n : normals) s << ", <" << num(n.x()) << "," << num(n.y()) << "," << num(n.z()) << ">";
    s << " }\n  texture_list { " << palette.size();
    std::vector<Rgb> by_index(palette.size());
    for (const auto& [c, k] : palette) by_index[static_cast<size_t>(k)] = c;
    for (const Rgb& c : by_index) {
      // The maps' sRGB colours to POV-Ray's linear light (assumed_gamma 1).
      auto lin = [](std::uint8_t x) { return num(std::pow(x / 255.0, 2.2)); };
      s << ",\n    texture { pigment { rgb <" << lin(c[0]) << "," << lin(c[1]) << "," << lin(c[2])
        << "> } finish { ambient 0.35 diffuse 0.7 specular 0.08 } }";
    }
    s << " }\n  face_indices { " << 2 * (p.rows - 1) * (p.cols - 1);
    for (int i = 0; i + 1 < p.rows; ++i)
      for (int j = 0; j + 1 < p.cols; ++j) {
        const int a = i * p.cols + j, b = a + 1, c = a + p.cols, e = c + 1;
        s << ", <" << a << "," << b << "," << e << ">," << tex[a] << "," << tex[b] << "," << tex[e];
        s << ", <" << a << "," << e << "," << c << ">," << tex[a] << "," << tex[e] << "," << tex[c];
      }
    s << " }\n}\n";
  }
  return s.str();
}

namespace {

// Runs POV-Ray in `dir` on scene.pov, writing part.png. Throws Error with
// the renderer's last lines on failure.
void run_povray(const fs::path& dir, int width_px, int height_px, const std::string& povray) {
  const std::string log = (dir / "povray.log").string();
  const std::vector<std::string> args = {
      povray, "+Iscene.pov", "+Opart.png", "+FN", "+W" + std::to_string(width_px),
      "+H" + std::to_string(height_px), "+A0.1", "+R3", "-D", "-P", "+Q9", "+WT2", "-V", "+GA"};
  // Everything the child needs is made before the fork: a worker thread
  // (post.write_all) may fork while another holds the allocator's lock.
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string folder = dir.string();
  const pid_t pid = ::fork();
  if (pid < 0) throw Error("part picture: cannot start " + povray + " (fork failed)");
  if (pid == 0) {
    if (::chdir(folder.c_str()) != 0) ::_exit(126);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::close(fd);
    }
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw Error("part picture: lost the renderer process");
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::exists(dir / "part.png")) return;
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string tail = text.size() > 600 ? text.substr(text.size() - 600) : text;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
    throw Error("part picture: the renderer '" + povray + "' is not installed (Debian: apt-get install povray)");
  throw Error("part picture: " + povray + " failed (" +
              (WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status)) : std::string("killed")) +
              "): " + tail);
}

// A temporary folder removed on scope exit.
struct TempFolder {
  fs::path path;
  TempFolder() {
    std::random_device rd;
    for (int tries = 0; tries < 100; ++tries) {
      path = fs::temp_directory_path() / ("bliskrun_picture_" + std::to_string(::getpid()) + "_" +
                                          std::to_string(rd()));
      if (fs::create_directory(path)) return;
    }
    throw Error("part picture: cannot create a temporary folder in " + fs::temp_directory_path().string());
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

RgbImage render_povray_scene(const std::string& scene, int width_px, int height_px, const std::string& povray) {
  if (width_px < 50 || height_px < 50 || width_px > 8000 || height_px > 8000)
    throw ParameterError("width/height", "expected 50..8000 pixels");
  TempFolder tmp;
  {
    std::ofstream out(tmp.path / "scene.pov");
    out << scene;
    if (!out) throw Error("part picture: cannot write the scene in " + tmp.path.string());
  }
  run_povray(tmp.path, width_px, height_px, povray);
  std::ifstream in(tmp.path / "part.png", std::ios::binary);
  return decode_png(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()),
                    "the rendered picture");
}

RgbImage render_part_picture(const std::vector<PaintedPiece>& pieces, const PartPictureOptions& o) {
  if (o.width_px < 50 || o.height_px < 50 || o.width_px > 8000 || o.height_px > 8000)
    throw ParameterError("width/height", "expected 50..8000 pixels");
  if (o.levels < 2) throw ParameterError("levels", "expected at least 2 colours");
  const RgbImage part = render_povray_scene(part_picture_scene(pieces, o), o.width_px, o.height_px, o.povray);

  // The picture: title above, the part, the colour bar and its legend right.
  const int margin = 10, title_h = o.title.empty() ? 0 : 24, bar_w = 18, labels_w = 70;
  const int footer_h = o.footer.empty() ? 0 : 16, legend_h = 34;
  RgbImage img(part.width + bar_w + labels_w + 3 * margin, title_h + part.height + footer_h + legend_h + 2 * margin,
               kBackground);
  if (!o.title.empty()) img.text(margin, margin, o.title, {0, 0, 0}, 2);
  const int top = margin + title_h;
  for (int y = 0; y < part.height; ++y)
    for (int x = 0; x < part.width; ++x) img.set(margin + x, top + y, part.at(x, y));
  const double m = scale_of(pieces, o);
  const int bx = 2 * margin + part.width, bh = part.height - 20, by = top + 10;
  for (int y = 0; y < bh; ++y) {
    const double value = m * (1 - 2.0 * (y + 0.5) / bh);
    img.fill(bx, by + y, bx + bar_w, by + y + 1, heat_map_colour(value, m, o.levels));
  }
  img.frame(bx, by, bx + bar_w, by + bh, {0, 0, 0});
  for (int k = 0; k <= 4; ++k) {
    const double value = m * (1 - k / 2.0);
    const int y = by + static_cast<int>(std::lround(k * (bh - 1) / 4.0));
    img.fill(bx + bar_w, y, bx + bar_w + 4, y + 1, {0, 0, 0});
    img.text(bx + bar_w + 6, y - 3, significant_text(value), {0, 0, 0});
  }
  img.text(bx, by - 10 > top ? by - 10 : top, o.value_label, {0, 0, 0});
  int y = top + part.height + 4;
  if (!o.footer.empty()) {
    img.text(margin, y, o.footer, {60, 60, 60});
    y += footer_h;
  }
  img.fill(margin, y, margin + 14, y + 10, heat_map_colour(kInf, m, o.levels));
  img.frame(margin, y, margin + 14, y + 10, {0, 0, 0});
  img.text(margin + 20, y + 2, "never reached", {0, 0, 0});
  const int x2 = margin + 20 + text_width("never reached") + 20;
  img.fill(x2, y, x2 + 14, y + 10, kPlainPart);
  img.frame(x2, y, x2 + 14, y + 10, {0, 0, 0});
  img.text(x2 + 20, y + 2, "not painted (outside the maps)", {0, 0, 0});
  return img;
}

void write_part_picture_png(const std::vector<PaintedPiece>& pieces, const std::string& path,
                            const PartPictureOptions& options) {
  write_file_atomic(path, encode_png(render_part_picture(pieces, options)));
}

}  // namespace bliskrun
