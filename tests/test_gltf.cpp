// glTF 2.0 import (scene/import_gltf.cpp, scene/gltf_accessors.cpp) on the
// assets scripts/make-gltf-test-assets.py writes: the node tree against the
// same objects placed by hand in a darts file, the two formats' renders
// against each other, binary files with textures, sparse and normalized
// accessors, cameras, files kept inside the model's folder, and every kind
// of bad input refused in one line that names the file and the place.
#include <nlohmann/json.hpp>
#include <stb_image_write.h>

#include "stats/compare.h"
#include "test_support.h"

namespace wp::test {
namespace {

using json = nlohmann::json;

std::string gltf_path(const std::string& name) {
  return source_path("tests/data/gltf/" + name);
}

json read_json(const std::string& path) {
  std::ifstream in(path);
  return json::parse(in);
}

// Triangles as sorted vertex lists, for comparing two scenes' geometry.
std::vector<std::array<float, 9>> triangle_set(const Scene& s) {
  std::vector<std::array<float, 9>> out;
  for (const SceneTriangle& t : s.triangles) {
    std::array<glm::vec3, 3> v = {t.v[0], t.v[1], t.v[2]};
    std::sort(v.begin(), v.end(), [](glm::vec3 a, glm::vec3 b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); });
    out.push_back({v[0].x, v[0].y, v[0].z, v[1].x, v[1].y, v[1].z, v[2].x, v[2].y, v[2].z});
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Gltf, NodeTreePlacesMeshesAsTheDartsTwinDoes) {
  const Scene g = load_scene(gltf_path("box-room.gltf"));
  const Scene d = load_scene(gltf_path("box-room.json"));
  const auto a = triangle_set(g), b = triangle_set(d);
  ASSERT_EQ(a.size(), 28u);  // floor 2, two boxes 12 each, panel 2
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 9; ++k) ASSERT_NEAR(a[i][k], b[i][k], 1e-5f) << "triangle " << i;
  // Materials, emission, the light in W/sr (candela / 683) and the camera.
  ASSERT_EQ(g.materials.size(), 4u);
  EXPECT_EQ(g.materials[1].kind, MAT_METAL_ROUGH);
  EXPECT_EQ(g.materials[1].record.params, glm::vec4(0.35f, 1.0f, 1.5f, 0.0f));
  EXPECT_FLOAT_EQ(g.materials[2].record.params.z, 1.45f);  // KHR_materials_ior
  ASSERT_NE(g.materials[3].emission, WP_INVALID);
  const glm::vec3 emit = g.textures[g.materials[3].emission].color;
  EXPECT_NEAR(emit.y, 0.9f * 8.0f, 1e-5f);  // KHR_materials_emissive_strength
  // Point, spot and directional lights (candela and lux / 683), placed and
  // turned by their nodes as the twin places them by hand.
  ASSERT_EQ(g.pointLights.size(), 3u);
  ASSERT_EQ(d.pointLights.size(), 3u);
  EXPECT_NEAR(g.pointLights[0].intensity.x, 6.0f, 1e-4f);
  for (size_t i = 0; i < 3; ++i) {
    const ScenePointLight &a = g.pointLights[i], &b = d.pointLights[i];
    EXPECT_EQ(a.kind, b.kind) << "light " << i;
    EXPECT_LT(glm::distance(a.intensity, b.intensity), 1e-4f) << "light " << i;
    EXPECT_LT(glm::distance(a.direction, b.direction), 1e-5f) << "light " << i;
    if (a.kind != ScenePointLight::Kind::Directional) {
      EXPECT_LT(glm::distance(a.position, b.position), 1e-5f) << "light " << i;
    }
    EXPECT_NEAR(a.cosInner, b.cosInner, 1e-6f);
    EXPECT_NEAR(a.cosOuter, b.cosOuter, 1e-6f);
  }
  EXPECT_EQ(g.pointLights[1].kind, ScenePointLight::Kind::Spot);
  EXPECT_EQ(g.pointLights[2].kind, ScenePointLight::Kind::Directional);
  EXPECT_NEAR(g.camera.vfovDegrees, glm::degrees(0.75f), 1e-4f);
  EXPECT_EQ(g.camera.width, 800);
  EXPECT_EQ(g.camera.height, 640);  // aspect ratio 1.25
  EXPECT_NEAR(glm::distance(glm::vec3(g.camera.toWorld[3]), glm::vec3(0.3f, 1.6f, 4.2f)), 0.0f, 1e-5f);
  EXPECT_EQ(g.background, glm::vec3(0.0f)) << "a lit model gets no sky";
}

// The same objects in both formats estimate the same image.
TEST(Gltf, RendersTheSameImageAsItsDartsTwin) {
  auto render = [](const std::string& path, uint32_t seed) {
    Scene s = load_scene(path);
    s.camera.width = 40;
    s.camera.height = 32;
    RenderOptions o;
    o.spp = 256;  // at 64 its small light left the image mean's test a p of 0.002 to fail by on one seed pair
    o.seed = seed;
    Progress quiet("", 0, false);
    return render_cpu(compile_scene(s, reference_options(o)), 0, quiet);
  };
  ImageStats g = render(gltf_path("box-room.gltf"), 3);
  ImageStats d = render(gltf_path("box-room.json"), 4);
  CompareResult r = compare_images(g, d);
  EXPECT_TRUE(r.passed()) << r.summary();
  auto [mean, error] = image_mean(g);
  EXPECT_GT(mean, 0.02) << "the scene is lit";
}

TEST(Gltf, BinaryModelWithTexturesSparseAndNormalizedAccessors) {
  const Scene s = load_scene(gltf_path("textured.glb"));
  ASSERT_EQ(s.triangles.size(), 2u + 12u);
  float top = -1.0f;
  for (const SceneTriangle& t : s.triangles)
    for (const glm::vec3& v : t.v) top = std::max(top, v.y);
  EXPECT_NEAR(top, 0.5f + 0.9f, 1e-6f) << "the sparse accessor lifts the top of the box";
  // Normalized unsigned short UVs land in [0, 1]; the floor's repeat to 2 (v flipped: 1 - v).
  float lowest = 1.0f, highest = 0.0f;
  for (const SceneTriangleShading& sh : s.triangleShading)
    for (const glm::vec2& uv : sh.uv) {
      lowest = std::min({lowest, uv.x, uv.y});
      highest = std::max({highest, uv.x, uv.y});
    }
  EXPECT_NEAR(lowest, -1.0f, 1e-6f);
  EXPECT_NEAR(highest, 2.0f, 1e-6f);
  // Base colour decoded as sRGB, the metallic-roughness map as linear data:
  // its first column's green is 51 / 255 = 0.2 exactly.
  ASSERT_EQ(s.images.size(), 2u);
  const LinearImage& rough = s.images[s.textures[s.materials[1].amount()].image];
  EXPECT_NEAR(rough.pixels[0].y, 0.2f, 1e-6f);
  EXPECT_NEAR(s.images[0].pixels[0].x, srgb_to_linear(230.0f / 255.0f), 1e-6f);
  // KHR_texture_transform (offset 0.5, 0.25; rotation pi / 2; scale 2, 3) on
  // the floor: glTF's (0.3, 0.2) scales to (0.6, 0.6), turns to (0.6, -0.6)
  // (u' = cos u + sin v, v' = -sin u + cos v) and moves to (1.1, -0.35); in
  // wavepath's UVs (v flipped) (0.3, 0.8) maps to (1.1, 1.35).
  const glm::mat4& mapping = s.textures[s.materials[0].albedo()].mapping;
  const glm::vec4 mapped = mapping * glm::vec4(0.3f, 0.8f, 0.0f, 1.0f);
  EXPECT_NEAR(mapped.x, 1.1f, 1e-5f);
  EXPECT_NEAR(mapped.y, 1.35f, 1e-5f);
  // Two cameras, the first of the tree orthographic: xmag = ymag = 2, the
  // image square; its rays are parallel, down its -Z, from the points of a
  // 4 x 4 window around its node at (0, 1, 5).
  ASSERT_EQ(s.cameras.size(), 2u);
  EXPECT_EQ(s.camera.name, "ortho");
  EXPECT_EQ(s.camera.orthoHalfHeight, 2.0f);
  EXPECT_EQ(s.camera.width, s.camera.height);
  EXPECT_EQ(s.background, glm::vec3(1.0f)) << "a model without lights is lit by a white sky";
  {
    Scene small = s;
    set_resolution(small.camera, 8, 8);
    CompiledScene cs = compile_scene(small, RenderOptions{});
    shader::SceneView view = cs.view();
    for (uint32_t pixel : {0u, 7u, 56u, 63u, 27u}) {
      glm::vec3 lo(INFINITY), hi(-INFINITY);
      for (uint32_t k = 0; k < 64; ++k) {
        shader::PathState ps;
        view.path_begin(ps, pixel, k);
        EXPECT_NEAR(glm::distance(ps.dir, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
        lo = glm::min(lo, ps.origin);
        hi = glm::max(hi, ps.origin);
      }
      // Within the pixel's 0.5 x 0.5 square of the window (y up, rows down).
      const float x0 = -2.0f + 0.5f * float(pixel % 8), y1 = 3.0f - 0.5f * float(pixel / 8);
      EXPECT_GE(lo.x, x0 - 1e-5f);
      EXPECT_LE(hi.x, x0 + 0.5f + 1e-5f);
      EXPECT_GE(lo.y, y1 - 0.5f - 1e-5f);
      EXPECT_LE(hi.y, y1 + 1e-5f);
      EXPECT_NEAR(lo.z, 5.0f, 1e-6f);
      EXPECT_NEAR(hi.z, 5.0f, 1e-6f);
    }
  }
  Scene copy = s;
  choose_camera(copy, "persp");
  EXPECT_EQ(copy.camera.orthoHalfHeight, 0.0f);
  EXPECT_EQ(copy.camera.height, 600);  // no aspect ratio: 4:3
  try {
    choose_camera(copy, "side");
    ADD_FAILURE() << "a missing camera was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1 \"persp\""), std::string::npos) << e.what();
  }
  choose_camera(copy, "0");
  EXPECT_EQ(copy.camera.name, "ortho");
}

// Loading `path` fails with one line that names it and holds every part.
void expect_refused(const std::string& path, std::initializer_list<const char*> parts) {
  try {
    load_scene(path);
    ADD_FAILURE() << path << " loaded";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
    for (const char* p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
  }
}

// surface.glb: what glTF puts on a surface, read into the scene and seen by
// the CPU view of the compiled scene (the kernels' code compiled as C++).
TEST(Gltf, SurfaceDetailsNormalMapsVertexDataAlphaAndSides) {
  const Scene s = load_scene(gltf_path("surface.glb"));
  ASSERT_EQ(s.materials.size(), 6u);
  const SceneMaterial &floor = s.materials[0], &metal = s.materials[1], &fence = s.materials[2], &pane = s.materials[3],
                      &wall = s.materials[4], &glass = s.materials[5];
  ASSERT_NE(floor.normalMap, WP_INVALID);
  EXPECT_EQ(s.textures[floor.normalMap].kind, TEX_IMAGE);
  EXPECT_EQ(s.textures[metal.normalMap].color, glm::vec3(0.8f, 0.8f, 1.0f));  // the normal texture's scale
  EXPECT_EQ(fence.alphaCutoff, 0.5f);
  EXPECT_TRUE(fence.doubleSided);
  EXPECT_LT(pane.alphaCutoff, 0.0f);  // BLEND: stochastic
  EXPECT_FALSE(pane.doubleSided || wall.doubleSided);
  EXPECT_EQ(glass.record.params.w, 0.9f);  // KHR_materials_transmission, scaled by its texture
  ASSERT_NE(glass.record.children.y, WP_INVALID);
  EXPECT_EQ(s.textures[glass.record.children.y].kind, TEX_IMAGE);
  const SceneTexture& gradient = s.textures[pane.albedo()];
  EXPECT_TRUE(gradient.secondUvSet);
  EXPECT_EQ(gradient.wrapU, TEX_WRAP_CLAMP);
  EXPECT_EQ(gradient.wrapV, TEX_WRAP_MIRROR);
  EXPECT_FLOAT_EQ(gradient.alpha, 0.4f);
  EXPECT_EQ(s.images[s.textures[fence.albedo()].image].alpha.size(), 256u);  // the RGBA PNG's alpha
  // The floor's vertex colours (normalized bytes) and given tangents.
  int floorTriangles = 0;
  for (const SceneTriangle& t : s.triangles) {
    if (t.material != 0) continue;
    const SceneTriangleShading& sh = s.triangleShading.at(t.shading);
    ASSERT_TRUE(sh.hasVertexData);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(sh.tangent[c], glm::vec4(1, 0, 0, 1));
      const float lo = 60 / 255.0f;
      const glm::vec4 given[] = {{1, lo, lo, 1}, {lo, 1, lo, 1}, {lo, lo, 1, 1}, {1, 1, 1, 1}};
      EXPECT_NE(std::find(std::begin(given), std::end(given), sh.color[c]), std::end(given)) << "corner " << c;
    }
    ++floorTriangles;
  }
  EXPECT_EQ(floorTriangles, 2);

  RenderOptions o;
  const CompiledScene cs = compile_scene(s, o);
  const glm::uvec4 k = cs.params.kinds;
  for (uint32_t f : {FEATURE_VERTEX_DATA, FEATURE_NORMAL_MAPS, FEATURE_ONE_SIDED, FEATURE_CUTOUTS}) EXPECT_TRUE(k.w & KIND_BIT(f)) << f;
  shader::SceneView view = cs.view();
  auto trace = [&](glm::vec3 o, glm::vec3 d) {
    shader::Hit h;
    EXPECT_EQ(view.trace_ray(o, d, WP_INF, false, h), TRACE_OK);
    return h;
  };
  // The wall (at z = 1.6, facing -z) is not there from the camera's side, and is from behind.
  EXPECT_FALSE(trace({-0.3f, 0.5f, 3.0f}, {0, 0, -1}).t < 1.5f);
  EXPECT_NEAR(trace({-0.3f, 0.5f, 0.0f}, {0, 0, 1}).t, 1.6f, 1e-4f);
  // The fence (z = -1.5) is cut out in its texture's gaps and there on its bars
  // (texel centres: alpha is filtered between texels).
  const float v = 5.5f / 16.0f, y = 1.2f * (1.0f - v);  // glTF's v down the image
  EXPECT_EQ(trace({-0.8f + 6.5f / 16.0f, y, -1.3f}, {0, 0, -1}).prim, WP_INVALID) << "a gap";
  EXPECT_NEAR(trace({-0.8f + 1.5f / 16.0f, y, -1.3f}, {0, 0, -1}).t, 0.2f, 1e-4f) << "a bar";
  // The BLEND pane (alpha 0.4, at z = 0.6) lets through 60% of the rays that
  // cross it, each ray deciding by its own hash.
  uint32_t state = 5;
  int passed = 0;
  const int rays = 4000;
  for (int i = 0; i < rays; ++i) {
    const glm::vec3 o(1.25f + 0.4f * view.rng_next(state), 0.75f + 0.15f * view.rng_next(state), 2.0f);
    const shader::Hit ph = trace(o, {0, 0, -1});
    if (ph.prim == WP_INVALID) ++passed;
    else EXPECT_NEAR(ph.t, 1.4f, 1e-4f);
  }
  EXPECT_NEAR(double(passed) / rays, 0.6, 4.0 * std::sqrt(0.24 / rays));
  // The pane's gradient on the second UV set: clamped beyond u = 1, mirrored beyond v = 1.
  const glm::vec3 p(0.0f);
  auto at = [&](float u, float vv) { return view.texture_eval(s.materials[3].albedo(), glm::vec4(0.0f, 0.0f, u, vv), p); };
  EXPECT_EQ(at(1.3f, 0.4f), at(1.0f, 0.4f));
  EXPECT_EQ(at(-0.2f, 0.4f), at(0.0f, 0.4f));
  EXPECT_NEAR(glm::distance(at(0.5f, 1.25f), at(0.5f, 0.75f)), 0.0f, 1e-6f);
  EXPECT_NE(at(0.5f, 1.25f), at(0.5f, 0.25f));
  EXPECT_FLOAT_EQ(view.texture_alpha(s.materials[3].albedo(), glm::vec4(0.5f), p), 0.4f);
  // The floor's ripple map, at the centre of texel column 0: the shading
  // normal is the decoded texel in the frame (tangent +x, bitangent
  // cross(n, t) = -z, normal +y).
  const float u = 0.5f / 16.0f, x = 4.0f * u / 3.0f - 2.0f;  // u = 3 (x + 2) / 4
  const shader::Hit h = trace({x, 3.0f, 0.3f}, {0, -1, 0});
  ASSERT_NEAR(h.t, 3.0f, 1e-4f);
  const shader::SceneView::SurfaceHit hit = view.surface_at({x, 3.0f, 0.3f}, {0, -1, 0}, h);
  const shader::SceneView::Bsdf b = view.bsdf_at(hit, glm::vec3(0, 1, 0));
  const float slope = 0.9f * std::cos(2.0f * float(M_PI) * 0.5f / 8.0f);
  const glm::vec3 n = glm::normalize(glm::vec3(-slope, 0.0f, 1.0f));
  auto texel = [](float c) { return std::round(255.0f * (c * 0.5f + 0.5f)) / 255.0f * 2.0f - 1.0f; };
  const glm::vec3 expected = glm::normalize(glm::vec3(texel(n.x), texel(n.z), -texel(n.y)));
  EXPECT_NEAR(glm::distance(b.ns, expected), 0.0f, 2e-3f) << b.ns.x << " " << b.ns.y << " " << b.ns.z;
  // Tangents derived from the floor's UVs are the ones the file gives.
  const shader::Triangle& t = cs.triangles[h.prim];
  const shader::TriangleShading sh = view.load_shading(t.shading);
  const glm::vec4 derived = view.triangle_uv_tangent(t, {sh.u0, sh.v0}, {sh.uv12.x, sh.uv12.y}, {sh.uv12.z, sh.uv12.w}, hit.ng);
  EXPECT_NEAR(glm::distance(glm::normalize(glm::vec3(derived)), glm::vec3(1, 0, 0)), 0.0f, 1e-5f);
  EXPECT_EQ(derived.w, 1.0f);
}

// glTF's PBR extensions (layers.glb): a coat and a sheen become layers over
// the metal-rough base, which carries the specular factor and colour, the
// thin film, the anisotropy and the volume; each texture is read in its
// extension's channel (the image's left half has red 1 and alpha 1, its
// right half red 0 and alpha 64/255).
TEST(Gltf, PbrExtensionsBecomeLayersReadingTheirChannels) {
  const Scene s = load_scene(gltf_path("layers.glb"));
  auto named = [&](const std::string& name) {
    for (const SceneMaterial& m : s.materials)
      if (m.name == name) return m;
    ADD_FAILURE() << "no material " << name;
    return SceneMaterial{};
  };
  const SceneMaterial coat = named("lacquer (clear coat)"), sheen = named("velvet (sheen)"), tinted = named("tinted");
  ASSERT_EQ(coat.kind, MAT_CLEARCOAT);
  ASSERT_EQ(sheen.kind, MAT_SHEEN);
  EXPECT_EQ(s.materials.at(coat.part(0)).kind, MAT_METAL_ROUGH);
  EXPECT_EQ(s.materials.at(coat.part(0)).normalMap, WP_INVALID);  // the coat's normal map is not the base's
  ASSERT_NE(coat.normalMap, WP_INVALID);
  EXPECT_EQ(s.textures[coat.normalMap].color, glm::vec3(0.7f, 0.7f, 1.0f));
  EXPECT_EQ(coat.record.params.x, 1.5f);
  EXPECT_EQ(tinted.kind, MAT_METAL_ROUGH);
  EXPECT_NEAR(glm::distance(tinted.record.params2, glm::vec4(1.0f, 0.5f, 0.0f, -0.2f)), 0.0f, 1e-6f);
  const CompiledScene cs = compile_scene(s, RenderOptions{});
  EXPECT_TRUE(cs.params.kinds.w & KIND_BIT(FEATURE_SPECULAR_TINT));
  shader::SceneView view = cs.view();
  const glm::vec3 p(0.0f);
  auto at = [&](uint32_t tex, float u) { return view.texture_eval(tex, glm::vec4(u, 0.5f, 0.0f, 0.0f), p); };
  const float left = 1.0f / 16.0f, right = 9.0f / 16.0f, quarter = 64.0f / 255.0f;
  EXPECT_NEAR(at(coat.albedo(), left).x, 0.9f, 1e-3f);  // clearcoatTexture: red
  EXPECT_NEAR(at(coat.albedo(), right).x, 0.0f, 1e-3f);
  EXPECT_NEAR(at(coat.amount(), left).y, 0.5f * quarter, 2e-3f);  // clearcoatRoughnessTexture: green
  EXPECT_NEAR(at(sheen.amount(), left).y, 0.8f, 1e-3f);  // sheenRoughnessTexture: alpha
  EXPECT_NEAR(at(sheen.amount(), right).y, 0.8f * quarter, 2e-3f);
  EXPECT_NEAR(at(glm::floatBitsToUint(tinted.record.extra[MR_TEXTURES].x), right).x, quarter, 2e-3f);  // specularTexture: alpha
  EXPECT_NE(glm::floatBitsToUint(tinted.record.extra[MR_TEXTURES].y), WP_INVALID);
  // KHR_materials_iridescence, _anisotropy and _volume on the lower row.
  const SceneMaterial film = named("film"), brushed = named("brushed"), glass = named("glass");
  EXPECT_EQ(film.record.extra[MR_IRIDESCENCE], glm::vec4(1.0f, 1.4f, 200.0f, 500.0f));
  EXPECT_NE(glm::floatBitsToUint(film.record.extra[MR_TEXTURES].z), WP_INVALID);
  EXPECT_NE(glm::floatBitsToUint(film.record.extra[MR_TEXTURES].w), WP_INVALID);
  EXPECT_FLOAT_EQ(brushed.record.extra[MR_ANISOTROPY].x, 0.9f);
  EXPECT_FLOAT_EQ(brushed.record.extra[MR_ANISOTROPY].y, std::cos(0.4f));
  EXPECT_NE(glm::floatBitsToUint(brushed.record.extra[MR_ANISOTROPY].w), WP_INVALID);
  EXPECT_FLOAT_EQ(glass.record.extra[MR_VOLUME].w, 1.6f);  // 1 + the dispersion
  EXPECT_TRUE(glass.doubleSided);  // a volume's boundary is there from inside
  EXPECT_NEAR(glm::distance(glm::vec3(glass.record.extra[MR_VOLUME]), -glm::log(glm::vec3(0.9f, 0.4f, 0.2f)) / 0.8f), 0.0f, 1e-5f);
  for (uint32_t f : {FEATURE_IRIDESCENCE, FEATURE_ANISOTROPY, FEATURE_VOLUME}) EXPECT_TRUE(cs.params.kinds.w & KIND_BIT(f)) << f;
}

// A normal-mapped mesh without TANGENT (the README's spot.glb) gets smooth
// tangents: unit, orthogonal to each corner's normal, and turned as the
// UVs run on the triangles around it.
TEST(Gltf, NormalMappedMeshesWithoutTangentsGetSmoothOnes) {
  const Scene s = load_scene(source_path("scenes/spot.glb"));
  int corners = 0, along = 0;
  for (const SceneTriangle& t : s.triangles) {
    if (s.materials[t.material].normalMap == WP_INVALID) continue;
    const SceneTriangleShading& sh = s.triangleShading.at(t.shading);
    ASSERT_TRUE(sh.hasVertexData && sh.hasNormals && sh.hasUvs);
    const glm::vec3 e1 = t.v[1] - t.v[0], e2 = t.v[2] - t.v[0];
    const glm::vec2 d1 = sh.uv[1] - sh.uv[0], d2 = sh.uv[2] - sh.uv[0];
    const glm::vec3 dpdu = (e1 * d2.y - e2 * d1.y) / (d1.x * d2.y - d2.x * d1.y);
    for (int c = 0; c < 3; ++c) {
      const glm::vec3 tangent(sh.tangent[c]);
      ASSERT_NEAR(glm::length(tangent), 1.0f, 1e-4f);
      EXPECT_NEAR(glm::dot(tangent, sh.n[c]), 0.0f, 1e-4f);
      ++corners;
      if (glm::dot(tangent, dpdu) > 0.0f) ++along;
    }
  }
  EXPECT_GT(corners, 10000);
  EXPECT_GT(along, 0.97 * corners) << along << " of " << corners;
}

// A white mirror sphere under a steep normal map (slopes to 56 degrees), lit
// by the default white sky: a white furnace, every pixel 1 unless mapped
// normals lose light. Mirrored about such a normal the view ray went below
// the surface and the path ended: 15 % of the image (most of the sphere)
// rendered black. valid_reflection_normal keeps the reflection above it; what
// is left is the silhouette's, where a grazing ray's glossy lobe (alpha
// 1e-3) dips under the faceted surface, as it does without a map.
TEST(Gltf, NormalMappedMirrorLosesNoLightUnderAWhiteSky) {
  Scene s = load_scene(gltf_path("mirror-bumps.glb"));
  EXPECT_EQ(s.background, glm::vec3(1.0f));
  s.camera.width = s.camera.height = 64;
  RenderOptions o;
  o.spp = 16;
  Progress quiet("", 0, false);
  const ImageStats image = render_cpu(compile_scene(s, reference_options(o)), 0, quiet);
  double sum = 0.0, darkest = 1.0;
  for (size_t p = 0; p < image.pixels(); ++p) {
    sum += image.mean(p).x;
    darkest = std::min(darkest, image.mean(p).x);
  }
  EXPECT_GT(sum / double(image.pixels()), 0.99) << "the furnace loses light";
  EXPECT_GT(darkest, 0.5) << "a pixel of the mirror is (nearly) black";
}

TEST(Gltf, ExternalFilesAreReadOnlyInsideTheModelsFolder) {
  const Scene s = load_scene(gltf_path("external/scene.gltf"));
  EXPECT_EQ(s.triangles.size(), 2u);
  auto read = [&](const char* name) {
    return std::any_of(s.inputFiles.begin(), s.inputFiles.end(), [&](const std::string& f) { return f.find(name) != std::string::npos; });
  };
  EXPECT_TRUE(read("scene.bin"));
  EXPECT_TRUE(read("scene.gltf"));
  // The same model moved one folder down, its buffer left above it.
  const std::filesystem::path dir = scratch_dir(*testing::UnitTest::GetInstance()->current_test_info());
  std::filesystem::create_directories(dir / "model");
  std::filesystem::copy_file(gltf_path("external/scene.bin"), dir / "secret.bin", std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(gltf_path("external/checker.png"), dir / "model/checker.png", std::filesystem::copy_options::overwrite_existing);
  json doc = read_json(gltf_path("external/scene.gltf"));
  for (const std::string& uri : std::vector<std::string>{"../secret.bin", (dir / "secret.bin").string()}) {
    doc["buffers"][0]["uri"] = uri;
    const std::string path = (dir / "model/scene.gltf").string();
    std::ofstream(path) << doc.dump();
    expect_refused(path, {"secret.bin", "inside its own folder"});
  }
}

// A base64 data URI of raw bytes.
std::string data_uri(const std::vector<uint8_t>& bytes) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out = "data:application/octet-stream;base64,";
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t n = uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0u) | (i + 2 < bytes.size() ? bytes[i + 2] : 0u);
    out += kDigits[n >> 18 & 63];
    out += kDigits[n >> 12 & 63];
    out += i + 1 < bytes.size() ? kDigits[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[n & 63] : '=';
  }
  return out;
}

