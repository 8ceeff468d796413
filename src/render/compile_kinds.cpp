// compile_kinds.cpp — what compiling out and sorting by material need to
// know of a compiled scene: the kinds and features it uses (kinds.glsl),
// and the shade classes its materials fall into.
#include <glm/glm.hpp>

#include <algorithm>
#include <vector>

#include "render/compile_parts.h"
#include "scene/kinds.h"
#include "scene/materials/material_module.h"

namespace wp {

namespace {

// The kinds a compiled scene uses (SceneParams.kinds; kinds.glsl), before its
// empty arrays get their placeholder element: every material's and texture's
// kind, the light kinds of the emitter table's prims, and the features.
// `environment`: an environment map replaces the background. The media's
// features are added by compile_kinds, the sampler's and the integrator's
// with the render parameters (compiled_scene.cpp).
glm::uvec4 scene_kinds(const CompiledScene& cs, bool spheres, bool environment) {
  glm::uvec4 k(0u);
  for (const shader::Material& m : cs.materials) {
    k.x |= KIND_BIT(m.info.x);
    if (m.children.z != WP_INVALID) k.w |= KIND_BIT(FEATURE_NORMAL_MAPS);
    if (m.info.z != WP_INVALID && (cs.textures[m.info.z].info.x & TEX_TYPE_MASK) != TEX_CONSTANT) k.w |= KIND_BIT(FEATURE_EMISSION_TEXTURES);
    const MaterialModule& module = material_module(m.info.x);
    if (module.features) k.w |= module.features(m);
  }
  for (const shader::Texture& t : cs.textures) k.y |= KIND_BIT(t.info.x & TEX_TYPE_MASK);
  for (const shader::Emitter& e : cs.emitters) {
    const uint32_t prim = e.prim;
    if (prim == EMITTER_ENVIRONMENT) k.z |= KIND_BIT(LIGHT_ENVIRONMENT);
    else if (prim & EMITTER_POINT_BIT) k.z |= KIND_BIT(punctual_light_kind(cs.pointLights[prim & ~EMITTER_POINT_BIT]));
    else if (prim & HIT_SPHERE_BIT) k.z |= KIND_BIT(LIGHT_SPHERE);
    else k.z |= KIND_BIT(LIGHT_AREA);
  }
  if (environment) k.z |= KIND_BIT(LIGHT_ENVIRONMENT);
  if (spheres) k.w |= KIND_BIT(FEATURE_SPHERES);
  if (!cs.triangleShading.empty()) k.w |= KIND_BIT(FEATURE_SHADING_DATA);
  if (!cs.triangleVertexData.empty()) k.w |= KIND_BIT(FEATURE_VERTEX_DATA);
  if (!cs.instances.empty()) k.w |= KIND_BIT(FEATURE_INSTANCES);
  for (const shader::Triangle& t : cs.triangles) {
    if (is_placeholder(t)) continue;
    if (t.material & TRIANGLE_ONE_SIDED) k.w |= KIND_BIT(FEATURE_ONE_SIDED);
    if (t.material & TRIANGLE_CUTOUT) k.w |= KIND_BIT(FEATURE_CUTOUTS);
  }
  return k;
}

// The texture kinds texture t's lookup runs: its own, and a checker's
// squares' (nested up to TEXTURE_MAX_NESTING deep, as texture_eval follows).
uint32_t lookup_kinds(const std::vector<shader::Texture>& textures, uint32_t t, int depth = 0) {
  if (t == WP_INVALID || t >= textures.size()) return 0u;
  const shader::Texture& tex = textures[t];
  const uint32_t kind = tex.info.x & TEX_TYPE_MASK;
  if (kind != TEX_CHECKER || depth >= TEXTURE_MAX_NESTING) return KIND_BIT(kind);
  return KIND_BIT(kind) | lookup_kinds(textures, tex.info.y, depth + 1) | lookup_kinds(textures, tex.info.z, depth + 1);
}

// The kinds a ray that hits material m needs for its BSDF: x its material
// kinds (a blend's children's too), y the texture kinds it looks up. (Its
// emission's kinds every shade kernel has: shade_classes.)
glm::uvec2 bsdf_kinds(const CompiledScene& cs, uint32_t m, int depth = 0) {
  const shader::Material& mat = cs.materials[m];
  glm::uvec2 k(KIND_BIT(mat.info.x),
               lookup_kinds(cs.textures, mat.info.y) | lookup_kinds(cs.textures, mat.info.w) | lookup_kinds(cs.textures, mat.children.z));
  const MaterialModule& module = material_module(mat.info.x);
  if (module.lookups)
    for (uint32_t t : module.lookups(mat)) k.y |= lookup_kinds(cs.textures, t);
  // The loader bounds a blend's lobes (BSDF_MAX_LOBES), and so its depth.
  if (mat.info.x == MAT_BLEND && depth < int(BSDF_MAX_LOBES))
    k |= bsdf_kinds(cs, mat.children.x, depth + 1) | bsdf_kinds(cs, mat.children.y, depth + 1);
  if (is_layer(mat.info.x) && depth < int(BSDF_MAX_LOBES)) k |= bsdf_kinds(cs, mat.children.x, depth + 1);  // its base
  return k;
}

// Groups the materials that primitives use into shade classes by the kinds
// they need (bsdf_kinds), in order of first use, and writes each
// material's sort key (class + 1) to its children.w. Past SHADE_CLASSES_MAX
// classes, the rest share the last, which needs all of their kinds. Fills
// shadeClasses and shadeCommonKinds.
void shade_classes(CompiledScene& cs, uint32_t environmentTexture) {
  uint32_t common = lookup_kinds(cs.textures, environmentTexture);
  for (const shader::Material& m : cs.materials) common |= lookup_kinds(cs.textures, m.info.z);  // emission, hit or sampled
  cs.shadeCommonKinds = common;
  std::vector<bool> used(cs.materials.size(), false);
  for (const shader::Triangle& t : cs.triangles)
    if (!is_placeholder(t)) used[t.material & TRIANGLE_MATERIAL_MASK] = true;
  for (const shader::Sphere& sp : cs.spheres) used[sp.material] = true;
  for (uint32_t m = 0; m < cs.materials.size(); ++m) {
    cs.materials[m].children.w = SORT_KEY_MISS + 1u;  // for unused materials: any class will do
    if (!used[m]) continue;
    const glm::uvec2 kinds = bsdf_kinds(cs, m);
    auto found = std::find(cs.shadeClasses.begin(), cs.shadeClasses.end(), kinds);
    uint32_t c = uint32_t(found - cs.shadeClasses.begin());
    if (found == cs.shadeClasses.end()) {
      if (c < SHADE_CLASSES_MAX) {
        cs.shadeClasses.push_back(kinds);
      } else {
        c = SHADE_CLASSES_MAX - 1;
        cs.shadeClasses[c] |= kinds;
      }
    }
    cs.materials[m].children.w = c + 1u;
  }
}

}  // namespace

void compile_kinds(const Scene& scene, CompiledScene& out) {
  glm::uvec4 kinds = scene_kinds(out, !scene.spheres.empty(), scene.environment != WP_INVALID);
  kinds.w |= media_features(scene);
  out.params.kinds = kinds;
  shade_classes(out, scene.environment);
}

}  // namespace wp
