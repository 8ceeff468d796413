#include "scene/scene.h"

#include <glm/gtc/packing.hpp>

#include "scene/texture_image.h"
#include "util/error.h"

namespace wp {

const char* const kIntegratorNames =
    "normals, ao, path tracer mats, path tracer nee, path tracer mis, path tracer mixture or path tracer hemisphere";

std::optional<IntegratorKind> integrator_named(const std::string& name) {
  static const std::pair<const char*, IntegratorKind> kKinds[] = {
      {"path tracer mis", IntegratorKind::PathMis},   {"path tracer nee", IntegratorKind::PathNee},
      {"path tracer mats", IntegratorKind::PathMats}, {"path tracer mixture", IntegratorKind::PathMixture},
      {"path tracer hemisphere", IntegratorKind::PathHemisphere},
      {"normals", IntegratorKind::Normals},           {"ao", IntegratorKind::AmbientOcclusion}};
  for (const auto& [n, kind] : kKinds) {
    if (name == n) return kind;
  }
  return std::nullopt;
}

std::optional<SamplerKind> sampler_named(const std::string& name) {
  if (name == "independent") return SamplerKind::Independent;
  if (name == "cmj") return SamplerKind::Cmj;
  return std::nullopt;
}

shader::Texture constant_texture(glm::vec3 color) {
  shader::Texture t{};
  t.info.x = TEX_CONSTANT;
  t.color0 = glm::vec4(color, 0.0f);
  t.map0 = glm::vec4(1, 0, 0, 0);
  t.map1 = glm::vec4(0, 1, 0, 0);
  t.map2 = glm::vec4(0, 0, 1, 0);
  return t;
}

uint32_t add_texture(Scene& scene, const shader::Texture& texture) {
  scene.textures.push_back(texture);
  return uint32_t(scene.textures.size() - 1);
}

uint32_t add_lambertian(Scene& scene, glm::vec3 albedo, const std::string& name) {
  shader::Material m{};
  m.info = glm::uvec4(MAT_LAMBERTIAN, add_texture(scene, constant_texture(albedo)), WP_INVALID, WP_INVALID);
  m.children = glm::uvec4(WP_INVALID);
  scene.materials.push_back(m);
  scene.materialNames.push_back(name);
  return uint32_t(scene.materials.size() - 1);
}

shader::Texture image_texture(Scene& scene, const std::string& path, const std::string& where) {
  LinearImage img;
  try {
    img = load_linear_image(path);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + (where.empty() ? "" : " (" + where + ")"));
  }
  shader::Texture t = constant_texture(glm::vec3(0.0f));
  t.info = glm::uvec4(TEX_IMAGE, uint32_t(scene.texels.size()), uint32_t(img.width), uint32_t(img.height));
  scene.texels.reserve(scene.texels.size() + img.pixels.size());
  for (const glm::vec3& c : img.pixels) {
    scene.texels.emplace_back(glm::packHalf2x16(glm::vec2(c.x, c.y)), glm::packHalf2x16(glm::vec2(c.z, 1.0f)));
  }
  return t;
}

uint32_t add_image_texture(Scene& scene, const std::string& path, const std::string& where) {
  return add_texture(scene, image_texture(scene, path, where));
}

}  // namespace wp