// One triangle whose positions are `floats` (nine of them).
json one_triangle(const std::vector<float>& floats) {
  std::vector<uint8_t> bytes(floats.size() * 4);
  std::memcpy(bytes.data(), floats.data(), bytes.size());
  json doc = json::parse(R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}], "buffers": [{"byteLength": 36}]})");
  doc["buffers"][0]["uri"] = data_uri(bytes);
  return doc;
}

void expect_gltf_error(const std::string& name, const std::string& bytes, std::initializer_list<const char*> parts) {
  const std::string path = scratch_path(name);
  std::ofstream(path, std::ios::binary) << bytes;
  expect_refused(path, parts);
}

TEST(Gltf, BadInputIsRefusedInOneLineNamingThePlace) {
  const json good = one_triangle({0, 0, 0, 1, 0, 0, 0, 1, 0});
  ASSERT_EQ(load_scene(write_scene("good.gltf", good.dump())).triangles.size(), 1u);
  auto with = [&](const json& patch) {
    json doc = good;
    doc.merge_patch(patch);
    return doc.dump();
  };
  expect_gltf_error("syntax.gltf", "{\"asset\": ", {"cannot read glTF"});
  // What tinygltf passes without a word, named where it is.
  expect_gltf_error("version.gltf", with({{"asset", {{"version", "1.0"}}}}), {"/asset/version", "glTF 1.0 is not supported"});
  json primitivesObject = good;
  primitivesObject["meshes"][0]["primitives"] = good["meshes"][0]["primitives"][0];
  expect_gltf_error("primitives.gltf", primitivesObject.dump(), {"/meshes/0/primitives", "must be an array of primitives, not object"});
  expect_gltf_error("version1.glb", std::string("glTF\1\0\0\0\24\0\0\0\0\0\0\0\0\0\0\0", 20), {"glTF 1.0 is not supported"});
  expect_gltf_error("nan.gltf", one_triangle({0, 0, 0, NAN, 0, 0, 0, 1, 0}).dump(), {"/attributes/POSITION", "finite"});
  expect_gltf_error("count.gltf", with({{"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}}}}}),
                    {"/accessors/0", "past the end of buffer view 0"});
  expect_gltf_error("view.gltf", with({{"bufferViews", {{{"buffer", 0}, {"byteLength", 48}}}}}), {"/bufferViews/0", "past the end of buffer 0"});
  expect_gltf_error("type.gltf", with({{"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC2"}}}}}),
                    {"/accessors/0/type", "VEC3"});
  json indexed = good;
  indexed["meshes"][0]["primitives"][0]["indices"] = 1;
  // The indices are the bytes of the positions 1, 0, 0: 1.0f as an unsigned int is 1065353216.
  indexed["accessors"].push_back({{"bufferView", 0}, {"byteOffset", 12}, {"componentType", 5125}, {"count", 3}, {"type", "SCALAR"}});
  expect_gltf_error("indices.gltf", indexed.dump(), {"/accessors/1", "names no vertex"});
  json points = good;
  points["meshes"][0]["primitives"][0]["mode"] = 0;
  expect_gltf_error("points.gltf", points.dump(), {"/meshes/0/primitives/0/mode", "triangles only, not points"});
  json cycle = good;
  cycle["nodes"] = json::parse(R"([{"mesh": 0, "children": [1]}, {"children": [0]}])");
  expect_gltf_error("cycle.gltf", cycle.dump(), {"/nodes/1/children/0", "its own ancestor"});
  expect_gltf_error("node.gltf", with({{"scenes", {{{"nodes", {7}}}}}}), {"/scenes/0/nodes/0", "node 7"});
  expect_gltf_error("required.gltf", with({{"extensionsRequired", {"KHR_draco_mesh_compression"}}}),
                    {"/extensionsRequired/0", "KHR_draco_mesh_compression"});
  json material = good;
  material["meshes"][0]["primitives"][0]["material"] = 3;
  expect_gltf_error("material.gltf", material.dump(), {"/meshes/0/primitives/0/material", "material 3"});
  json image = good;
  image["meshes"][0]["primitives"][0]["material"] = 0;
  image["materials"] = json::parse(R"([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}])");
  image["textures"] = json::parse(R"([{"source": 0}])");
  image["images"] = json::array({{{"uri", data_uri({'n', 'o', 't', ' ', 'a', 'n', ' ', 'i', 'm', 'a', 'g', 'e'})}}});
  expect_gltf_error("image.gltf", image.dump(), {"/images/0", "not a PNG"});
  // Material and attribute values outside what glTF allows.
  auto with_material = [&](const char* material) {
    json doc = good;
    doc["meshes"][0]["primitives"][0]["material"] = 0;
    doc["materials"] = json::array({json::parse(material)});
    return doc.dump();
  };
  expect_gltf_error("alpha-mode.gltf", with_material(R"({"alphaMode": "CUTOUT"})"), {"/materials/0/alphaMode", "OPAQUE, MASK or BLEND"});
  expect_gltf_error("cutoff.gltf", with_material(R"({"alphaMode": "MASK", "alphaCutoff": 1.5})"), {"/materials/0/alphaCutoff", "[0, 1]"});
  expect_gltf_error("transmission.gltf", with_material(R"({"extensions": {"KHR_materials_transmission": {"transmissionFactor": 2}}})"),
                    {"/materials/0/extensions/KHR_materials_transmission/transmissionFactor", "[0, 1]"});
  // The PBR extensions' values.
  expect_gltf_error("clearcoat.gltf", with_material(R"({"extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.2}}})"),
                    {"/materials/0/extensions/KHR_materials_clearcoat/clearcoatFactor", "[0, 1]"});
  expect_gltf_error("sheen.gltf", with_material(R"({"extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1, 0.5]}}})"),
                    {"/materials/0/extensions/KHR_materials_sheen/sheenColorFactor", "3 numbers"});
  expect_gltf_error("specular.gltf", with_material(R"({"extensions": {"KHR_materials_specular": {"specularColorFactor": [1, -1, 1]}}})"),
                    {"/materials/0/extensions/KHR_materials_specular/specularColorFactor/1"});
  expect_gltf_error("volume.gltf", with_material(R"({"extensions": {"KHR_materials_volume": {"thicknessFactor": 1, "attenuationDistance": 0}}})"),
                    {"/materials/0/extensions/KHR_materials_volume/attenuationDistance", "above 0"});
  expect_gltf_error("dispersion.gltf",
                    with_material(R"({"extensions": {"KHR_materials_volume": {"thicknessFactor": 1}, "KHR_materials_dispersion": {"dispersion": -1}}})"),
                    {"/materials/0/extensions/KHR_materials_dispersion/dispersion"});
  // Dispersion is read with a volume, and a thin-walled surface ignores it.
  for (bool thick : {true, false}) {
    json doc = json::parse(with_material(thick ? R"({"extensions": {"KHR_materials_volume": {"thicknessFactor": 1}, "KHR_materials_dispersion": {"dispersion": 0.5}}})"
                                               : R"({"extensions": {"KHR_materials_dispersion": {"dispersion": 0.5}}})"));
    const Scene s = load_scene(write_scene(thick ? "dispersive.gltf" : "thin-dispersive.gltf", doc.dump()));
    ASSERT_FALSE(s.materials.empty());
    EXPECT_EQ(s.materials[0].record.extra[MR_VOLUME].w, thick ? 1.5f : 0.0f);  // 1 + the dispersion, 0 thin-walled
    const bool compiled = (compile_scene(s, RenderOptions{}).params.kinds.w & KIND_BIT(FEATURE_DISPERSION)) != 0u;
    EXPECT_EQ(compiled, thick);
  }
  expect_gltf_error("coat-texture.gltf", with_material(R"({"extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatTexture": {"index": 4}}}})"),
                    {"/materials/0/extensions/KHR_materials_clearcoat/clearcoatTexture/index", "texture 4"});
  expect_gltf_error("alpha-factor.gltf", with_material(R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, -1]}})"),
                    {"/materials/0/pbrMetallicRoughness/baseColorFactor/3", "[0, 1]"});
  json sampled = json::parse(with_material(R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 2}}})"));
  sampled["textures"] = json::parse(R"([{"source": 0, "sampler": 0}])");
  sampled["images"] = image["images"];
  sampled["samplers"] = json::parse(R"([{"wrapS": 10497}])");
  expect_gltf_error("texcoord.gltf", sampled.dump(), {"/materials/0/pbrMetallicRoughness/baseColorTexture/texCoord", "not set 2"});
  sampled["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 0;
  sampled["samplers"][0]["wrapT"] = 1234;
  expect_gltf_error("wrap.gltf", sampled.dump(), {"/samplers/0/wrapT", "not a wrap mode"});
  sampled["textures"][0]["sampler"] = 4;
  expect_gltf_error("sampler.gltf", sampled.dump(), {"/textures/0/sampler", "sampler 4"});
  // COLOR_0 read from the positions' accessor, where a 2 is no colour.
  json twice = one_triangle({0, 0, 0, 2, 0, 0, 0, 1, 0});
  twice["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 0;
  expect_gltf_error("color.gltf", twice.dump(), {"/attributes/COLOR_0", "outside [0, 1]"});
  // Binary containers: a wrong magic, a truncated file, a chunk longer than the file.
  std::ifstream in(gltf_path("textured.glb"), std::ios::binary);
  const std::string glb((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  expect_gltf_error("magic.glb", "glTX" + glb.substr(4), {"not a binary glTF file"});
  expect_gltf_error("truncated.glb", glb.substr(0, glb.size() / 2), {"cannot read glTF"});
  std::string longChunk = glb;
  longChunk[12] = char(0xff);
  longChunk[13] = char(0xff);
  expect_gltf_error("chunk.glb", longChunk, {"cannot read glTF"});
}

// The default light: a model without punctual lights is lit by the white
// sky where its emitters are no brighter than that sky (a label: here one
// that would light its small model if it counted); one with a punctual
// light is not. Animations are named in the warning.
TEST(Gltf, WhiteSkyUnlessTheModelBringsPunctualLights) {
  json glow = one_triangle({0, 0, 0, 1, 0, 0, 0, 1, 0});
  glow["meshes"][0]["primitives"][0]["material"] = 0;
  glow["materials"] = json::parse(R"([{"emissiveFactor": [1, 0.5, 0.2]}])");
  Scene s = load_scene(write_scene("glow.gltf", glow.dump()));
  EXPECT_EQ(s.background, glm::vec3(1.0f)) << "an emissive label switched the sky off";
  json lit = glow;
  lit["extensionsUsed"] = {"KHR_lights_punctual"};
  lit["extensions"] = json::parse(R"({"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 100}]}})");
  lit["nodes"].push_back(json::parse(R"({"translation": [0, 0, 2], "extensions": {"KHR_lights_punctual": {"light": 0}}})"));
  lit["scenes"][0]["nodes"].push_back(1);
  EXPECT_EQ(load_scene(write_scene("lit.gltf", lit.dump())).background, glm::vec3(0.0f));
  json animated = glow;
  animated["animations"] = json::parse(R"([{"channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
                                           "samplers": [{"input": 0, "output": 0}]}])");
  testing::internal::CaptureStderr();
  load_scene(write_scene("animated.gltf", animated.dump()));
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("not read yet, rendered without: animations (the model renders at rest)"), std::string::npos) << said;
}

