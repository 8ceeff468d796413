#include "scene/scene.h"

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

SceneTexture constant_texture(glm::vec3 color) {
  SceneTexture t;
  t.kind = TEX_CONSTANT;
  t.color = color;
  return t;
}

uint32_t add_texture(Scene& scene, const SceneTexture& texture) {
  scene.textures.push_back(texture);
  return uint32_t(scene.textures.size() - 1);
}

uint32_t add_lambertian(Scene& scene, glm::vec3 albedo, const std::string& name) {
  SceneMaterial m;
  m.kind = MAT_LAMBERTIAN;
  m.name = name;
  m.albedo = add_texture(scene, constant_texture(albedo));
  scene.materials.push_back(m);
  return uint32_t(scene.materials.size() - 1);
}

SceneTexture image_texture(Scene& scene, const std::string& path, const std::string& where) {
  LinearImage img;
  try {
    img = load_linear_image(path);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + (where.empty() ? "" : " (" + where + ")"));
  }
  SceneTexture t;
  t.kind = TEX_IMAGE;
  t.image = uint32_t(scene.images.size());
  scene.images.push_back(std::move(img));
  return t;
}

uint32_t add_image_texture(Scene& scene, const std::string& path, const std::string& where) {
  return add_texture(scene, image_texture(scene, path, where));
}

}  // namespace wp
