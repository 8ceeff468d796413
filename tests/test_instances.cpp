// Instancing (scene.h's instanced meshes, the two-level BVH of
// compile_geometry.cpp and traverse_*.glsl): glTF meshes that several nodes
// place are kept once; the walks through their instances find the hits the
// flattened scene has, with the same surfaces; emitters placed by instances
// light the scene with their world-space size.
#include <gtest/gtest.h>

#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "cpu/reference.h"
#include "scene/materials/material_module.h"
#include "test_support.h"

namespace wp::test {
namespace {

using namespace shader;

Scene instances_scene() {
  return load_scene(source_path("tests/data/gltf/instances.gltf"));
}

// tests/data/gltf/instances.gltf places a pebble by six nodes (plain, turned,
// stretched, mirrored, sheared, nested two groups deep) and three
// EXT_mesh_gpu_instancing elements (one mirrored), a block by three nodes
// (one mirrored, one sheared), a lamp by two and a floor by one.
TEST(Instances, MeshesPlacedSeveralTimesAreKeptOnce) {
  Scene scene = instances_scene();
  ASSERT_EQ(scene.instancedMeshes.size(), 2u) << "the pebble and the block; the floor (placed once) and the lamp (emissive) flattened";
  std::vector<size_t> placed(scene.instancedMeshes.size(), 0);
  for (const SceneInstance& i : scene.instances) ++placed[i.mesh];
  std::sort(placed.begin(), placed.end());
  EXPECT_EQ(placed, (std::vector<size_t>{3, 9}));
  EXPECT_EQ(scene.triangles.size(), 2u + 2u * 2u) << "the floor and both lamps, in world space";
  const size_t pebble = scene.instancedMeshes[0].triangles.size() > 12 ? 0 : 1;
  EXPECT_EQ(scene.instancedMeshes[1 - pebble].triangles.size(), 12u);
  EXPECT_EQ(instanced_triangle_count(scene), 9 * scene.instancedMeshes[pebble].triangles.size() + 3 * 12u);

  // Flattened, the same triangles in world space.
  Scene flat = scene;
  flatten_instances(flat);
  EXPECT_TRUE(flat.instances.empty());
  EXPECT_TRUE(flat.instancedMeshes.empty());
  EXPECT_EQ(flat.triangles.size(), scene.triangles.size() + instanced_triangle_count(scene));
  // The framing camera and the bounds see the instances.
  const auto [lo, hi] = scene_bounds(scene);
  const auto [flo, fhi] = scene_bounds(flat);
  EXPECT_LE(glm::length(lo - flo), 1e-4f);
  EXPECT_LE(glm::length(hi - fhi), 1e-4f);

  CompiledScene cs = compile_scene(scene, RenderOptions{});
  EXPECT_NE(cs.params.kinds.w & KIND_BIT(FEATURE_INSTANCES), 0u);
  EXPECT_EQ(cs.instancing.instances, 12u);
  EXPECT_EQ(cs.instancing.meshes, 2u);
  EXPECT_EQ(cs.instancing.instancedTriangles, instanced_triangle_count(scene));
  EXPECT_GT(cs.instancing.bottomLevelBytes, 0u);
  CompiledScene fcs = compile_scene(flat, RenderOptions{});
  EXPECT_EQ(fcs.params.kinds.w & KIND_BIT(FEATURE_INSTANCES), 0u) << "a flat scene's kernels hold no instancing";
  EXPECT_EQ(fcs.instancing.instances, 0u);
  // A model whose every mesh one node places renders through the flat path.
  Scene once = load_scene(source_path("tests/data/gltf/box-room.gltf"));
  EXPECT_TRUE(once.instances.empty());
  EXPECT_EQ(compile_scene(once, RenderOptions{}).params.kinds.w & KIND_BIT(FEATURE_INSTANCES), 0u);
}

// Closest hits through the instances (both layouts, all kinds of placement)
// are those of the flattened scene, and the surfaces there are the same:
// position, both normals, UVs, tangents and vertex colours. With every
// material two-sided, brute force checks the hits too (it knows no one-sided
// triangles). The walks stay within the stack slots the host sized.
TEST(Instances, HitsAndSurfacesAreThoseOfTheFlattenedScene) {
  for (bool twoSided : {false, true}) {
    Scene scene = instances_scene();
    if (twoSided)
      for (SceneMaterial& m : scene.materials) m.doubleSided = true;
    Scene flat = scene;
    flatten_instances(flat);
    std::vector<ShadowRay> rays = random_rays(flat, 6000, 4321);
    const std::vector<float> truth = twoSided ? brute_force_closest(flat, rays) : std::vector<float>{};
    for (int walk = 0; walk < 5; ++walk) {
      const BvhLayout layout = walk < 3 ? BvhLayout::Wide : BvhLayout::Binary;
      SCOPED_TRACE(std::string(walk == 0 ? "wide, nearest first" : walk == 1 ? "wide, octant order" : walk == 2 ? "wide, root at entry" :
                               walk == 3 ? "binary" : "binary, fused") +
                   (twoSided ? ", two-sided" : ", as the file says"));
      RenderOptions options;
      options.bvhLayout = layout;
      options.wideChildOrder = walk == 1 ? WideChildOrder::Octant : WideChildOrder::Auto;  // Auto: nearest first here
      options.rootAtEntry = walk == 2;
      options.binaryFused = walk == 4;
      CompiledScene cs = compile_scene(scene, options);
      options.binaryFused = false;  // the flattened scene by the plain walk
      CompiledScene fcs = compile_scene(flat, options);
      SceneView view = cs.view();
      SceneView fview = fcs.view();
      uint32_t deepest = 0;
      view.stackDepthSeen = &deepest;
      int hits = 0, instanceHits = 0, mirroredHits = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        const ShadowRay& r = rays[i];
        Hit h, fh;
        ASSERT_EQ(view.trace_ray(r.origin, r.dir, r.tmax, false, h), TRACE_OK);
        ASSERT_EQ(fview.trace_ray(r.origin, r.dir, r.tmax, false, fh), TRACE_OK);
        const bool hit = h.prim != WP_INVALID;
        ASSERT_EQ(hit, fh.prim != WP_INVALID) << "ray " << i;
        if (twoSided) {
          ASSERT_EQ(hit, truth[i] != WP_INF) << "ray " << i;
        }
        // Any hit: found exactly where a closest hit is.
        Hit any;
        view.trace_ray(r.origin, r.dir, r.tmax, true, any);
        EXPECT_EQ(any.prim != WP_INVALID, hit) << "ray " << i;
        if (!hit) continue;
        ++hits;
        EXPECT_NEAR(h.t, fh.t, 2e-5f * fh.t + 1e-6f) << "ray " << i;
        if (twoSided) {
          EXPECT_NEAR(h.t, truth[i], 2e-5f * truth[i] + 1e-6f) << "ray " << i;
        }
        if (h.instance == WP_INVALID) continue;
        ++instanceHits;
        if (cs.instances[h.instance].flags & INSTANCE_MIRRORED) ++mirroredHits;
        const SceneView::SurfaceHit s = view.surface_at(r.origin, r.dir, h);
        const SceneView::SurfaceHit fs = fview.surface_at(r.origin, r.dir, fh);
        EXPECT_LE(glm::length(s.p - fs.p), 1e-4f) << "ray " << i;
        EXPECT_GT(glm::dot(s.ng, fs.ng), 0.9999f) << "ray " << i << ": geometric normal";
        EXPECT_GT(glm::dot(s.ns, fs.ns), 0.999f) << "ray " << i << ": shading normal";
        EXPECT_LE(glm::length(s.uv - fs.uv), 1e-4f) << "ray " << i;
        EXPECT_LE(glm::length(s.color - fs.color), 1e-4f) << "ray " << i;
        EXPECT_LE(glm::length(glm::vec3(s.tangent) - glm::vec3(fs.tangent)), 1e-3f * glm::length(glm::vec3(fs.tangent)) + 1e-5f)
            << "ray " << i << ": tangent";
        EXPECT_EQ(s.tangent.w, fs.tangent.w) << "ray " << i << ": handedness";
        EXPECT_EQ(s.material, fs.material);
      }
      EXPECT_GT(hits, 1500);
      EXPECT_GT(instanceHits, 500);
      EXPECT_GT(mirroredHits, 30);
      EXPECT_LE(deepest, cs.params.accel.z);
    }
  }
}

// A wood: 1600 small meshes on a jittered grid, turned and scaled so that
// their boxes overlap, over a floor, and rays skimming it from one edge as a
// camera standing there casts them, besides rays from everywhere. Entering
// an instance here often leaves top-level nodes and primitives of a leaf
// waiting, which the walks set aside beneath the way back (a walk that loses
// one misses the hits behind it); every walk finds the flattened wood's hits
// within the stack the host sized.
TEST(Instances, AWoodOfInstancesIsWalkedAsItsFlattenedCopy) {
  Scene scene;
  scene.sourcePath = "wood";
  const uint32_t grey = add_lambertian(scene, glm::vec3(0.5f), "floor");
  const uint32_t green = add_lambertian(scene, glm::vec3(0.2f, 0.6f, 0.2f), "tree");
  auto fail = [](const std::string& what) { throw InputError(what); };
  SceneMesh floor;
  floor.positions = {{-25, 0, -25}, {-25, 0, 25}, {25, 0, 25}, {25, 0, -25}};
  floor.positionIndices = {0, 1, 2, 0, 2, 3};
  // A tree: a tall octahedron, its crown wider than its foot.
  SceneMesh tree;
  tree.positions = {{0, 0, 0}, {0.55f, 0.9f, 0}, {0, 0.9f, 0.45f}, {-0.5f, 0.9f, 0}, {0, 0.9f, -0.6f}, {0.05f, 2.0f, 0}};
  for (uint32_t k = 0; k < 4; ++k)
    for (uint32_t apex : {0u, 5u}) {
      const uint32_t a = 1 + k, b = 1 + (k + 1) % 4;
      tree.positionIndices.insert(tree.positionIndices.end(), {apex, apex == 0 ? b : a, apex == 0 ? a : b});
    }
  for (SceneMesh* m : {&floor, &tree}) {
    m->normalIndices.assign(m->positionIndices.size(), WP_INVALID);
    m->uvIndices.assign(m->positionIndices.size(), WP_INVALID);
    m->materials.assign(m->positionIndices.size() / 3, 0);
  }
  add_mesh(scene, floor, glm::mat4(1.0f), {grey}, WP_INVALID, fail);
  const uint32_t mesh = add_instanced_mesh(scene);
  add_to_instanced_mesh(scene, mesh, tree, {green}, WP_INVALID, fail);
  std::mt19937 engine(2024);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  auto uniform = [&] { return unit(engine); };
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      const glm::vec3 at(float(i) - 19.5f + 0.7f * (uniform() - 0.5f), 0.0f, float(j) - 19.5f + 0.7f * (uniform() - 0.5f));
      const glm::mat4 toWorld = glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), at), 6.2832f * uniform(), glm::vec3(0, 1, 0)),
                                           glm::vec3(0.7f + 0.6f * uniform()));
      add_instance(scene, mesh, toWorld, fail);
    }
  settle_instances(scene);
  ASSERT_EQ(scene.instances.size(), 1600u);
  for (SceneMaterial& m : scene.materials) m.doubleSided = true;  // as brute force sees triangles
  Scene flat = scene;
  flatten_instances(flat);
  std::vector<ShadowRay> rays = random_rays(flat, 2000, 77);
  for (int k = 0; k < 3000; ++k) {
    ShadowRay r;
    r.origin = glm::vec3(-20.0f + 40.0f * uniform(), 1.0f + 1.5f * uniform(), 21.0f);
    r.dir = glm::normalize(glm::vec3(0.6f * (uniform() - 0.5f), -0.02f - 0.08f * uniform(), -1.0f));
    r.tmax = WP_INF;
    rays.push_back(r);
  }
  const std::vector<float> truth = brute_force_closest(flat, rays);
  for (int walk = 0; walk < 5; ++walk) {
    SCOPED_TRACE(walk == 0 ? "wide, nearest first" : walk == 1 ? "wide, octant order" : walk == 2 ? "wide, root at entry" :
                 walk == 3 ? "binary" : "binary, fused");
    RenderOptions options;
    options.bvhLayout = walk < 3 ? BvhLayout::Wide : BvhLayout::Binary;
    options.wideChildOrder = walk == 1 ? WideChildOrder::Octant : WideChildOrder::Auto;
    options.rootAtEntry = walk == 2;
    options.binaryFused = walk == 4;
    CompiledScene cs = compile_scene(scene, options);
    SceneView view = cs.view();
    uint32_t deepest = 0;
    view.stackDepthSeen = &deepest;
    int instanceHits = 0, wrong = 0, wrongAny = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const ShadowRay& r = rays[i];
      Hit h, any;
      ASSERT_EQ(view.trace_ray(r.origin, r.dir, r.tmax, false, h), TRACE_OK);
      view.trace_ray(r.origin, r.dir, r.tmax, true, any);
      const float t = h.prim == WP_INVALID ? WP_INF : h.t;
      // Rounding in the instances' transforms moves a hit by up to about
      // 1e-4 here (origins on the surfaces, grazing rays); a node the walk
      // lost moves it to a surface behind, a tree's depth away, or misses.
      const bool bad = (t == WP_INF) != (truth[i] == WP_INF) || (t != WP_INF && std::fabs(t - truth[i]) > 1e-3f + 1e-4f * truth[i]);
      wrong += bad;
      wrongAny += (any.prim != WP_INVALID) != (truth[i] != WP_INF);
      instanceHits += h.instance != WP_INVALID;
    }
    EXPECT_EQ(wrong, 0) << "closest hits of " << rays.size() << " rays";
    EXPECT_EQ(wrongAny, 0) << "any hits";
    EXPECT_GT(instanceHits, 2500);
    EXPECT_LE(deepest, cs.params.accel.z) << "the stack slots the host sized";
  }
}

