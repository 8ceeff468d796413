// pnanovdb.glsl — NanoVDB grids, read with PNanoVDB.h (Debian's
// libnanovdb-dev), the port of NanoVDB its authors wrote to compile as C and
// as GLSL: the kernels and the CPU reference walk the same grid bytes with
// the same code. This file gives PNanoVDB its buffer in each language: the
// volume words (BINDING_VOLUMES), every grid of the scene back to back.
//
// Reads past the buffer return 0 in both languages. The host validates a
// grid when it loads it (src/scene/nanovdb_file.cpp), but a lookup follows
// offsets stored in the grid, and a bounded read keeps a damaged one from
// reaching outside the buffer whatever they hold.
//
// In C++ this file is included at namespace scope (shader_cpp.h), not inside
// SceneView as the rest of the shared code, since PNanoVDB's C declares
// static tables; SceneView::volume_buf() hands it the buffer.
#ifndef WP_PNANOVDB_GLSL
#define WP_PNANOVDB_GLSL

#define PNANOVDB_BUF_CUSTOM
#ifdef __cplusplus
#define PNANOVDB_C
#include <cstdint>
#include <cstring>
struct pnanovdb_buf_t {
  const std::uint32_t* words;
  std::uint64_t count;
};
static inline std::uint32_t pnanovdb_buf_read_uint32(pnanovdb_buf_t buf, std::uint64_t byteOffset) {
  std::uint64_t w = byteOffset >> 2u;
  return w < buf.count ? buf.words[w] : 0u;
}
static inline std::uint64_t pnanovdb_buf_read_uint64(pnanovdb_buf_t buf, std::uint64_t byteOffset) {
  return std::uint64_t(pnanovdb_buf_read_uint32(buf, byteOffset)) |
         (std::uint64_t(pnanovdb_buf_read_uint32(buf, byteOffset + 4u)) << 32u);
}
typedef std::uint32_t pnanovdb_grid_type_t;
#else
#define PNANOVDB_GLSL
struct pnanovdb_buf_t {
  uint unused;
};
uint pnanovdb_buf_read_uint32(pnanovdb_buf_t buf, uint byteOffset) {
  int w = int(byteOffset >> 2u);
  return w < textureSize(volumeWords) ? texelFetch(volumeWords, w).x : 0u;
}
uvec2 pnanovdb_buf_read_uint64(pnanovdb_buf_t buf, uint byteOffset) {
  return uvec2(pnanovdb_buf_read_uint32(buf, byteOffset), pnanovdb_buf_read_uint32(buf, byteOffset + 4u));
}
pnanovdb_buf_t volume_buf() {
  pnanovdb_buf_t b;
  b.unused = 0u;
  return b;
}
#define pnanovdb_grid_type_t uint
#endif
#define PNANOVDB_GRID_TYPE_GET(grid_typeIn, nameIn) pnanovdb_grid_type_constants[grid_typeIn].nameIn
#include "nanovdb/PNanoVDB.h"

#endif  // WP_PNANOVDB_GLSL