// The default sky only where a file has no light worth the name
// (default_sky_wanted): a room lit by an emissive mesh as Blender exports it
// renders by its lamp alone; balls with emissive labels no brighter than a
// white surface get the sky, as viewers show them (counted as lights, those
// labels would emit enough to switch it off); so does a model whose one
// emitter brighter than the sky is a speck. One line on stderr exactly when
// the sky is added; --env none and --env sky say what they are asked.
TEST(Gltf, DefaultSkyOnlyWhereNoLightIsWorthTheName) {
  const std::string room = gltf_path("lamp-room.glb"), labels = gltf_path("labels.glb");
  struct Case {
    std::string file, env;
    bool line;
    float background;
  };
  const Case cases[] = {{labels, "", true, 1.0f},  {labels, "none", false, 0.0f}, {labels, "sky", false, 1.0f},
                        {room, "", false, 0.0f},   {room, "none", false, 0.0f},   {room, "sky", false, 1.0f}};
  for (const Case& c : cases) {
    Scene s = load_scene(c.file);
    EXPECT_EQ(s.defaultSky, c.file == labels) << c.file;
    testing::internal::CaptureStderr();
    apply_environment(s, c.env);
    const std::string said = testing::internal::GetCapturedStderr();
    EXPECT_EQ(s.background, glm::vec3(c.background)) << c.file << " --env '" << c.env << "'";
    if (c.line) {
      EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), 1) << said;
      EXPECT_NE(said.find(c.file + ": "), std::string::npos) << said;
      EXPECT_NE(said.find("white sky"), std::string::npos) << said;
      EXPECT_NE(said.find("--env none removes it"), std::string::npos) << said;
    } else {
      EXPECT_EQ(said, "") << c.file << " --env '" << c.env << "'";
    }
  }
  // Rendered: the camera sees past the room's open front, black without the
  // sky, white with it asked for.
  Scene s = load_scene(room);
  s.integrator.maxBounces = 1;
  set_resolution(s.camera, 32, 24);
  RenderOptions o;
  o.spp = 2;
  Progress quiet("", 0, false);
  EXPECT_EQ(render_cpu(compile_scene(s, reference_options(o)), 0, quiet).mean(0), glm::dvec3(0.0));
  apply_environment(s, "sky");
  EXPECT_EQ(render_cpu(compile_scene(s, reference_options(o)), 0, quiet).mean(0), glm::dvec3(1.0));
  // The threshold: a bright emitter is a light when it emits at least
  // kEmittersLightTheScene of what the sky would pour onto the model's box.
  // An emissive triangle of area 0.5 and strength 40 (illuminance 23.4)
  // in a 1 x 1 box: a light; the same beside a second triangle that widens the box to 100 x
  // 100: a speck (its 11.7 against 2 * 100 * 100: below 5 %).
  const std::vector<float> glow = {0, 0, 0, 1, 0, 0, 0, 1, 0}, wide = {0, 0, 0, 100, 0, 0, 0, 100, 0};
  for (bool speck : {false, true}) {
    std::vector<float> floats = glow;
    if (speck) floats.insert(floats.end(), wide.begin(), wide.end());
    json doc = one_triangle(floats);
    doc["accessors"][0]["count"] = 3;
    doc["bufferViews"][0]["byteLength"] = 36;
    doc["buffers"][0]["byteLength"] = floats.size() * 4;
    if (speck) {
      doc["accessors"].push_back(json::parse(R"({"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"})"));
      doc["bufferViews"].push_back(json::parse(R"({"buffer": 0, "byteOffset": 36, "byteLength": 36})"));
      doc["meshes"][0]["primitives"].push_back(json::parse(R"({"attributes": {"POSITION": 1}})"));
    }
    doc["meshes"][0]["primitives"][0]["material"] = 0;
    doc["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    doc["materials"] = json::parse(R"([{"emissiveFactor": [1, 0.5, 0.2], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 40}}}])");
    const Scene g = load_scene(write_scene(speck ? "speck.gltf" : "lamp.gltf", doc.dump()));
    EXPECT_EQ(g.defaultSky, speck) << (speck ? "a speck of light switched the sky off" : "a light got the sky");
  }
}

