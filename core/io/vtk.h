#pragma once
// VTK XML PolyData (.vtp) and a ParaView collection (.pvd) per run, so the
// part, the toolpath and the refused poses open together in ParaView.
//
// ASCII format, by choice: the files diff and grep, a test reads them back
// with a few lines of parsing, and ParaView reads them directly; a flank mesh
// of ~50 000 points is a few MB, which is fine next to the run's other files.
// Numbers are written with 17 significant digits (%.17g) so coordinates
// round-trip exactly.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/surface.h"

namespace bliskrun {

// A per-point array: `components` values per point (1 scalar, 3 vector).
struct VtkPointArray {
  std::string name;
  int components = 1;
  std::vector<double> values;  // points x components
};

struct VtkPolyData {
  std::vector<Vec3> points;
  bool vertices = false;                    // one vertex cell per point (point sets)
  std::vector<std::vector<int>> lines;      // polylines, point indices
  std::vector<std::array<int, 3>> triangles;
  std::vector<VtkPointArray> point_data;
  // Names for an integer-coded point array (e.g. reason 0 = "..."), written as
  // an XML comment and in the .pvd, since ParaView colours by numbers.
  std::vector<std::string> code_names;
};

// The .vtp document. Throws ParameterError naming the array or cell that does
// not fit the points (wrong length, index out of range, non-finite value).
std::string vtp_xml(const VtkPolyData& data);
// Writes vtp_xml(...) with write_file_atomic.
void write_vtp(const VtkPolyData& data, const std::string& path);

// One .pvd listing (name, file relative to the .pvd's folder) as parts of
// timestep 0, written atomically.
void write_pvd(const std::vector<std::pair<std::string, std::string>>& blocks, const std::string& path);

}  // namespace bliskrun
