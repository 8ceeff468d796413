// compile_lights.cpp — compile_scene's lights and the environment: the
// punctual lights' records, the emitter table that next-event estimation
// picks from, and the environment map's sampling distribution.
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "render/compile_parts.h"

namespace wp {

std::vector<float> environment_cdf(const shader::Texture& t, const std::vector<glm::uvec2>& texels) {
  const int w = int(t.info.z), h = int(t.info.w);
  auto lum = [&](int x, int y) { return double(luminance(texel_rgb(texels[t.info.y + size_t(y) * size_t(w) + size_t(x)]))); };
  std::vector<double> weight(size_t(w) * size_t(h));
  double total = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double m = 0.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) m = std::max(m, lum((x + dx + w) % w, std::clamp(y + dy, 0, h - 1)));
      weight[size_t(y) * size_t(w) + size_t(x)] = m;
      total += m;
    }
  double floor = total > 0.0 ? 1e-3 * total / double(weight.size()) : 1.0;
  std::vector<float> cdf(size_t(h + 1) + size_t(h) * size_t(w + 1));
  std::vector<double> rowSum(size_t(h), 0.0);
  for (int y = 0; y < h; ++y) {
    double sinTheta = std::sin(WP_PI * (double(y) + 0.5) / double(h));
    size_t off = size_t(h + 1) + size_t(y) * size_t(w + 1);
    double acc = 0.0;
    std::vector<double> partial(size_t(w) + 1, 0.0);
    for (int x = 0; x < w; ++x) {
      acc += (weight[size_t(y) * size_t(w) + size_t(x)] + floor) * sinTheta;
      partial[size_t(x) + 1] = acc;
    }
    for (int x = 0; x <= w; ++x) cdf[off + size_t(x)] = float(partial[size_t(x)] / acc);
    cdf[off + size_t(w)] = 1.0f;
    rowSum[size_t(y)] = acc;
  }
  double all = 0.0;
  for (double r : rowSum) all += r;
  double acc = 0.0;
  cdf[0] = 0.0f;
  for (int y = 0; y < h; ++y) {
    acc += rowSum[size_t(y)];
    cdf[size_t(y) + 1] = float(acc / all);
  }
  cdf[size_t(h)] = 1.0f;
  return cdf;
}