// One material, written once in glTF's vocabulary (with every extension the
// metal-rough module reads) and once in darts', packs into the same records:
// the importers only translate names, and the modules pack.
TEST(Gltf, AMaterialPacksAsItsDartsTwinDoes) {
  json doc = one_triangle({0, 0, 0, 1, 0, 0, 0, 1, 0});
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  doc["materials"] = json::parse(R"([{"name": "twin",
    "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.4, 0.3, 1], "metallicFactor": 0.2, "roughnessFactor": 0.6},
    "emissiveFactor": [1, 0.5, 0.25],
    "extensions": {
      "KHR_materials_ior": {"ior": 1.4},
      "KHR_materials_transmission": {"transmissionFactor": 0.3},
      "KHR_materials_specular": {"specularFactor": 0.7, "specularColorFactor": [0.9, 0.8, 0.7]},
      "KHR_materials_volume": {"thicknessFactor": 1, "attenuationColor": [0.5, 0.6, 0.7], "attenuationDistance": 2},
      "KHR_materials_dispersion": {"dispersion": 0.5},
      "KHR_materials_iridescence": {"iridescenceFactor": 0.8, "iridescenceIor": 1.5, "iridescenceThicknessMinimum": 120,
                                    "iridescenceThicknessMaximum": 380},
      "KHR_materials_anisotropy": {"anisotropyStrength": 0.4, "anisotropyRotation": 0.3},
      "KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.35, "diffuseTransmissionColorFactor": [0.9, 0.2, 0.1]},
      "KHR_materials_sheen": {"sheenColorFactor": [0.2, 0.3, 0.4], "sheenRoughnessFactor": 0.5},
      "KHR_materials_clearcoat": {"clearcoatFactor": 0.6, "clearcoatRoughnessFactor": 0.2}}}])");
  const Scene g = load_scene(write_scene("twin.gltf", doc.dump()));
  const Scene d = load_scene(write_scene("twin.json", R"({"camera": {"resolution": [4, 4]}, "materials": [{"type": "clearcoat", "name": "twin",
    "factor": 0.6, "roughness": 0.2, "emit": [1, 0.5, 0.25], "base": {"type": "sheen", "color": [0.2, 0.3, 0.4], "roughness": 0.5,
    "base": {"type": "metal_rough", "base_color": [0.5, 0.4, 0.3], "metallic": 0.2, "roughness": 0.6, "ior": 1.4, "transmission": 0.3,
      "specular": 0.7, "specular_color": [0.9, 0.8, 0.7],
      "volume": {"attenuation_color": [0.5, 0.6, 0.7], "attenuation_distance": 2, "dispersion": 0.5},
      "iridescence": {"factor": 0.8, "ior": 1.5, "thickness_minimum": 120, "thickness_maximum": 380},
      "anisotropy": {"strength": 0.4, "rotation": 0.3},
      "diffuse_transmission": 0.35, "diffuse_transmission_color": [0.9, 0.2, 0.1]}}}],
    "surfaces": [{"type": "sphere", "material": "twin"}]})"));
  ASSERT_EQ(g.materials.size(), 3u);
  ASSERT_EQ(d.materials.size(), 3u);
  auto colour = [](const Scene& s, uint32_t t) { return t == WP_INVALID ? glm::vec3(-1.0f) : s.textures[t].color; };
  for (size_t i = 0; i < 3; ++i) {
    const SceneMaterial &a = g.materials[i], &b = d.materials[i];
    SCOPED_TRACE(kind_list(material_kinds(), KIND_BIT(a.kind)));
    EXPECT_EQ(a.kind, b.kind);
    // The record less its texture and part indices, which differ with the order the importers add them.
    EXPECT_EQ(a.record.params, b.record.params);
    EXPECT_EQ(a.record.params2, b.record.params2);
    EXPECT_EQ(a.record.extra[MR_VOLUME], b.record.extra[MR_VOLUME]);
    EXPECT_EQ(a.record.extra[MR_IRIDESCENCE], b.record.extra[MR_IRIDESCENCE]);
    EXPECT_EQ(glm::vec3(a.record.extra[MR_ANISOTROPY]), glm::vec3(b.record.extra[MR_ANISOTROPY]));
    EXPECT_EQ(a.record.extra[MR_DIFFUSE_TRANSMISSION], b.record.extra[MR_DIFFUSE_TRANSMISSION]);
    EXPECT_EQ(a.part(0) == WP_INVALID, b.part(0) == WP_INVALID);
    EXPECT_EQ(colour(g, a.albedo()), colour(d, b.albedo()));
    EXPECT_EQ(colour(g, a.amount()), colour(d, b.amount()));
    EXPECT_EQ(colour(g, a.emission), colour(d, b.emission));
  }
  EXPECT_EQ(g.materials[2].kind, MAT_CLEARCOAT);
  EXPECT_NE(g.materials[2].emission, WP_INVALID) << "the top layer carries the emission";
  EXPECT_GT(g.materials[0].record.extra[MR_VOLUME].w, 0.0f) << "a volume";
  EXPECT_EQ(g.materials[0].record.extra[MR_DIFFUSE_TRANSMISSION], glm::vec4(0.9f, 0.2f, 0.1f, 0.35f));
}

