// compile_materials.cpp — compile_scene's materials and textures: the
// records the kernels' material_at and texture_eval read, and what the other
// parts weigh by a material's emission.
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>
#include <vector>

#include "render/compile_parts.h"
#include "scene/kinds.h"
#include "scene/transform.h"
#include "util/error.h"

namespace wp {

glm::vec3 texture_mean(const std::vector<shader::Texture>& textures, const std::vector<glm::uvec2>& texels, uint32_t index) {
  const shader::Texture& t = textures.at(index);
  switch (t.info.x & TEX_TYPE_MASK) {
    case TEX_CHECKER:
      return 0.5f * (texture_mean(textures, texels, t.info.y) + texture_mean(textures, texels, t.info.z));
    case TEX_MARBLE:
      return 0.5f * (glm::vec3(t.color0) + glm::vec3(t.color1));
    case TEX_IMAGE: {
      glm::dvec3 sum(0.0);
      size_t n = size_t(t.info.z) * t.info.w;
      for (size_t i = 0; i < n; ++i) sum += glm::dvec3(texel_rgb(texels[t.info.y + i]));
      return glm::vec3(sum / double(std::max<size_t>(n, 1))) * glm::vec3(t.color0);
    }
    default:
      return glm::vec3(t.color0);
  }
}

PackedTextures pack_textures(const Scene& scene) {
  PackedTextures out;
  std::vector<uint32_t> firstTexel;
  for (const LinearImage& img : scene.images) {
    firstTexel.push_back(uint32_t(out.texels.size()));
    for (size_t i = 0; i < img.pixels.size(); ++i) {
      const glm::vec3 c = img.pixels[i];
      const float alpha = img.alpha.empty() ? 1.0f : img.alpha[i];
      out.texels.emplace_back(glm::packHalf2x16(glm::vec2(c.x, c.y)), glm::packHalf2x16(glm::vec2(c.z, alpha)));
    }
  }
  for (const SceneTexture& in : scene.textures) {
    shader::Texture t{};
    t.info = glm::uvec4(in.kind | (in.solid ? TEX_SOLID : 0u) | (in.secondUvSet ? TEX_UV1 : 0u) | in.wrapU << TEX_WRAP_U_SHIFT |
                            in.wrapV << TEX_WRAP_V_SHIFT,
                        0u, 0u, 0u);
    rows_3x4(in.mapping, t.map0, t.map1, t.map2);
    switch (in.kind) {
      case TEX_CHECKER:
        t.info.y = in.even;
        t.info.z = in.odd;
        t.color0.w = in.scale;
        break;
      case TEX_MARBLE:
        t.color0 = glm::vec4(in.color, in.scale);
        t.color1 = glm::vec4(in.veins, 0.0f);
        break;
      case TEX_IMAGE: {
        const LinearImage& img = scene.images.at(in.image);
        t.info.y = firstTexel[in.image];
        t.info.z = uint32_t(img.width);
        t.info.w = uint32_t(img.height);
        t.color0 = glm::vec4(in.color, in.alpha);
        break;
      }
      case TEX_FRESNEL: t.color0.x = in.ior; break;
      default: t.color0 = glm::vec4(in.color, in.alpha); break;
    }
    out.textures.push_back(t);
  }
  return out;
}

// The module's record (scene/materials/) with the surface's properties.
static shader::Material pack_material(const SceneMaterial& in) {
  shader::Material m = in.record;
  m.info.x = in.kind;
  m.info.z = in.emission;
  m.children.z = in.normalMap;
  m.children.w = WP_INVALID;  // the sort key (shade_classes)
  if (in.kind != MAT_BLEND && !is_layer(in.kind)) m.children.x = glm::floatBitsToUint(in.alphaCutoff);
  // Media: index 0 is the vacuum, the scene's follow (compile_media).
  auto medium = [](uint32_t i) { return i == WP_INVALID ? 0u : i + 1u; };
  m.media = in.boundsMedia ? glm::uvec4(medium(in.interior), medium(in.exterior), 0u, 0u) : glm::uvec4(WP_INVALID, WP_INVALID, 0u, 0u);
  return m;
}

std::vector<double> material_radiance(const Scene& scene, const PackedTextures& packed) {
  std::vector<double> radiance(scene.materials.size(), 0.0);
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    uint32_t tex = scene.materials[m].emission;
    if (tex != WP_INVALID) radiance[m] = luminance(texture_mean(packed.textures, packed.texels, tex));
  }
  return radiance;
}

std::vector<double> compile_materials(const Scene& scene, CompiledScene& out) {
  PackedTextures packed = pack_textures(scene);
  std::vector<double> materialRadiance = material_radiance(scene, packed);
  for (const SceneMaterial& m : scene.materials) out.materials.push_back(pack_material(m));
  // The float tables start with the sheen's albedo (bindings.glsl).
  out.floatTables.assign(std::begin(shader::SHEEN_ALBEDO), std::end(shader::SHEEN_ALBEDO));
  out.textures = std::move(packed.textures);
  out.texels = std::move(packed.texels);
  return materialRadiance;
}

void flag_triangle_materials(const Scene& scene, const std::vector<double>& materialRadiance, CompiledScene& out) {
  // What the traversal must know of a triangle's material: whether its back
  // is there, whether its alpha cuts it (an emitter is never cut: light
  // sampling could not see the cuts).
  if (scene.materials.size() > TRIANGLE_MATERIAL_MASK) throw RenderError("the scene has more materials than wavepath can index");
  for (shader::Triangle& t : out.triangles) {
    if (is_placeholder(t)) continue;
    const SceneMaterial& m = scene.materials[t.material];
    if (!m.doubleSided) t.material |= TRIANGLE_ONE_SIDED;
    if (m.alphaCutoff != 0.0f && materialRadiance[t.material & TRIANGLE_MATERIAL_MASK] <= 0.0) t.material |= TRIANGLE_CUTOUT;
  }
}

}  // namespace wp