// The iteration that enters an instance also visits a node: the top level's
// node waiting to be visited (nearest first, when the primitive group the
// instance came from is done), or, with the root at entry, the instance's
// root. Neither walk takes an iteration of its own to enter, where it can
// help it (the forest: docs/benchmarks.md).
TEST(Instances, TheIterationThatEntersAnInstanceVisitsANodeToo) {
  Scene scene = instances_scene();
  Scene flat = scene;
  flatten_instances(flat);
  const std::vector<ShadowRay> rays = random_rays(flat, 3000, 99);
  for (bool rootAtEntry : {false, true}) {
    SCOPED_TRACE(rootAtEntry ? "root at entry" : "nearest first");
    RenderOptions options;
    options.rootAtEntry = rootAtEntry;
    CompiledScene cs = compile_scene(scene, options);
    SceneView view = cs.view();
    WalkLog log;
    view.walkLog = &log;
    int entries = 0, withTopNode = 0, withRoot = 0;
    for (const ShadowRay& r : rays) {
      log.clear();
      Hit h;
      ASSERT_EQ(view.trace_ray(r.origin, r.dir, r.tmax, false, h), TRACE_OK);
      for (const WalkIteration& it : log.iterations) {
        if (!(it.phases & WALK_PHASE_INSTANCE)) continue;
        ++entries;
        if (!(it.phases & WALK_PHASE_NODE)) continue;
        ++((it.phases & WALK_NOTE_NODE_IN_INSTANCE) ? withRoot : withTopNode);
      }
    }
    ASSERT_GT(entries, 500);
    if (rootAtEntry) {
      EXPECT_EQ(withRoot, entries);
      EXPECT_EQ(withTopNode, 0);
    } else {
      EXPECT_EQ(withRoot, 0);
      EXPECT_GT(withTopNode, 10) << "of " << entries << " entries";  // 31 of 1531 here: a small scene rarely has a node waiting
    }
  }
}