// KHR_materials_diffuse_transmission's textures: the factor's alpha (as grey)
// and the colour's sRGB; a factor out of range names its path.
TEST(Gltf, DiffuseTransmissionReadsItsTexturesChannels) {
  json doc = one_triangle({0, 0, 0, 1, 0, 0, 0, 1, 0});
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  doc["materials"] = json::parse(R"([{"extensions": {"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.5,
    "diffuseTransmissionTexture": {"index": 0}, "diffuseTransmissionColorTexture": {"index": 0}}}}])");
  doc["textures"] = json::parse(R"([{"source": 0}])");
  doc["images"] = json::parse(R"([{"uri": "rgba.png"}])");
  // One texel: red 255, green 0, blue 0, alpha 64.
  const unsigned char texel[4] = {255, 0, 0, 64};
  ASSERT_TRUE(stbi_write_png(scratch_path("rgba.png").c_str(), 1, 1, 4, texel, 4));
  const Scene s = load_scene(write_scene("dt.gltf", doc.dump()));
  const glm::vec4 dt = s.materials[0].record.extra[MR_DIFFUSE_TRANSMISSION];
  EXPECT_EQ(dt, glm::vec4(1.0f, 1.0f, 1.0f, 0.5f));
  const glm::uvec4 textures = glm::floatBitsToUint(s.materials[0].record.extra[MR_DIFFUSE_TRANSMISSION_TEXTURES]);
  ASSERT_NE(textures.x, WP_INVALID);
  ASSERT_NE(textures.y, WP_INVALID);
  const CompiledScene cs = compile_scene(s, RenderOptions{});
  shader::SceneView view = cs.view();
  const glm::vec3 factor = view.texture_eval(textures.x, glm::vec4(0.5f), glm::vec3(0.0f));
  const glm::vec3 colour = view.texture_eval(textures.y, glm::vec4(0.5f), glm::vec3(0.0f));
  EXPECT_NEAR(factor.x, 64.0f / 255.0f, 2e-3f) << "the factor is the alpha, linear";
  EXPECT_NEAR(colour.x, 1.0f, 2e-3f);
  EXPECT_NEAR(colour.y, 0.0f, 2e-3f);
  doc["materials"][0]["extensions"]["KHR_materials_diffuse_transmission"]["diffuseTransmissionFactor"] = 2;
  expect_error(doc.dump(), {"/materials/0/extensions/KHR_materials_diffuse_transmission/diffuseTransmissionFactor", "[0, 1]"}, "bad.gltf");
}

