// Ray-sphere and ray-triangle intersection: basic hits, grazing rays,
// watertightness on shared edges, and no self-hits for rays leaving a surface.
#include "test_support.h"

namespace wp::test {
namespace {

using namespace shader;

TEST(Triangle, HitReportsDistanceAndBarycentrics) {
  ShaderMath m;
  glm::vec3 v0(0, 0, 0), v1(1, 0, 0), v2(0, 1, 0);
  glm::vec3 o(0.25f, 0.5f, 2.0f), d(0, 0, -1);
  float t, u, v;
  ASSERT_TRUE(m.intersect_triangle(o, m.make_ray_shear(d), v0, v1, v2, WP_INF, t, u, v));
  EXPECT_FLOAT_EQ(t, 2.0f);
  EXPECT_NEAR(u, 0.25f, 1e-6f);
  EXPECT_NEAR(v, 0.5f, 1e-6f);
  // Both sides are hit (culling is the BSDF's business, not intersection's).
  ASSERT_TRUE(m.intersect_triangle(glm::vec3(0.25f, 0.5f, -2.0f), m.make_ray_shear(-d), v0, v1, v2, WP_INF, t, u, v));
  // Beyond tmax, behind the origin, or outside: no hit.
  EXPECT_FALSE(m.intersect_triangle(o, m.make_ray_shear(d), v0, v1, v2, 1.5f, t, u, v));
  EXPECT_FALSE(m.intersect_triangle(o, m.make_ray_shear(-d), v0, v1, v2, WP_INF, t, u, v));
  EXPECT_FALSE(m.intersect_triangle(glm::vec3(0.8f, 0.8f, 2.0f), m.make_ray_shear(d), v0, v1, v2, WP_INF, t, u, v));
}

TEST(Triangle, GrazingRaysInThePlaneMissWithoutNaN) {
  ShaderMath m;
  glm::vec3 v0(0, 0, 0), v1(1, 0, 0), v2(0, 1, 0);
  float t = -1.0f, u, v;
  // A ray lying in the triangle's plane has det == 0: a miss, never a NaN hit.
  EXPECT_FALSE(m.intersect_triangle(glm::vec3(-1, 0.2f, 0), m.make_ray_shear(glm::vec3(1, 0, 0)), v0, v1, v2, WP_INF, t, u, v));
  // Nearly grazing rays: hits, when they happen, are finite and inside.
  uint32_t state = 3;
  for (int i = 0; i < 10000; ++i) {
    float eps = 1e-6f + m.rng_next(state) * 1e-3f;
    glm::vec3 o(-1.0f, m.rng_next(state) * 0.5f, eps);
    glm::vec3 d = glm::normalize(glm::vec3(1.0f, 0.0f, -eps * (0.5f + m.rng_next(state))));
    if (m.intersect_triangle(o, m.make_ray_shear(d), v0, v1, v2, WP_INF, t, u, v)) {
      ASSERT_TRUE(std::isfinite(t) && t > 0.0f);
      ASSERT_GE(u, 0.0f);
      ASSERT_GE(v, 0.0f);
      ASSERT_LE(u + v, 1.0f + 1e-5f);
    }
  }
}

// Two triangles sharing an edge in a tilted plane: rays aimed exactly at points
// of the edge must hit at least one of them. (The edge's end points are on the
// patch's boundary, where a miss is legitimate; see the fan test for vertices.)
TEST(Triangle, SharedEdgesAreWatertight) {
  ShaderMath m;
  glm::vec3 origin(0.3f, -0.2f, 0.1f);
  glm::vec3 e1 = glm::normalize(glm::vec3(1.0f, 0.3f, -0.4f));
  glm::vec3 e2 = glm::normalize(glm::cross(glm::vec3(0.2f, 0.1f, 1.0f), e1));
  auto at = [&](float u, float v) { return origin + e1 * u + e2 * v; };
  glm::vec3 a = at(-1.3f, -0.7f), b = at(1.1f, 0.9f), c = at(-0.5f, 1.7f), d = at(0.8f, -1.4f);
  glm::vec3 n = glm::normalize(glm::cross(e1, e2));
  uint32_t state = 11;
  int missed = 0;
  for (int i = 0; i < 100000; ++i) {
    float s = 0.001f + 0.998f * m.rng_next(state);
    glm::vec3 target = a + (b - a) * s;
    glm::vec3 o = target + n * 3.0f + e1 * (m.rng_next(state) * 4 - 2) + e2 * (m.rng_next(state) * 4 - 2);
    glm::vec3 dir = target - o;
    ShaderMath::RayShear sh = m.make_ray_shear(dir);
    float t, u, v;
    bool hit1 = m.intersect_triangle(o, sh, a, b, c, 2.0f, t, u, v);
    bool hit2 = m.intersect_triangle(o, sh, a, d, b, 2.0f, t, u, v);
    if (!hit1 && !hit2) ++missed;
  }
  EXPECT_EQ(missed, 0);
}

// A closed fan of triangles around a vertex: rays aimed exactly at the shared
// vertex, from anywhere above the fan, must hit one of them.
TEST(Triangle, InteriorVerticesAreWatertight) {
  ShaderMath m;
  glm::vec3 center(12.3f, -4.1f, 7.7f);
  glm::vec3 n = glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f)), t, b;
  m.make_frame(n, t, b);
  const int k = 7;
  glm::vec3 ring[k];
  for (int i = 0; i < k; ++i) {
    float phi = 2.0f * WP_PI * (float(i) + 0.3f * float(i % 2)) / k;
    ring[i] = center + (t * std::cos(phi) + b * std::sin(phi)) * (1.0f + 0.2f * float(i % 3));
  }
  uint32_t state = 12;
  int missed = 0;
  for (int r = 0; r < 20000; ++r) {
    glm::vec3 local = m.square_to_cosine_hemisphere(glm::vec2(m.rng_next(state), m.rng_next(state)));
    glm::vec3 o = center + m.frame_to_world(local, t, b, n) * 5.0f;
    glm::vec3 dir = center - o;
    ShaderMath::RayShear sh = m.make_ray_shear(dir);
    bool hit = false;
    for (int i = 0; i < k && !hit; ++i) {
      float th, u, v;
      hit = m.intersect_triangle(o, sh, center, ring[i], ring[(i + 1) % k], 2.0f, th, u, v);
    }
    missed += !hit;
  }
  EXPECT_EQ(missed, 0);
}

