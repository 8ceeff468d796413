// The BVH against brute force: every build method must give exactly the closest
// hit that testing every primitive gives, and the tree must be well formed.
#include "test_support.h"

#include "bvh/bvh.h"

namespace wp::test {
namespace {

using namespace shader;

void expect_matches_brute_force(const AcceleratorSettings& accel, int rayCount) {
  Scene scene = bunny_with_spheres(accel);
  CompiledScene cs = compile_scene(scene, RenderOptions{});
  SceneView view = cs.view();
  std::vector<ShadowRay> rays = random_rays(scene, rayCount, 1234);
  std::vector<float> truth = brute_force_closest(scene, rays);
  int hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit h;
    ASSERT_EQ(view.trace_ray(rays[i].origin, rays[i].dir, rays[i].tmax, false, h), TRACE_OK);
    float expected = truth[i];
    if (expected == WP_INF) {
      ASSERT_EQ(h.prim, WP_INVALID) << "ray " << i << " hit at t = " << h.t << " but brute force found nothing";
    } else {
      ASSERT_NE(h.prim, WP_INVALID) << "ray " << i << " missed; brute force hit at t = " << expected;
      ASSERT_EQ(h.t, expected) << "ray " << i;
      ++hits;
    }
    // Any-hit queries agree on whether something is hit.
    Hit any;
    view.trace_ray(rays[i].origin, rays[i].dir, rays[i].tmax, true, any);
    ASSERT_EQ(any.prim == WP_INVALID, expected == WP_INF) << "ray " << i;
  }
  EXPECT_GT(hits, rayCount / 5);
}

TEST(Bvh, SahClosestHitsEqualBruteForce) {
  expect_matches_brute_force(AcceleratorSettings{4, SplitMethod::Sah}, 20000);
}

TEST(Bvh, OtherSplitMethodsAndLeafSizesEqualBruteForce) {
  expect_matches_brute_force(AcceleratorSettings{1, SplitMethod::Sah}, 5000);
  expect_matches_brute_force(AcceleratorSettings{8, SplitMethod::Middle}, 5000);
  expect_matches_brute_force(AcceleratorSettings{2, SplitMethod::Equal}, 5000);
}

TEST(Bvh, TreeIsWellFormed) {
  Scene scene = bunny_with_spheres(AcceleratorSettings{4, SplitMethod::Sah});
  CompiledScene cs = compile_scene(scene, RenderOptions{});
  ASSERT_LE(cs.bvhDepth, BVH_MAX_DEPTH);
  std::vector<int> seenTri(cs.triangles.size(), 0), seenSphere(cs.spheres.size(), 0);
  std::vector<int> parents(cs.nodes.size(), 0);
  for (const BvhNode& n : cs.nodes) {
    if (n.count == 0) {
      ASSERT_LT(n.leftFirst + 1, cs.nodes.size());
      for (uint32_t c = n.leftFirst; c <= n.leftFirst + 1; ++c) {
        parents[c]++;
        const BvhNode& ch = cs.nodes[c];
        for (int k = 0; k < 3; ++k) {
          EXPECT_GE(ch.bmin[k], n.bmin[k]);
          EXPECT_LE(ch.bmax[k], n.bmax[k]);
        }
      }
      continue;
    }
    uint32_t count = n.count & ~BVH_SPHERE_LEAF;
    EXPECT_LE(count, 4u);
    for (uint32_t i = n.leftFirst; i < n.leftFirst + count; ++i) {
      if (n.count & BVH_SPHERE_LEAF) seenSphere.at(i)++;
      else {
        seenTri.at(i)++;
        const Triangle& t = cs.triangles[i];
        for (glm::vec3 v : {t.v0, t.v1, t.v2})
          for (int k = 0; k < 3; ++k) {
            EXPECT_GE(v[k], n.bmin[k]);
            EXPECT_LE(v[k], n.bmax[k]);
          }
      }
    }
  }
  for (int s : seenTri) ASSERT_EQ(s, 1) << "every triangle sits in exactly one leaf";
  for (int s : seenSphere) ASSERT_EQ(s, 1) << "every sphere sits in exactly one leaf";
  EXPECT_EQ(parents[0], 0);
  for (size_t i = 1; i < parents.size(); ++i) ASSERT_EQ(parents[i], 1) << "node " << i;
}

TEST(Bvh, SahBeatsMidpointSplitsOnCost) {
  Scene sah = bunny_with_spheres(AcceleratorSettings{4, SplitMethod::Sah});
  Scene mid = bunny_with_spheres(AcceleratorSettings{4, SplitMethod::Middle});
  double costSah = compile_scene(sah, RenderOptions{}).bvhSahCost;
  double costMid = compile_scene(mid, RenderOptions{}).bvhSahCost;
  EXPECT_LT(costSah, costMid);
}

TEST(Bvh, DegenerateInputsBuild) {
  // Many identical triangles (all centroids equal) and an empty scene.
  Scene scene;
  add_lambertian(scene, glm::vec3(0.5f));
  for (int i = 0; i < 1000; ++i) scene.triangles.push_back(SceneTriangle{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 0});
  CompiledScene cs = compile_scene(scene, RenderOptions{});
  SceneView view = cs.view();
  Hit h;
  ASSERT_EQ(view.trace_ray(glm::vec3(0.2f, 0.2f, 1), glm::vec3(0, 0, -1), WP_INF, false, h), TRACE_OK);
  EXPECT_FLOAT_EQ(h.t, 1.0f);
  Scene empty;
  CompiledScene ce = compile_scene(empty, RenderOptions{});
  SceneView ev = ce.view();
  ASSERT_EQ(ev.trace_ray(glm::vec3(0), glm::vec3(0, 0, -1), WP_INF, false, h), TRACE_OK);
  EXPECT_EQ(h.prim, WP_INVALID);
}

// A traversal that would need more steps than the cap reports itself
// truncated instead of returning a wrong answer.
TEST(Bvh, TraversalPastTheStepCapIsReported) {
  Scene scene = bunny_with_spheres(AcceleratorSettings{4, SplitMethod::Sah});
  RenderOptions options;
  options.traversalStepCap = 3;
  CompiledScene cs = compile_scene(scene, options);
  SceneView view = cs.view();
  std::vector<ShadowRay> rays = random_rays(scene, 200, 7);
  int truncated = 0;
  for (const ShadowRay& r : rays) {
    Hit h;
    truncated += view.trace_ray(r.origin, r.dir, r.tmax, false, h) == TRACE_TRUNCATED;
  }
  EXPECT_GT(truncated, 100);
}

}  // namespace
}  // namespace wp::test
