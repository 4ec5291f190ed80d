#pragma once
// Internal to core/cad: process-wide OpenCASCADE settings, made once.
namespace bliskrun::detail {

// Removes OCCT's stdout message printers and sets transferred lengths to mm.
void quiet_occt();

}  // namespace bliskrun::detail