std::vector<shader::Emitter> build_alias_table(const std::vector<double>& weights) {
  size_t n = weights.size();
  std::vector<shader::Emitter> table(n);
  double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  std::vector<double> scaled(n);
  std::vector<uint32_t> small, large;
  for (size_t i = 0; i < n; ++i) {
    table[i].pmf = float(weights[i] / total);
    table[i].alias = uint32_t(i);
    table[i].threshold = 1.0f;
    scaled[i] = weights[i] / total * double(n);
    (scaled[i] < 1.0 ? small : large).push_back(uint32_t(i));
  }
  while (!small.empty() && !large.empty()) {
    uint32_t s = small.back();
    small.pop_back();
    uint32_t l = large.back();
    table[s].threshold = float(scaled[s]);
    table[s].alias = l;
    scaled[l] -= 1.0 - scaled[s];
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // Leftovers are 1 up to rounding: they always keep their own index.
  return table;
}

size_t compile_lights(const Scene& scene, const std::vector<double>& materialRadiance, const CompiledGeometry& geometry,
                      CompiledScene& out) {
  for (const ScenePointLight& l : scene.pointLights) {
    shader::PointLight p{glm::vec4(l.position, float(LIGHT_POINT)), glm::vec4(l.intensity, l.falloff ? 1.0f : 0.0f),
                         glm::vec4(l.direction, 0.0f)};
    if (l.kind == ScenePointLight::Kind::Directional) p.position.w = float(LIGHT_DIRECTIONAL);
    if (l.kind == ScenePointLight::Kind::Hemisphere) p.position.w = float(LIGHT_HEMISPHERE);
    if (l.kind == ScenePointLight::Kind::Spot) {
      p.position.w = float(LIGHT_SPOT);
      p.intensity.w = l.cosInner;
      p.direction.w = l.cosOuter;
    }
    out.pointLights.push_back(p);
  }

  // Emitters: every primitive whose material emits (under CS184's estimator
  // only the light-only triangles), and every point light, picked in
  // proportion to power (luminance of the mean emitted radiance times pi
  // times area; of the intensity times 4 pi).
  std::vector<double> power;
  std::vector<uint32_t> prims;
  auto emits = [&](uint32_t material, float area) {
    double p = materialRadiance[material] * WP_PI * double(area);
    return p > 0.0 ? p : 0.0;
  };
  for (size_t i = 0; i < out.triangles.size(); ++i) {
    shader::Triangle& t = out.triangles[i];
    if (is_placeholder(t)) continue;
    const bool lightOnly = i >= geometry.firstLightOnly;
    if (scene.cs184Estimator && !lightOnly) continue;
    double p = emits(t.material, 0.5f * glm::length(glm::cross(t.v1 - t.v0, t.v2 - t.v0)));
    if (p <= 0.0) continue;
    t.emitter = uint32_t(prims.size());
    prims.push_back(uint32_t(i) | (lightOnly ? EMITTER_UNSEEN_BIT : 0u));
    power.push_back(p);
  }
  for (size_t i = 0; i < out.spheres.size(); ++i) {
    if (scene.cs184Estimator) break;  // CS184's emissive spheres are no lights
    shader::Sphere& s = out.spheres[i];
    double p = emits(s.material, s.area);
    if (p <= 0.0) continue;
    s.emitter = uint32_t(prims.size());
    prims.push_back(uint32_t(i) | HIT_SPHERE_BIT);
    power.push_back(p);
  }
  // The environment map: power of its mean radiance falling on a disc the
  // size of the scene (only steers the choice among emitters).
  const double sceneRadius = geometry.bounds.empty() ? 0.0 : 0.5 * double(glm::length(geometry.bounds.hi - geometry.bounds.lo));
  uint32_t environmentEmitter = WP_INVALID;
  if (scene.environment != WP_INVALID) {
    const shader::Texture& env = out.textures[scene.environment];
    const std::vector<float> cdf = environment_cdf(env, out.texels);
    out.floatTables.insert(out.floatTables.end(), cdf.begin(), cdf.end());
    double p = luminance(texture_mean(out.textures, out.texels, scene.environment)) * WP_PI * WP_PI * sceneRadius * sceneRadius * 4.0;
    if (p > 0.0) {
      environmentEmitter = uint32_t(prims.size());
      prims.push_back(EMITTER_ENVIRONMENT);
      power.push_back(p);
    }
  }
  // Punctual lights' power steers the choice too: a spot's is that of its
  // cones' mean solid angle; a directional light's, its irradiance over a
  // disc the size of the scene.
  for (size_t i = 0; i < out.pointLights.size(); ++i) {
    const shader::PointLight& l = out.pointLights[i];
    const uint32_t kind = punctual_light_kind(l);
    double spread = 4.0 * WP_PI;  // a point light's solid angle
    if (kind == LIGHT_SPOT) spread = 2.0 * WP_PI * (1.0 - 0.5 * (double(l.intensity.w) + double(l.direction.w)));
    if (kind == LIGHT_DIRECTIONAL) spread = WP_PI * sceneRadius * sceneRadius;  // the area its light falls on
    if (kind == LIGHT_HEMISPHERE) spread = WP_PI * WP_PI * sceneRadius * sceneRadius;  // pi L on that area
    double p = luminance(glm::vec3(l.intensity)) * spread;
    if (p <= 0.0) continue;
    prims.push_back(uint32_t(i) | EMITTER_POINT_BIT);
    power.push_back(p);
  }
  out.emitters = build_alias_table(power);
  for (size_t i = 0; i < prims.size(); ++i) out.emitters[i].prim = prims[i];
  shader::SceneParams& p = out.params;
  p.background = glm::vec4(scene.background, 0.0f);
  p.environment = glm::uvec4(scene.environment, environmentEmitter, 0u, 0u);
  if (scene.environment != WP_INVALID) {
    p.environment.z = out.textures[scene.environment].info.z;
    p.environment.w = out.textures[scene.environment].info.w;
  }
  return prims.size();
}

}  // namespace wp