// The irradiance a Lambertian emitter polygon (radiance L, facing x) gives
// point x of normal n (Lambert's formula: the sum over the edges of the
// angle each subtends times the cosine of its plane's normal with n).
double polygon_irradiance(const std::vector<glm::dvec3>& corners, glm::dvec3 x, glm::dvec3 n, double radiance) {
  double sum = 0.0;
  for (size_t i = 0; i < corners.size(); ++i) {
    const glm::dvec3 a = glm::normalize(corners[i] - x), b = glm::normalize(corners[(i + 1) % corners.size()] - x);
    const double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += angle * glm::dot(glm::normalize(glm::cross(a, b)), n);
  }
  return 0.5 * radiance * std::fabs(sum);
}

// An emissive quad placed by two instances (a stretched one, and a mirrored
// one whose front must stay the quad's front) lights a white floor that an
// orthographic camera sees from above: each pixel is albedo / pi times the
// irradiance Lambert's formula gives. Taking the quads' size before their
// scale (the mistake renderers have made with instanced lights) is caught.
TEST(Instances, EmittersPlacedByInstancesLightWithTheirWorldSize) {
  Scene scene;
  scene.sourcePath = "instanced-lamps";
  const uint32_t white = add_lambertian(scene, glm::vec3(0.8f), "floor");
  SceneMaterial lamp;
  lamp.kind = MAT_LIGHT;
  lamp.name = "lamp";
  lamp.emission = add_texture(scene, constant_texture(glm::vec3(2.0f)));
  scene.materials.push_back(lamp);
  const uint32_t lampMaterial = uint32_t(scene.materials.size() - 1);
  auto quad = [](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    SceneMesh m;
    m.positions = {a, b, c, d};
    m.positionIndices = {0, 1, 2, 0, 2, 3};
    m.normalIndices.assign(6, WP_INVALID);
    m.uvIndices.assign(6, WP_INVALID);
    m.materials = {0, 0};
    return m;
  };
  auto fail = [](const std::string& what) { throw InputError(what); };
  add_mesh(scene, quad({-20, 0, -20}, {-20, 0, 20}, {20, 0, 20}, {20, 0, -20}), glm::mat4(1.0f), {white}, WP_INVALID, fail);
  // The lamp's front faces -y: (b - a) x (c - a) for a counter-clockwise
  // order seen from below.
  const uint32_t mesh = add_instanced_mesh(scene);
  add_to_instanced_mesh(scene, mesh, quad({-0.5f, 0, -0.5f}, {0.5f, 0, -0.5f}, {0.5f, 0, 0.5f}, {-0.5f, 0, 0.5f}), {lampMaterial},
                        WP_INVALID, fail);
  const glm::mat4 right = glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(2.6f, 1.0f, 0.0f)), glm::radians(-35.0f),
                                                 glm::vec3(0, 0, 1)),
                                     glm::vec3(1.5f, 1.0f, 0.8f));
  const glm::mat4 left = glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(-2.4f, 1.3f, 0.4f)), glm::radians(35.0f),
                                                glm::vec3(0, 0, 1)),
                                    glm::vec3(-1.0f, 1.0f, 1.3f));
  add_instance(scene, mesh, right, fail);
  add_instance(scene, mesh, left, fail);
  add_instance(scene, mesh, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, -5.0f, 0.0f)), fail);  // under the floor
  settle_instances(scene);
  ASSERT_TRUE(scene.instances.empty()) << "an emissive mesh's instances become world-space lights";
  ASSERT_EQ(scene.triangles.size(), 2u + 3u * 2u);
  scene.camera.orthoHalfHeight = 1.0f;
  scene.camera.width = scene.camera.height = 24;
  scene.camera.toWorld = glm::inverse(glm::lookAt(glm::vec3(0, 6, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1)));
  RenderOptions o;
  o.spp = 256;
  o.maxBounces = 1;
  o.integrator = IntegratorKind::PathMis;
  Progress quiet("", 0, false);
  const ImageStats img = render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);

  // Each pixel's expected value: the mean of 4x4 points over its square.
  auto placed = [](const glm::mat4& m) {
    std::vector<glm::dvec3> c;
    for (glm::vec3 p : {glm::vec3(-0.5f, 0, -0.5f), glm::vec3(0.5f, 0, -0.5f), glm::vec3(0.5f, 0, 0.5f), glm::vec3(-0.5f, 0, 0.5f)})
      c.push_back(glm::dvec3(glm::vec3(m * glm::vec4(p, 1.0f))));
    return c;
  };
  // `shrink` scales each lamp's size about its centre.
  auto expected_mean = [&](double shrink) {
    const glm::mat4 s = glm::scale(glm::mat4(1.0f), glm::vec3(float(shrink)));
    const std::vector<glm::dvec3> a = placed(right * s), b = placed(left * s);
    double sum = 0.0;
    const int w = scene.camera.width;
    for (int py = 0; py < w; ++py)
      for (int px = 0; px < w; ++px)
        for (int s = 0; s < 16; ++s) {
          // The camera looks down -y with -z up in the image: x grows to the right, z downwards.
          const double x = -1.0 + 2.0 * (px + (s % 4 + 0.5) / 4.0) / w, z = -1.0 + 2.0 * (py + (s / 4 + 0.5) / 4.0) / w;
          const glm::dvec3 at(x, 0.0, z), up(0.0, 1.0, 0.0);
          sum += 0.8 / WP_PI * (polygon_irradiance(a, at, up, 2.0) + polygon_irradiance(b, at, up, 2.0)) / 16.0;
        }
    return sum / double(w * w);
  };
  expect_mean(img, expected_mean(1.0), "two instanced lamps");
  // Lamps of their mesh's size, not their instances' (1.2 and 1.3 times larger): about as dim as these.
  auto [mean, se] = image_mean(img);
  const double unscaled = expected_mean(1.0 / std::sqrt(1.4));
  EXPECT_GT(std::fabs(mean - unscaled), 10.0 * se) << "the check tells the lamps' world size from a smaller one";
}

