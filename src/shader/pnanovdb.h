// pnanovdb.h — NanoVDB's PNanoVDB.h compiled as C++ (pnanovdb.glsl gives it
// its buffer), in namespace wp::shader: the grid walk the kernels and the CPU
// reference share, and what the loader of .nvdb files validates a grid with
// (scene/nanovdb_grid.cpp), without the rest of the shared code.
#pragma once

// PNanoVDB includes these C headers; included here first, they stay out of
// the namespace it is included into.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "../../shaders/shared/common.glsl"

namespace wp::shader {
#include "../../shaders/shared/pnanovdb.glsl"
}  // namespace wp::shader