// translucent.glb (scripts/make-gltf-test-assets.py), laid out as the
// Khronos DiffuseTransmissionTest: panes lit from behind by a sun of 3 W/m^2
// along the view, direct light only. As that model's README describes, the
// panes of factor f glow with what they let through, (1 - F0) f E / pi with
// F0 = 0.04 (white, then red of the colour factor), and nothing of their
// base colour; the texture row's brighter where its texture's alpha is.
TEST(Gltf, BacklitPanesGlowWithTheirDiffuseTransmission) {
  Scene scene = load_scene(source_path("tests/data/gltf/translucent.glb"));
  scene.integrator.maxBounces = 1;
  set_resolution(scene.camera, 140, 100);
  scene.samplesPerPixel = 16;
  RenderOptions o;
  const CompiledScene cs = compile_scene(scene, reference_options(o));
  Progress quiet("", 0, false);
  const ImageStats img = render_cpu(cs, 0, quiet);
  const double tanHalf = std::tan(0.3), irradiance = 3.0;
  auto pane = [&](int column, int row, double along = 0.0) {  // the mean of the 3 x 3 pixels at a pane's centre (+ along)
    const double x = 1.2 * (column - 2) + along, y = 1.8 - 1.2 * row;
    const int px = int((x / 9.0 / tanHalf / 1.4 + 1.0) * 0.5 * 140), py = int((1.0 - y / 9.0 / tanHalf) * 0.5 * 100);
    glm::dvec3 sum(0.0);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) sum += glm::dvec3(img.mean(size_t(py + dy) * 140 + size_t(px + dx)));
    return sum / 9.0;
  };
  for (int c = 0; c < 5; ++c) {
    const double f = 0.25 * c, expected = 0.96 * f * irradiance / M_PI;
    const glm::dvec3 white = pane(c, 0), red = pane(c, 1);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(white[ch], expected, 0.01 * expected + 1e-4) << "factor " << f << ", channel " << ch;
    EXPECT_NEAR(red.x, expected, 0.01 * expected + 1e-4) << "red, factor " << f;
    EXPECT_NEAR(red.y + red.z, 0.0, 1e-4) << "red, factor " << f;
    // The texture row: its factor's alpha ramps from 16/255 to 240/255 across each pane.
    EXPECT_GT(pane(c, 2, 0.3).x, 1.5 * pane(c, 2, -0.3).x) << "the factor texture's alpha, pane " << c;
  }
}

