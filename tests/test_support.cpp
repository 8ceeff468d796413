#include "test_support.h"

#include <glm/gtc/matrix_transform.hpp>

#include <tbb/parallel_for.h>

#include "bvh/bvh.h"
#include "scene/materials/material_module.h"
#include "scene/obj_mesh.h"

namespace wp::test {

namespace {
// Removes a test's scratch folder when it passes; a failed test keeps its
// files to look at. Registered before main runs the tests.
class ScratchCleanup : public testing::EmptyTestEventListener {
  void OnTestEnd(const testing::TestInfo& t) override {
    if (t.result()->Failed()) return;
    std::error_code ignored;  // a folder the test never made is no error
    std::filesystem::remove_all(scratch_dir(t), ignored);
  }
};
const bool kScratchCleanupRegistered = [] {
  testing::UnitTest::GetInstance()->listeners().Append(new ScratchCleanup);
  return true;
}();
}  // namespace

Scene bunny_with_spheres(const AcceleratorSettings& accel) {
  Scene scene;
  scene.accelerator = accel;
  add_lambertian(scene, glm::vec3(0.5f));
  const SceneMesh mesh = load_obj(source_path("scenes/assets/bunny.obj")).mesh;
  Aabb box;
  for (glm::vec3 p : mesh.positions) box.grow(p);
  float scale = 10.0f / glm::length(box.hi - box.lo);
  for (size_t t = 0; t + 2 < mesh.positionIndices.size(); t += 3) {
    SceneTriangle tri;
    for (int c = 0; c < 3; ++c) tri.v[c] = (mesh.positions[mesh.positionIndices[t + size_t(c)]] - box.lo) * scale;
    tri.material = 0;
    scene.triangles.push_back(tri);
  }
  const glm::vec3 centers[] = {{1, 1, 1}, {5, 3, 2}, {3, 6, 4}, {8, 2, 6}, {2, 2, 7}};
  for (int i = 0; i < 5; ++i) {
    glm::mat4 m = glm::translate(glm::mat4(1.0f), centers[i]) * glm::scale(glm::mat4(1.0f), glm::vec3(0.4f + 0.3f * float(i)));
    if (i == 3) m = m * glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 2.5f, 0.5f));
    scene.spheres.push_back(SceneSphere{m, 0});
  }
  return scene;
}

std::vector<shader::ShadowRay> random_rays(const Scene& scene, int count, uint32_t seed) {
  shader::ShaderMath m;
  Aabb box;
  for (const SceneTriangle& t : scene.triangles)
    for (glm::vec3 v : t.v) box.grow(v);
  glm::vec3 lo = box.lo - 0.2f * (box.hi - box.lo), hi = box.hi + 0.2f * (box.hi - box.lo);
  uint32_t state = seed;
  std::vector<shader::ShadowRay> rays{size_t(count)};
  for (int i = 0; i < count; ++i) {
    shader::ShadowRay& r = rays[size_t(i)];
    r = shader::ShadowRay{};
    auto rnd3 = [&] { return glm::vec3(m.rng_next(state), m.rng_next(state), m.rng_next(state)); };
    r.origin = lo + (hi - lo) * rnd3();
    if (i % 4 == 0) {
      const SceneTriangle& t = scene.triangles[size_t(m.rng_next_uint(state) % scene.triangles.size())];
      glm::vec2 b = m.square_to_triangle_barycentric(glm::vec2(m.rng_next(state), m.rng_next(state)));
      r.dir = glm::normalize(t.v[0] * (1 - b.x - b.y) + t.v[1] * b.x + t.v[2] * b.y - r.origin);
    } else {
      r.dir = m.square_to_uniform_sphere(glm::vec2(m.rng_next(state), m.rng_next(state)));
    }
    r.tmax = (i % 7 == 0) ? 3.0f : WP_INF;  // some bounded rays, like shadow rays
  }
  return rays;
}

static float brute_force_one(const Scene& scene, const shader::ShadowRay& r) {
  shader::ShaderMath m;
  shader::ShaderMath::RayShear sh = m.make_ray_shear(r.dir);
  float best = r.tmax;
  bool hit = false;
  for (const SceneTriangle& t : scene.triangles) {
    float th, u, v;
    if (m.intersect_triangle(r.origin, sh, t.v[0], t.v[1], t.v[2], best, th, u, v)) {
      best = th;
      hit = true;
    }
  }
  for (const SceneSphere& s : scene.spheres) {
    glm::mat4 inv = glm::inverse(s.toWorld);
    glm::vec3 o(inv * glm::vec4(r.origin, 1.0f)), d(inv * glm::vec4(r.dir, 0.0f));
    float th;
    if (m.intersect_unit_sphere(o, d, best, th)) {
      best = th;
      hit = true;
    }
  }
  return hit ? best : WP_INF;
}

std::vector<float> brute_force_closest(const Scene& scene, const std::vector<shader::ShadowRay>& rays) {
  std::vector<float> out(rays.size());
  tbb::parallel_for(size_t(0), rays.size(), [&](size_t i) { out[i] = brute_force_one(scene, rays[i]); });
  return out;
}

}  // namespace wp::test