// Points on a triangle far from the origin (where a fixed epsilon fails):
// rays leaving in random directions on the normal's side must not hit it again.
TEST(Triangle, RaysLeavingTheSurfaceDoNotHitItAgain) {
  ShaderMath m;
  glm::vec3 v0(5000.0f, 548.7f, 227.0f), v1(5000.0f, 548.8f, 332.0f), v2(4870.0f, 548.75f, 332.0f);
  glm::vec3 n = glm::normalize(glm::cross(v1 - v0, v2 - v0));
  uint32_t state = 21;
  for (int i = 0; i < 100000; ++i) {
    glm::vec2 b = m.square_to_triangle_barycentric(glm::vec2(m.rng_next(state), m.rng_next(state)));
    glm::vec3 p = v0 * (1 - b.x - b.y) + v1 * b.x + v2 * b.y;
    glm::vec3 side = (i & 1) ? n : -n;  // leave from either face
    glm::vec3 tng, bit;
    m.make_frame(side, tng, bit);
    glm::vec3 local = m.square_to_cosine_hemisphere(glm::vec2(m.rng_next(state), m.rng_next(state)));
    glm::vec3 d = m.frame_to_world(local, tng, bit, side);
    float t, u, v;
    ASSERT_FALSE(m.intersect_triangle(m.offset_ray(p, side), m.make_ray_shear(d), v0, v1, v2, WP_INF, t, u, v))
        << "self-hit at sample " << i << " t = " << t;
  }
}

// A point light, or a light no ray meets, may sit exactly on other
// geometry: CS184's Cornell files place the point or area light in the
// plane of the lamp mesh (CBempty.dae, CBspheres_lambertian.dae), through
// node matrices with 1e-7 rounding terms. A shadow ray that ended on the
// light point itself was blocked by that mesh or not by rounding, one way
// on the CPU and another on lavapipe (0.3 % darker there). It must stop
// short of the light point and never meet the surface the light lies in.
TEST(Triangle, ShadowRaysToLightsLyingOnASurfaceAreNotBlockedByIt) {
  SceneView view;  // aim_shadow_ray reads no scene buffer
  // A lamp panel at y = 1.49, turned from Z up by Blender's matrix.
  const glm::mat3 blender(-1.0f, 1.50996e-7f, 2.34488e-15f, 2.69452e-14f, 1.62921e-7f, 1.0f, 1.50996e-7f, 1.0f, -1.62921e-7f);
  const glm::vec3 at(-2.62268e-8f, 0.004315853f, 0.0f);
  const glm::vec3 v0 = blender * glm::vec3(0.4f, -0.3f, 1.49f) + at, v1 = blender * glm::vec3(0.4f, 0.3f, 1.49f) + at,
                  v2 = blender * glm::vec3(-0.4f, 0.3f, 1.49f) + at;
  const glm::vec3 down = glm::normalize(glm::cross(v1 - v0, v2 - v0));
  uint32_t state = 37;
  int blocked = 0, blockedAtTheLight = 0;
  for (int i = 0; i < 20000; ++i) {
    // The light point on the lamp's plane, inside the triangle, and a
    // shading point on the floor below (its geometric normal up).
    glm::vec2 b = view.square_to_triangle_barycentric(glm::vec2(view.rng_next(state), view.rng_next(state)));
    SceneView::LightSample ls;
    ls.p = v0 * (1 - b.x - b.y) + v1 * b.x + v2 * b.y;
    ls.n = glm::dot(down, glm::vec3(0, -1, 0)) > 0.0f ? down : -down;  // facing the room
    ls.isDelta = 1u;                                                     // a point light, or a light no ray meets
    const glm::vec3 p(view.rng_next(state) * 2.0f - 1.0f, 0.0f, view.rng_next(state) * 2.0f - 1.0f);
    ls.dist = glm::length(ls.p - p);
    ls.wi = (ls.p - p) / ls.dist;
    glm::vec3 origin, dir;
    float tmax, t, u, v;
    view.aim_shadow_ray(p, glm::vec3(0, 1, 0), ls, origin, dir, tmax);
    blocked += view.intersect_triangle(origin, view.make_ray_shear(dir), v0, v1, v2, tmax, t, u, v);
    // Ending on the light point itself, the segment meets the plane by rounding.
    blockedAtTheLight += view.intersect_triangle(origin, view.make_ray_shear(ls.p - origin), v0, v1, v2, 1.0f, t, u, v);
  }
  EXPECT_EQ(blocked, 0);
  EXPECT_GT(blockedAtTheLight, 100) << "the segment ending on the light point was expected to be blocked by rounding";
}