// KHR_materials_volume_scatter (KhronosGroup/glTF PR #2453 at 134d0766,
// README.md:85-127): the attenuation is the whole extinction
// sigma_t = -ln(c) / d, split into scattering sigma_t rho and absorption
// sigma_t (1 - rho) by the single-scattering albedo rho of Kulla and
// Conty's fit to the multiscatter colour, written here again; the medium is
// the volume's inside, which no longer absorbs by itself. Its darts twin,
// and both names the draft has given the colour, make the same medium.
TEST(Gltf, VolumeScatterMakesTheMediumInside) {
  auto rho = [](double a) {
    const double s = 4.09712 + 4.20863 * a - std::sqrt(9.59217 + 41.6808 * a + 17.7126 * a * a);
    return std::clamp(1.0 - s * s, 0.0, 1.0);
  };
  EXPECT_NEAR(rho(0.5), 0.912, 1e-3);  // the draft's own curve
  const glm::dvec3 multiscatter(0.1, 0.5, 0.9);
  const double sigmaT = std::log(2.0) / 2.0;
  auto check = [&](const Scene& s, const char* what) {
    SCOPED_TRACE(what);
    ASSERT_EQ(s.media.size(), 1u);
    const SceneMedium& m = s.media[0];
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(m.sigmaS[c], sigmaT * rho(multiscatter[c]), 1e-5) << "channel " << c;
      EXPECT_NEAR(m.sigmaA[c], sigmaT * (1.0 - rho(multiscatter[c])), 1e-5) << "channel " << c;
    }
    EXPECT_FLOAT_EQ(m.g, 0.3f);
    const SceneMaterial& glass = s.materials.back();
    EXPECT_TRUE(glass.boundsMedia);
    EXPECT_EQ(glass.interior, 0u);
    EXPECT_EQ(glm::vec3(glass.record.extra[MR_VOLUME]), glm::vec3(0.0f)) << "the medium absorbs, not the surface";
    EXPECT_GT(glass.record.extra[MR_VOLUME].w, 0.0f) << "still a volume's boundary";
  };
  json doc = one_triangle({0, 0, 0, 1, 0, 0, 0, 1, 0});
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  for (const char* key : {"multiscatterColorFactor", "multiscatterColor"}) {
    doc["materials"] = json::parse(std::string(R"([{"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
      "KHR_materials_volume": {"thicknessFactor": 1, "attenuationColor": [0.5, 0.5, 0.5], "attenuationDistance": 2},
      "KHR_materials_volume_scatter": {")") + key + R"(": [0.1, 0.5, 0.9], "scatterAnisotropy": 0.3}}}])");
    check(load_scene(write_scene("scatter.gltf", doc.dump())), key);
  }
  check(load_scene(write_scene("scatter.json", R"({"camera": {"resolution": [4, 4]}, "materials": [{"type": "metal_rough", "name": "m",
    "transmission": 1, "volume": {"attenuation_color": 0.5, "attenuation_distance": 2, "multiscatter_color": [0.1, 0.5, 0.9],
    "scatter_anisotropy": 0.3}}], "surfaces": [{"type": "sphere", "material": "m"}]})")), "darts");
  doc["materials"][0]["extensions"]["KHR_materials_volume_scatter"]["scatterAnisotropy"] = 2;
  expect_error(doc.dump(), {"/materials/0/extensions/KHR_materials_volume_scatter/scatterAnisotropy", "[-1, 1]"}, "bad.gltf");
}

}  // namespace
}  // namespace wp::test
