#include "scene/nanovdb_grid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include "scene/json_cursor.h"
#include "shader/pnanovdb.h"
#include "shader/types.h"
#include "util/error.h"

namespace wp {

namespace {

using namespace shader;

// NanoVDB's file records (nanovdb/util/IO.h: Header, MetaData).
constexpr uint64_t kHeaderBytes = 16;
constexpr uint64_t kMetaBytes = 176;
constexpr uint32_t kFormatMajor = 32;  // NANOVDB_MAJOR_VERSION_NUMBER: the format's ABI
constexpr uint32_t kNameBytesMax = 1u << 16;
const char* const kCodecs[] = {"none", "ZIP", "BLOSC"};
const char* const kGridTypes[] = {"unknown", "float", "double", "int16", "int32", "int64", "Vec3f", "Vec3d", "mask", "half",
                                  "uint32", "bool", "RGBA8", "Fp4", "Fp8", "Fp16", "FpN", "Vec4f", "Vec4d", "index"};
const char* const kGridClasses[] = {"unknown", "level set", "fog volume", "staggered", "point index", "point data",
                                    "topology", "voxel volume", "index grid"};

template <typename T>
T read_le(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

std::string version_string(uint32_t v) {
  return std::to_string(v >> 21) + "." + std::to_string((v >> 10) & 1023u) + "." + std::to_string(v & 1023u);
}

std::string grid_type_name(uint32_t t) { return t < std::size(kGridTypes) ? kGridTypes[t] : "type " + std::to_string(t); }
std::string grid_class_name(uint32_t c) { return c < std::size(kGridClasses) ? kGridClasses[c] : "class " + std::to_string(c); }

// The grid-relative byte range [offset, offset + count * size) lies in a
// grid of `bytes` bytes.
bool fits(uint64_t offset, uint64_t count, uint64_t size, uint64_t bytes) {
  return offset <= bytes && count <= (bytes - offset) / std::max<uint64_t>(size, 1);
}

}  // namespace

static DensityGrid read_grid(const std::string& path, const std::string& gridName) {
  const std::string at = path + ": ";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(at + "cannot open the NanoVDB file");
  in.seekg(0, std::ios::end);
  const uint64_t fileBytes = uint64_t(in.tellg());
  in.seekg(0);
  auto read = [&](unsigned char* dst, uint64_t offset, uint64_t n, const std::string& what) {
    if (offset > fileBytes || n > fileBytes - offset)
      throw InputError(at + "truncated: " + what + " needs " + std::to_string(n) + " bytes at byte " + std::to_string(offset) +
                       ", the file has " + std::to_string(fileBytes));
    in.seekg(std::streamoff(offset));
    if (!in.read(reinterpret_cast<char*>(dst), std::streamsize(n))) throw InputError(at + "cannot read " + what);
  };

  // The magic number first: a file of a few bytes is not a short grid.
  unsigned char magic[8] = {};
  if (fileBytes >= 8) read(magic, 0, 8, "the magic number");
  if (read_le<uint64_t>(magic) != PNANOVDB_MAGIC_NUMBER) throw InputError(at + "not a NanoVDB file (its first 8 bytes are not \"NanoVDB0\")");

  std::vector<std::string> names;
  uint64_t offset = 0;
  for (uint32_t segment = 0; offset < fileBytes; ++segment) {
    unsigned char header[kHeaderBytes];
    read(header, offset, kHeaderBytes, "the header of segment " + std::to_string(segment));
    const uint64_t magic = read_le<uint64_t>(header);
    if (magic != PNANOVDB_MAGIC_NUMBER) {
      if (segment == 0) throw InputError(at + "not a NanoVDB file (its first 8 bytes are not \"NanoVDB0\")");
      throw InputError(at + "segment " + std::to_string(segment) + " at byte " + std::to_string(offset) + " does not start with \"NanoVDB0\"");
    }
    const uint32_t version = read_le<uint32_t>(header + 8);
    const uint16_t gridCount = read_le<uint16_t>(header + 12), codec = read_le<uint16_t>(header + 14);
    if ((version >> 21) != kFormatMajor)
      throw InputError(at + "written by NanoVDB " + version_string(version) + "; wavepath reads the format of NanoVDB " +
                       std::to_string(kFormatMajor) + ".x (libnanovdb-dev 10)");
    if (codec != 0)
      throw InputError(at + "its grids are compressed (" + (codec < std::size(kCodecs) ? kCodecs[codec] : "codec " + std::to_string(codec)) +
                       "); wavepath reads uncompressed .nvdb files (NanoVDB's codec NONE)");
    if (gridCount == 0) throw InputError(at + "segment " + std::to_string(segment) + " holds no grids");
    offset += kHeaderBytes;
    // The records, then the grids in the same order.
    struct Record {
      uint64_t gridBytes;
      uint32_t type, cls;
      std::string name;
    };
    std::vector<Record> records;
    for (uint32_t i = 0; i < gridCount; ++i) {
      unsigned char meta[kMetaBytes];
      read(meta, offset, kMetaBytes, "the record of grid " + std::to_string(i));
      Record r;
      r.gridBytes = read_le<uint64_t>(meta + 0);
      const uint64_t fileSize = read_le<uint64_t>(meta + 8);
      r.type = read_le<uint32_t>(meta + 32);
      r.cls = read_le<uint32_t>(meta + 36);
      const uint32_t nameBytes = read_le<uint32_t>(meta + 136);
      if (fileSize != r.gridBytes) throw InputError(at + "grid " + std::to_string(i) + "'s record gives two sizes for an uncompressed grid");
      if (nameBytes == 0 || nameBytes > kNameBytesMax) throw InputError(at + "grid " + std::to_string(i) + "'s record has a name of " + std::to_string(nameBytes) + " bytes");
      std::vector<unsigned char> name(nameBytes);
      read(name.data(), offset + kMetaBytes, nameBytes, "the name of grid " + std::to_string(i));
      r.name.assign(reinterpret_cast<const char*>(name.data()), strnlen(reinterpret_cast<const char*>(name.data()), nameBytes));
      offset += kMetaBytes + nameBytes;
      records.push_back(r);
    }
    for (const Record& r : records) {
      if (r.name == gridName) {
        const std::string what = "grid \"" + r.name + "\"";
        if (r.type != PNANOVDB_GRID_TYPE_FLOAT)
          throw InputError(at + what + " holds " + grid_type_name(r.type) + " values; a medium's density needs a float grid");
        if (r.cls != PNANOVDB_GRID_CLASS_FOG_VOLUME && r.cls != PNANOVDB_GRID_CLASS_UNKNOWN)
          throw InputError(at + what + " is a " + grid_class_name(r.cls) + ", not a fog volume");
        if (r.gridBytes % 32 != 0 || r.gridBytes < PNANOVDB_GRID_SIZE + PNANOVDB_TREE_SIZE || r.gridBytes > (uint64_t(1) << 32) - 32)
          throw InputError(at + what + " has a size of " + std::to_string(r.gridBytes) + " bytes, which no NanoVDB grid wavepath reads has");
        DensityGrid g;
        g.file = path;
        g.name = r.name;
        g.words.resize(r.gridBytes / 4);
        read(reinterpret_cast<unsigned char*>(g.words.data()), offset, r.gridBytes, what);
        check_density_grid(g);
        return g;
      }
      names.push_back(r.name);
      offset += r.gridBytes;
      if (offset > fileBytes) throw InputError(at + "truncated: grid \"" + r.name + "\" runs past the end of the file");
    }
  }
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "\"" : ", \"") + n + "\"";
  throw InputError(at + "no grid named \"" + gridName + "\"" + "; it holds " + list + did_you_mean(gridName, names));
}

DensityGrid read_nanovdb(const std::string& path, const std::string& gridName, const std::string& where) {
  try {
    return read_grid(path, gridName);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (" + where + ")");
  }
}

void check_density_grid(DensityGrid& g) {
  const std::string at = g.file + ": grid \"" + g.name + "\": ";
  const pnanovdb_buf_t buf{g.words.data(), g.words.size()};
  const uint64_t bytes = uint64_t(g.words.size()) * 4u;
  pnanovdb_grid_handle_t grid{};
  if (pnanovdb_grid_get_magic(buf, grid) != PNANOVDB_MAGIC_NUMBER) throw InputError(at + "its bytes do not start with NanoVDB's magic number");
  if (pnanovdb_version_get_major(pnanovdb_grid_get_version(buf, grid)) != kFormatMajor)
    throw InputError(at + "written by NanoVDB " + version_string(pnanovdb_grid_get_version(buf, grid)) + "; wavepath reads version " +
                     std::to_string(kFormatMajor) + ".x");
  if (pnanovdb_grid_get_grid_size(buf, grid) != bytes) throw InputError(at + "its size disagrees with its file record");
  if (pnanovdb_grid_get_grid_type(buf, grid) != PNANOVDB_GRID_TYPE_FLOAT)
    throw InputError(at + "holds " + grid_type_name(pnanovdb_grid_get_grid_type(buf, grid)) + " values; a medium's density needs a float grid");
  const uint32_t cls = pnanovdb_grid_get_grid_class(buf, grid);
  if (cls != PNANOVDB_GRID_CLASS_FOG_VOLUME && cls != PNANOVDB_GRID_CLASS_UNKNOWN)
    throw InputError(at + "is a " + grid_class_name(cls) + ", not a fog volume");

  // The nodes of each level lie back to back within the grid.
  const pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(buf, grid);
  const uint64_t treeAt = tree.address.byte_offset;
  const uint64_t rootAt = treeAt + pnanovdb_tree_get_node_offset_root(buf, tree);
  const pnanovdb_root_handle_t root = pnanovdb_tree_get_root(buf, tree);
  const uint32_t tiles = pnanovdb_root_get_tile_count(buf, root);
  const uint32_t T = PNANOVDB_GRID_TYPE_FLOAT;
  if (!fits(rootAt, 1, PNANOVDB_GRID_TYPE_GET(T, root_size), bytes) ||
      !fits(rootAt + PNANOVDB_GRID_TYPE_GET(T, root_size), tiles, PNANOVDB_GRID_TYPE_GET(T, root_tile_size), bytes))
    throw InputError(at + "its root node lies outside the grid");
  if (tiles > NANOVDB_ROOT_TILES_MAX)
    throw InputError(at + "its root has " + std::to_string(tiles) + " tiles; wavepath reads grids of at most " +
                     std::to_string(NANOVDB_ROOT_TILES_MAX) + " (each spans 4096 voxels along each axis)");
  struct Level {
    uint64_t offset;
    uint32_t count, size;
    const char* name;
  };
  const Level levels[3] = {
      {pnanovdb_tree_get_node_offset_leaf(buf, tree), pnanovdb_tree_get_node_count_leaf(buf, tree), PNANOVDB_GRID_TYPE_GET(T, leaf_size), "leaf"},
      {pnanovdb_tree_get_node_offset_lower(buf, tree), pnanovdb_tree_get_node_count_lower(buf, tree), PNANOVDB_GRID_TYPE_GET(T, lower_size), "lower"},
      {pnanovdb_tree_get_node_offset_upper(buf, tree), pnanovdb_tree_get_node_count_upper(buf, tree), PNANOVDB_GRID_TYPE_GET(T, upper_size), "upper"}};
  for (const Level& l : levels)
    if (l.count > 0 && !fits(treeAt + l.offset, l.count, l.size, bytes))
      throw InputError(at + "its " + std::to_string(l.count) + " " + l.name + " nodes lie outside the grid");

  // The map, and the box of active values.
  const pnanovdb_map_handle_t map = pnanovdb_grid_get_map(buf, grid);
  glm::dmat4 toIndex(1.0);
  glm::dvec3 vec;
  for (uint32_t r = 0; r < 3; ++r) {
    vec[r] = pnanovdb_map_get_vecd(buf, map, r);
    for (uint32_t c = 0; c < 3; ++c) toIndex[c][r] = pnanovdb_map_get_invmatd(buf, map, 3 * r + c);
  }
  toIndex[3] = glm::dvec4(-glm::dvec3(toIndex * glm::dvec4(vec, 0.0)), 1.0);
  bool finite = true;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) finite = finite && std::isfinite(toIndex[c][r]);
  if (!finite || !(std::abs(glm::determinant(glm::dmat3(toIndex))) > 0.0))
    throw InputError(at + "its map from world to index space is not an invertible affine map");
  g.worldToIndex = toIndex;
  const pnanovdb_coord_t lo = pnanovdb_root_get_bbox_min(buf, root), hi = pnanovdb_root_get_bbox_max(buf, root);
  g.indexMin = glm::ivec3(lo.x, lo.y, lo.z);
  g.indexMax = glm::ivec3(hi.x, hi.y, hi.z);
  g.activeVoxels = pnanovdb_tree_get_voxel_count(buf, tree);
  g.leaves = levels[0].count;
  if (!(g.indexMin.x <= g.indexMax.x && g.indexMin.y <= g.indexMax.y && g.indexMin.z <= g.indexMax.z))
    throw InputError(at + "it holds no active voxels");
  const glm::ivec3 limit(1 << 30);
  if (glm::any(glm::lessThan(g.indexMin, -limit)) || glm::any(glm::greaterThan(g.indexMax, limit)))
    throw InputError(at + "its active voxels span more than the 2^31 voxels wavepath indexes");

