// Any text given to the point-grid reader either parses into a consistent
// grid or fails with a DataError naming file:line — never a crash, hang or
// undefined behaviour.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/common/error.h"
#include "core/io/point_grid_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const bliskrun::PointGrid g = bliskrun::parse_point_grid(text, "fuzz.txt");
    if (g.points.size() != static_cast<size_t>(g.rows) * g.cols || g.rows < 2 || g.cols < 2) __builtin_trap();
  } catch (const bliskrun::DataError& e) {
    if (std::string(e.what()).rfind("fuzz.txt:", 0) != 0) __builtin_trap();  // must say where
  }
  return 0;
}