// Bad instancing input names the place: EXT_mesh_gpu_instancing without
// attributes, with accessors of different counts, with a rotation that is
// not one; a transform past the range of floats.
TEST(Instances, BadInstancingIsRefusedNamingThePlace) {
  const std::string head = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"byteLength": 76, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAA=="}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 16}, {"buffer": 0, "byteOffset": 52, "byteLength": 24}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": 1, "type": "VEC4"},
                  {"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"}],
    "nodes": [)";
  expect_error(head + R"({"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {}}}]})",
               {"/nodes/0/extensions/EXT_mesh_gpu_instancing", "has no attributes"}, "bad.gltf");
  expect_error(head + R"({"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": 2, "ROTATION": 1}}}}]})",
               {"/nodes/0/extensions/EXT_mesh_gpu_instancing/attributes/ROTATION"}, "bad.gltf");
  expect_error(head + R"({"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"ROTATION": 1}}}}]})",
               {"/nodes/0/extensions/EXT_mesh_gpu_instancing/attributes (instance 0)", "not a rotation"}, "bad.gltf");
  expect_error(head + R"({"scale": [1e30, 1e30, 1e30], "children": [1]}, {"mesh": 0, "scale": [1e30, 1e30, 1e30]}]})",
               {"/nodes/1/mesh", kPastFloatRange}, "bad.gltf");
}

}  // namespace
}  // namespace wp::test