  // Every value a lookup can return is finite; the largest bounds them.
  float most = std::max(0.0f, pnanovdb_read_float(buf, pnanovdb_address_offset(root.address, PNANOVDB_GRID_TYPE_GET(T, root_off_background))));
  auto value = [&](pnanovdb_address_t a, const char* where) {
    const float v = pnanovdb_read_float(buf, a);
    if (!std::isfinite(v)) throw InputError(at + "a " + where + " holds a value that is not finite (" + std::to_string(v) + ")");
    most = std::max(most, v);
  };
  for (uint32_t i = 0; i < levels[0].count; ++i) {
    pnanovdb_leaf_handle_t leaf{pnanovdb_address_offset64(tree.address, levels[0].offset + uint64_t(i) * levels[0].size)};
    for (uint32_t n = 0; n < 512u; ++n) value(pnanovdb_leaf_get_table_address(T, buf, leaf, n), "voxel");
  }
  for (uint32_t i = 0; i < levels[1].count; ++i) {
    pnanovdb_lower_handle_t lower{pnanovdb_address_offset64(tree.address, levels[1].offset + uint64_t(i) * levels[1].size)};
    for (uint32_t n = 0; n < 4096u; ++n)
      if (!pnanovdb_lower_get_child_mask(buf, lower, n)) value(pnanovdb_lower_get_table_address(T, buf, lower, n), "tile");
  }
  for (uint32_t i = 0; i < levels[2].count; ++i) {
    pnanovdb_upper_handle_t upper{pnanovdb_address_offset64(tree.address, levels[2].offset + uint64_t(i) * levels[2].size)};
    for (uint32_t n = 0; n < 32768u; ++n)
      if (!pnanovdb_upper_get_child_mask(buf, upper, n)) value(pnanovdb_upper_get_table_address(T, buf, upper, n), "tile");
  }
  for (uint32_t i = 0; i < tiles; ++i) {
    pnanovdb_root_tile_handle_t tile = pnanovdb_root_get_tile(T, root, i);
    if (pnanovdb_root_tile_get_child(buf, tile) == 0) value(pnanovdb_root_tile_get_value_address(T, buf, tile), "root tile");
  }
  g.maxDensity = most;
}

