// compile_media.cpp — compile_scene's participating media: each medium's
// record, and the NanoVDB grids and majorant grids that grid media read.
#include <glm/glm.hpp>
#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "render/compile_parts.h"
#include "util/error.h"

namespace wp {

// A medium's record. A grid medium's grid and majorant grid go to the end
// of `volumeWords` (BINDING_VOLUMES), each grid once however many media
// read it.
static shader::Medium pack_medium(const SceneMedium& in, std::vector<uint32_t>& volumeWords,
                                  std::map<const DensityGrid*, uint32_t>& gridAt) {
  shader::Medium m{};  // a vacuum: kind 0, nothing in it
  if (in.kind == MEDIUM_VACUUM) return m;
  m.info = glm::uvec4(in.kind, 0u, 0u, 0u);
  const glm::vec3 total = in.sigmaA + in.sigmaS + in.sigmaN;
  m.sigmaA = glm::vec4(in.sigmaA, in.g);
  // Homogeneous: the majorant. Grid: what scales the majorant grid's
  // densities into majorants.
  m.sigmaS = glm::vec4(in.sigmaS, std::max(total.x, std::max(total.y, total.z)));
  m.sigmaN = glm::vec4(in.sigmaN, 0.0f);
  if (in.kind != MEDIUM_NANOVDB) return m;
  const DensityGrid& g = *in.grid;
  auto placed = gridAt.find(&g);
  if (placed == gridAt.end()) {
    placed = gridAt.emplace(&g, uint32_t(volumeWords.size())).first;
    volumeWords.insert(volumeWords.end(), g.words.begin(), g.words.end());
  }
  const glm::uvec3 cells = majorant_cells(in);
  const std::vector<float> majorants = majorant_grid(g, cells);
  m.info = glm::uvec4(in.kind, placed->second * 4u, uint32_t(volumeWords.size()), cells.x | (cells.y << 10u) | (cells.z << 20u));
  for (float v : majorants) volumeWords.push_back(glm::floatBitsToUint(v));
  if (uint64_t(volumeWords.size()) * 4u > 0xffffffffull)
    throw InputError(g.file + ": the scene's grids take more than the 4 GiB the kernels address");
  const glm::dmat4 toIndex = g.worldToIndex * glm::inverse(glm::dmat4(in.gridToScene));
  m.toIndex0 = glm::vec4(glm::row(toIndex, 0));
  m.toIndex1 = glm::vec4(glm::row(toIndex, 1));
  m.toIndex2 = glm::vec4(glm::row(toIndex, 2));
  m.boundsLo = glm::vec4(glm::vec3(g.indexMin) - 1.0f, 0.0f);
  m.boundsHi = glm::vec4(glm::vec3(g.indexMax) + 1.0f, 0.0f);
  return m;
}

void compile_media(const Scene& scene, CompiledScene& out) {
  if (scene.media.size() >= MEDIA_MAX) throw InputError(scene.sourcePath + ": more than " + std::to_string(MEDIA_MAX - 1) + " media");
  out.media.push_back(shader::Medium{});  // the vacuum
  std::map<const DensityGrid*, uint32_t> gridAt;
  for (const SceneMedium& m : scene.media) out.media.push_back(pack_medium(m, out.volumeWords, gridAt));
  out.params.media = glm::uvec4(scene.cameraMedium == WP_INVALID ? 0u : scene.cameraMedium + 1u, 0u, 0u, 0u);
}

bool scene_has_media(const Scene& scene) {
  return !scene.media.empty() || std::any_of(scene.materials.begin(), scene.materials.end(), [](const SceneMaterial& m) {
    return m.boundsMedia || m.kind == MAT_INTERFACE;
  });
}

uint32_t media_features(const Scene& scene) {
  uint32_t features = 0u;
  if (scene_has_media(scene)) features |= KIND_BIT(FEATURE_MEDIA);
  if (std::any_of(scene.media.begin(), scene.media.end(), [](const SceneMedium& m) { return m.kind == MEDIUM_NANOVDB; }))
    features |= KIND_BIT(FEATURE_MEDIA_GRID);
  return features;
}

}  // namespace wp
