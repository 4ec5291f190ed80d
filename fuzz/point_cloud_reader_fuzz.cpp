// Any bytes given to the point-cloud reader, as any of its formats, either
// parse into finite points or fail with a DataError that names the file —
// never a crash, hang or undefined behaviour. The first byte picks the
// format (auto, xyz, csv, ply, stl); the rest is the file.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/common/error.h"
#include "core/io/point_cloud_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  bliskrun::PointCloudReadOptions o;
  o.format = static_cast<bliskrun::PointCloudFormat>(data[0] % 5);
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    const bliskrun::PointCloud c = bliskrun::parse_point_cloud(bytes, "fuzz", o);
    if (c.points.empty() || (!c.normals.empty() && c.normals.size() != c.points.size())) __builtin_trap();
    for (const bliskrun::Vec3& p : c.points)
      if (!p.allFinite()) __builtin_trap();
  } catch (const bliskrun::DataError& e) {
    if (std::string(e.what()).rfind("fuzz:", 0) != 0) __builtin_trap();  // must say where
  }
  return 0;
}