TEST(Sphere, HitsFromOutsideAndInside) {
  ShaderMath m;
  float t;
  ASSERT_TRUE(m.intersect_unit_sphere(glm::vec3(0, 0, 5), glm::vec3(0, 0, -1), WP_INF, t));
  EXPECT_FLOAT_EQ(t, 4.0f);
  ASSERT_TRUE(m.intersect_unit_sphere(glm::vec3(0, 0, 0), glm::vec3(0, 2, 0), WP_INF, t));  // inside, unnormalised
  EXPECT_FLOAT_EQ(t, 0.5f);
  EXPECT_FALSE(m.intersect_unit_sphere(glm::vec3(0, 0, 5), glm::vec3(0, 0, 1), WP_INF, t));  // pointing away
  EXPECT_FALSE(m.intersect_unit_sphere(glm::vec3(0, 0, 5), glm::vec3(0, 0, -1), 3.9f, t));   // beyond tmax
  EXPECT_FALSE(m.intersect_unit_sphere(glm::vec3(0, 1.001f, 5), glm::vec3(0, 0, -1), WP_INF, t));
}

TEST(Sphere, GrazingRaysHitNearTheSilhouetteOnly) {
  ShaderMath m;
  uint32_t state = 8;
  for (int i = 0; i < 100000; ++i) {
    float y = 1.0f + (m.rng_next(state) - 0.5f) * 2e-4f;
    float t = -1.0f;
    bool hit = m.intersect_unit_sphere(glm::vec3(-10.0f, y, 0.0f), glm::vec3(1, 0, 0), WP_INF, t);
    if (y > 1.0f + 1e-5f) {
      ASSERT_FALSE(hit) << y;
    }
    if (y < 1.0f - 1e-5f) {
      ASSERT_TRUE(hit) << y;
    }
    if (hit) {
      ASSERT_NEAR(t, 10.0f, 0.05f);
    }
  }
}

// Through the BVH: an ellipsoid placed by a transform, rays leaving its surface
// outwards never hit it again, and rays entering from inside hit the far side.
TEST(Sphere, TransformedSphereLeavesWithoutSelfHits) {
  Scene scene;
  add_lambertian(scene, glm::vec3(0.5f));
  glm::mat4 xf = glm::translate(glm::mat4(1.0f), glm::vec3(300.0f, -20.0f, 7.0f)) *
                 glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(1, 2, 3))) *
                 glm::scale(glm::mat4(1.0f), glm::vec3(2.0f, 0.5f, 1.0f));
  scene.spheres.push_back(SceneSphere{xf, 0});
  CompiledScene cs = compile_scene(scene, RenderOptions{});
  SceneView view = cs.view();
  uint32_t state = 4;
  for (int i = 0; i < 50000; ++i) {
    glm::vec3 dir = view.square_to_uniform_sphere(glm::vec2(view.rng_next(state), view.rng_next(state)));
    Hit h;
    glm::vec3 center(300.0f, -20.0f, 7.0f);
    ASSERT_EQ(view.trace_ray(center, dir, WP_INF, false, h), TRACE_OK);
    ASSERT_NE(h.prim, WP_INVALID) << "a ray from the centre must hit the shell";
    SceneView::SurfaceHit s = view.surface_at(center, dir, h);
    ASSERT_GT(glm::dot(s.ng, dir), 0.0f) << "normals point outwards";
    glm::vec3 tng, bit;
    view.make_frame(s.ng, tng, bit);
    glm::vec3 out = view.frame_to_world(view.square_to_cosine_hemisphere(glm::vec2(view.rng_next(state), view.rng_next(state))), tng, bit, s.ng);
    Hit h2;
    view.trace_ray(view.offset_ray(s.p, s.ng), out, WP_INF, false, h2);
    ASSERT_EQ(h2.prim, WP_INVALID) << "self-hit leaving the ellipsoid at sample " << i;
    // Entering: from just inside, towards the inside, the far side is hit.
    Hit h3;
    view.trace_ray(view.offset_ray(s.p, -s.ng), -out, WP_INF, false, h3);
    ASSERT_NE(h3.prim, WP_INVALID);
    ASSERT_GT(h3.t, 1e-3f);
  }
}

}  // namespace
}  // namespace wp::test
