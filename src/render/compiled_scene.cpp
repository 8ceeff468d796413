#include "render/compiled_scene.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>
#include <numeric>

#include "util/error.h"

namespace wp {

namespace {

Aabb triangle_bounds(const SceneTriangle& t) {
  Aabb b;
  for (const glm::vec3& v : t.v) b.grow(v);
  return b;
}

// Exact bounds of a transformed unit sphere: the half-extent along world axis i
// is the length of row i of the linear part.
Aabb sphere_bounds(const glm::mat4& m) {
  glm::vec3 c(m[3]);
  glm::vec3 e;
  for (int i = 0; i < 3; ++i) e[i] = glm::length(glm::vec3(m[0][i], m[1][i], m[2][i]));
  Aabb b;
  b.lo = c - e;
  b.hi = c + e;
  return b;
}

void rows_3x4(const glm::mat4& m, glm::vec4& r0, glm::vec4& r1, glm::vec4& r2) {
  glm::mat4 t = glm::transpose(m);
  r0 = t[0];
  r1 = t[1];
  r2 = t[2];
}

float luminance(glm::vec3 c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

}  // namespace

shader::SceneView CompiledScene::view() const {
  shader::SceneView v;
  v.scene = params;
  v.nodes = nodes.data();
  v.triangles = triangles.data();
  v.spheres = spheres.data();
  v.materials = materials.data();
  v.emitters = emitters.data();
  return v;
}

size_t CompiledScene::gpu_bytes() const {
  return nodes.size() * sizeof(shader::BvhNode) + triangles.size() * sizeof(shader::Triangle) +
         spheres.size() * sizeof(shader::Sphere) + materials.size() * sizeof(shader::Material) +
         emitters.size() * sizeof(shader::Emitter);
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

CompiledScene compile_scene(const Scene& scene, const RenderOptions& options) {
  CompiledScene out;
  const size_t numTris = scene.triangles.size();
  const size_t numSpheres = scene.spheres.size();
  if (numTris + numSpheres >= size_t(HIT_SPHERE_BIT)) throw InputError(scene.sourcePath + ": too many primitives");

  BvhInput input;
  input.bounds.reserve(numTris + numSpheres);
  for (const SceneTriangle& t : scene.triangles) input.bounds.push_back(triangle_bounds(t));
  for (const SceneSphere& s : scene.spheres) input.bounds.push_back(sphere_bounds(s.toWorld));
  input.isSphere.assign(numTris + numSpheres, 0);
  std::fill(input.isSphere.begin() + long(numTris), input.isSphere.end(), 1);
  Bvh bvh = build_bvh(input, scene.accelerator);
  if (bvh.depth > BVH_MAX_DEPTH) throw RenderError("internal error: BVH deeper than BVH_MAX_DEPTH");
  out.bvhDepth = bvh.depth;
  out.bvhSahCost = bvh.sahCost;
  out.bvhBuildSeconds = bvh.buildSeconds;

  // Reorder primitives into leaf order, one array per kind, and rewrite the
  // leaves to index those arrays.
  std::vector<uint32_t> newIndex(bvh.order.size());
  for (size_t pos = 0; pos < bvh.order.size(); ++pos) {
    uint32_t id = bvh.order[pos];
    if (id < numTris) {
      newIndex[pos] = uint32_t(out.triangles.size());
      const SceneTriangle& t = scene.triangles[id];
      shader::Triangle g{};
      g.v0 = t.v[0];
      g.v1 = t.v[1];
      g.v2 = t.v[2];
      g.material = t.material;
      g.emitter = WP_INVALID;
      g.sourceIndex = id;
      out.triangles.push_back(g);
    } else {
      newIndex[pos] = uint32_t(out.spheres.size());
      const SceneSphere& s = scene.spheres[id - numTris];
      shader::Sphere g{};
      rows_3x4(s.toWorld, g.toWorld0, g.toWorld1, g.toWorld2);
      rows_3x4(glm::inverse(s.toWorld), g.toObject0, g.toObject1, g.toObject2);
      g.material = s.material;
      g.emitter = WP_INVALID;
      float r = glm::length(glm::vec3(s.toWorld[0]));  // uniform scale (checked when emissive)
      g.area = 4.0f * WP_PI * r * r;
      g.sourceIndex = uint32_t(id - numTris);
      out.spheres.push_back(g);
    }
  }
  out.nodes = std::move(bvh.nodes);
  for (shader::BvhNode& n : out.nodes) {
    if (n.count != 0u && (n.count & ~BVH_SPHERE_LEAF) != 0u) n.leftFirst = newIndex[n.leftFirst];
  }

  out.materials = scene.materials;
  if (out.materials.empty()) out.materials.push_back(shader::Material{});  // buffers are never empty

  // Emitters: every primitive whose material emits, picked in proportion to
  // its power (luminance of the emitted radiance times area).
  std::vector<double> power;
  std::vector<uint32_t> prims;
  auto emits = [&](uint32_t material, float area) {
    glm::vec3 e(out.materials[material].emission);
    double p = double(luminance(e)) * double(area);
    return p > 0.0 ? p : 0.0;
  };
  for (size_t i = 0; i < out.triangles.size(); ++i) {
    shader::Triangle& t = out.triangles[i];
    double p = emits(t.material, 0.5f * glm::length(glm::cross(t.v1 - t.v0, t.v2 - t.v0)));
    if (p <= 0.0) continue;
    t.emitter = uint32_t(prims.size());
    prims.push_back(uint32_t(i));
    power.push_back(p);
  }
  for (size_t i = 0; i < out.spheres.size(); ++i) {
    shader::Sphere& s = out.spheres[i];
    double p = emits(s.material, s.area);
    if (p <= 0.0) continue;
    s.emitter = uint32_t(prims.size());
    prims.push_back(uint32_t(i) | HIT_SPHERE_BIT);
    power.push_back(p);
  }
  out.emitters = build_alias_table(power);
  for (size_t i = 0; i < prims.size(); ++i) out.emitters[i].prim = prims[i];
  if (out.triangles.empty()) out.triangles.push_back(shader::Triangle{});
  if (out.spheres.empty()) out.spheres.push_back(shader::Sphere{});
  if (out.emitters.empty()) out.emitters.push_back(shader::Emitter{});

  const Camera& cam = scene.camera;
  out.width = cam.width;
  out.height = cam.height;
  out.spp = options.spp > 0 ? options.spp : scene.samplesPerPixel;
  int maxBounces = options.maxBounces >= 0 ? options.maxBounces : scene.integrator.maxBounces;
  shader::SceneParams& p = out.params;
  rows_3x4(cam.toWorld, p.camToWorld0, p.camToWorld1, p.camToWorld2);
  p.camLens = glm::vec4(std::tan(glm::radians(cam.vfovDegrees) * 0.5f), float(cam.width) / float(cam.height),
                        cam.apertureRadius, cam.focusDistance);
  p.background = glm::vec4(scene.background, 0.0f);
  p.image = glm::uvec4(uint32_t(cam.width), uint32_t(cam.height), uint32_t(maxBounces),
                       uint32_t(scene.integrator.russianRouletteDepth));
  uint32_t flags = 0;
  if (scene.integrator.kind == IntegratorKind::PathMats) flags |= SCENE_FLAG_NO_NEE;
  if (scene.integrator.kind == IntegratorKind::PathNee) flags |= SCENE_FLAG_NO_BSDF_MIS;
  p.counts = glm::uvec4(uint32_t(prims.size()), options.seed, options.traversalStepCap, flags);
  p.debug = glm::vec4(options.plantedBias, 0.0f, 0.0f, 0.0f);
  p.debugRegion = options.plantedRegion;
  return out;
}

}  // namespace wp