std::vector<float> majorant_grid(const DensityGrid& g, glm::uvec3 cells) {
  const pnanovdb_buf_t buf{g.words.data(), g.words.size()};
  const uint32_t T = PNANOVDB_GRID_TYPE_FLOAT;
  std::vector<float> out(size_t(cells.x) * cells.y * cells.z, 0.0f);
  const glm::dvec3 lo = glm::dvec3(g.indexMin) - 1.0, hi = glm::dvec3(g.indexMax) + 1.0;
  const glm::dvec3 size = (hi - lo) / glm::dvec3(cells);
  // Value v at the voxels [a, b] (inclusive): lookups within (a - 1, b + 1)
  // blend it in.
  auto splat = [&](glm::ivec3 a, glm::ivec3 b, float v) {
    if (!(v > 0.0f)) return;
    glm::ivec3 c0, c1;
    for (int k = 0; k < 3; ++k) {
      const double from = std::max(double(a[k]) - 1.0, lo[k]), to = std::min(double(b[k]) + 1.0, hi[k]);
      if (from > to) return;
      c0[k] = std::clamp(int(std::floor((from - lo[k]) / size[k])), 0, int(cells[k]) - 1);
      c1[k] = std::clamp(int(std::floor((to - lo[k]) / size[k])), 0, int(cells[k]) - 1);
    }
    for (int z = c0.z; z <= c1.z; ++z)
      for (int y = c0.y; y <= c1.y; ++y)
        for (int x = c0.x; x <= c1.x; ++x) {
          float& m = out[size_t(x) + cells.x * (size_t(y) + cells.y * size_t(z))];
          m = std::max(m, v);
        }
  };
  const pnanovdb_grid_handle_t grid{};
  const pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(buf, grid);
  const pnanovdb_root_handle_t root = pnanovdb_tree_get_root(buf, tree);
  auto origin = [](pnanovdb_coord_t c) { return glm::ivec3(c.x, c.y, c.z); };
  const uint32_t leafCount = pnanovdb_tree_get_node_count_leaf(buf, tree), lowerCount = pnanovdb_tree_get_node_count_lower(buf, tree),
                 upperCount = pnanovdb_tree_get_node_count_upper(buf, tree);
  for (uint32_t i = 0; i < leafCount; ++i) {
    pnanovdb_leaf_handle_t leaf{pnanovdb_address_offset64(
        tree.address, pnanovdb_tree_get_node_offset_leaf(buf, tree) + uint64_t(i) * PNANOVDB_GRID_TYPE_GET(T, leaf_size))};
    const glm::ivec3 o = origin(pnanovdb_leaf_get_bbox_min(buf, leaf)) & ~7;
    for (uint32_t n = 0; n < 512u; ++n) {
      const glm::ivec3 v = o + glm::ivec3(int(n >> 6), int((n >> 3) & 7u), int(n & 7u));
      splat(v, v, pnanovdb_read_float(buf, pnanovdb_leaf_get_table_address(T, buf, leaf, n)));
    }
  }
  // Tiles: constant values over 8^3 voxels (lower nodes), 128^3 (upper)
  // and 4096^3 (root).
  for (uint32_t i = 0; i < lowerCount; ++i) {
    pnanovdb_lower_handle_t lower{pnanovdb_address_offset64(
        tree.address, pnanovdb_tree_get_node_offset_lower(buf, tree) + uint64_t(i) * PNANOVDB_GRID_TYPE_GET(T, lower_size))};
    const glm::ivec3 o = origin(pnanovdb_lower_get_bbox_min(buf, lower)) & ~127;
    for (uint32_t n = 0; n < 4096u; ++n) {
      if (pnanovdb_lower_get_child_mask(buf, lower, n)) continue;
      const glm::ivec3 a = o + 8 * glm::ivec3(int(n >> 8), int((n >> 4) & 15u), int(n & 15u));
      splat(a, a + 7, pnanovdb_read_float(buf, pnanovdb_lower_get_table_address(T, buf, lower, n)));
    }
  }
  for (uint32_t i = 0; i < upperCount; ++i) {
    pnanovdb_upper_handle_t upper{pnanovdb_address_offset64(
        tree.address, pnanovdb_tree_get_node_offset_upper(buf, tree) + uint64_t(i) * PNANOVDB_GRID_TYPE_GET(T, upper_size))};
    const glm::ivec3 o = origin(pnanovdb_upper_get_bbox_min(buf, upper)) & ~4095;
    for (uint32_t n = 0; n < 32768u; ++n) {
      if (pnanovdb_upper_get_child_mask(buf, upper, n)) continue;
      const glm::ivec3 a = o + 128 * glm::ivec3(int(n >> 10), int((n >> 5) & 31u), int(n & 31u));
      splat(a, a + 127, pnanovdb_read_float(buf, pnanovdb_upper_get_table_address(T, buf, upper, n)));
    }
  }
  const uint32_t tiles = pnanovdb_root_get_tile_count(buf, root);
  for (uint32_t i = 0; i < tiles; ++i) {
    pnanovdb_root_tile_handle_t tile = pnanovdb_root_get_tile(T, root, i);
    if (pnanovdb_root_tile_get_child(buf, tile) != 0) continue;
    const uint64_t key = pnanovdb_root_tile_get_key(buf, tile);
    const glm::ivec3 a(int32_t(uint32_t((key >> 42u) & 0x1fffffu) << 12u), int32_t(uint32_t((key >> 21u) & 0x1fffffu) << 12u),
                       int32_t(uint32_t(key & 0x1fffffu) << 12u));
    splat(a, a + 4095, pnanovdb_read_float(buf, pnanovdb_root_tile_get_value_address(T, buf, tile)));
  }
  // Between the nodes, the background.
  const float background = pnanovdb_read_float(buf, pnanovdb_address_offset(root.address, PNANOVDB_GRID_TYPE_GET(T, root_off_background)));
  if (background > 0.0f)
    for (float& m : out) m = std::max(m, background);
  return out;
}

glm::uvec3 default_majorant_cells(const DensityGrid& g) {
  const glm::ivec3 extent = g.indexMax - g.indexMin + 3;
  glm::uvec3 cells;
  for (int k = 0; k < 3; ++k) cells[k] = std::clamp(uint32_t((extent[k] + 7) / 8), 1u, MAJORANT_GRID_CELLS_MAX);
  return cells;
}

}  // namespace wp
