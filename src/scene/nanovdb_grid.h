// nanovdb_grid.h — the density grids of grid media (darts' "nanovdb" medium):
// reading one float grid out of a .nvdb file, checking it, and deriving the
// coarse majorant grid that delta tracking walks (media.glsl).
//
// The file format is NanoVDB's (nanovdb/util/IO.h, version 32): segments of
// a 16-byte header, one 176-byte record and a name per grid, then the grids'
// bytes. wavepath reads the records itself, so that every size in them is
// checked against the file before anything is allocated or read, and reads
// the grid's own bytes with PNanoVDB.h, as the kernels do.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace wp {

// One NanoVDB float grid, as the kernels read it (pnanovdb.glsl).
struct DensityGrid {
  std::string file;                 // where it was read from, for messages
  std::string name;                 // its grid name
  std::vector<uint32_t> words;      // the grid's bytes, whole
  glm::ivec3 indexMin{0}, indexMax{-1};  // the box of its active voxels, in index space (inclusive)
  glm::dmat4 worldToIndex{1.0};     // the grid's own map, inverted: its world space to index space
  float maxDensity = 0.0f;          // the largest value a lookup can return (negatives count as 0)
  uint64_t activeVoxels = 0;
  uint32_t leaves = 0;
};

// Reads grid `gridName` of the .nvdb file at `path`. Bad input throws
// InputError naming the file and the problem; `where` (a scene file and a
// JSON path) says who asked for it.
DensityGrid read_nanovdb(const std::string& path, const std::string& gridName, const std::string& where);

// Checks the bytes of a float grid (from a file or made in memory) and fills
// the fields derived from them; throws InputError("<file>: ...") where they
// are not a fog volume of floats that PNanoVDB can walk safely.
void check_density_grid(DensityGrid& g);

// The majorant grid of g: the largest density over each of cells.x * y * z
// equal cells of the box the kernels track through, [indexMin - 1,
// indexMax + 1] (a trilinear lookup reaches one voxel beyond the active
// ones), x fastest. Every voxel and tile value counts, over the cells its
// lookups reach.
std::vector<float> majorant_grid(const DensityGrid& g, glm::uvec3 cells);

// The default majorant cells of g: about one per NanoVDB leaf (8 voxels)
// along each axis, at most MAJORANT_GRID_CELLS_MAX.
glm::uvec3 default_majorant_cells(const DensityGrid& g);

}  // namespace wp
