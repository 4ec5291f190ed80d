#pragma once
// Measured point clouds from scanners and CMMs, for scan registration and the
// repair's measured sections:
//
//   XYZ  one point per line, "x y z" or "x y z nx ny nz", whitespace or comma
//        separated; '#' starts a comment.
//   CSV  the same with commas, plus one optional header line before the first
//        point: when it names columns x, y, z (any case; and nx, ny, nz) those
//        columns are read, in any order and among others; otherwise the header
//        is skipped and the columns are x y z [nx ny nz].
//   PLY  ASCII, binary_little_endian or binary_big_endian 1.0: the "vertex"
//        element's x, y, z (float or double) and, when all three are there,
//        nx, ny, nz; other properties and elements (faces) are skipped.
//   STL  ASCII or binary: the mesh's distinct vertices (exactly equal
//        coordinates are one point), in order of first appearance — for scans
//        delivered as meshes. No normals (an STL's are per facet).
//
// Coordinates are multiplied by `mm_per_unit` (25.4 for a file in inches);
// normals are returned as the file has them. An error in text names the file
// and line ("scan.xyz:12: ..."), in binary data the byte offset
// ("scan.stl: byte 184: ..."): truncated data, counts that disagree with the
// size, non-finite numbers, wrong property types, no points at all.
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/common/types.h"

namespace bliskrun {

enum class PointCloudFormat { kAuto, kXyz, kCsv, kPly, kStl };

// "auto", "xyz", "csv", "ply", "stl".
const char* point_cloud_format_name(PointCloudFormat format);

struct PointCloudReadOptions {
  // kAuto: from the file name's extension (.xyz .txt .asc .pts, .csv, .ply,
  // .stl), else from the content (PLY's "ply" line, an STL's "solid" line or
  // binary size, commas for CSV).
  PointCloudFormat format = PointCloudFormat::kAuto;
  double mm_per_unit = 1.0;  // file length unit in mm
};

struct PointCloud {
  std::vector<Vec3> points;         // mm
  std::vector<Vec3> normals;        // one per point when the file has them, else empty
  PointCloudFormat format = PointCloudFormat::kAuto;  // the format read (never kAuto)
};

// A DataError in binary data: what() is "<file>: byte <offset>: <message>";
// line() is 0.
class BinaryDataError : public DataError {
 public:
  BinaryDataError(const std::string& file, long long offset, const std::string& message)
      : DataError(file, 0, message),
        text_(file + ": byte " + std::to_string(offset) + ": " + message),
        offset_(offset) {}
  const char* what() const noexcept override { return text_.c_str(); }
  long long offset() const { return offset_; }

 private:
  std::string text_;
  long long offset_;
};

// Parses `bytes` as the contents of a file named `file_label` (used in
// messages, and for the extension when the format is kAuto).
PointCloud parse_point_cloud(const std::string& bytes, const std::string& file_label,
                             const PointCloudReadOptions& opts = {});

// Reads `path`; DataError(path, 0, ...) if it cannot be read.
PointCloud read_point_cloud(const std::string& path, const PointCloudReadOptions& opts = {});

}  // namespace bliskrun
