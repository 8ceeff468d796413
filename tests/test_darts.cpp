// The darts dialect (docs/scene-format.md): each key the darts-2022 skeleton
// reads, loaded with its darts meaning or refused with the reason; test
// files of every kind run on the CPU reference, against analytic densities;
// and a planted pdf error that the verdict must catch.
#include <cmath>
#include <cstdio>
#include <fstream>

#include "scene/darts_tests.h"
#include "stats/darts_tests.h"
#include "stats/direction_test.h"
#include "test_support.h"

namespace wp::test {
namespace {

Scene load_text(const std::string& name, const std::string& text) {
  return load_scene(write_scene(name, text));
}

// ---- the scene vocabulary ------------------------------------------------------

TEST(DartsKeys, NameIsALabelOnEverySurfaceKind) {
  std::string obj = scratch_path("tri.obj");
  std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  Scene s = load_text("names.json", R"({"camera": {}, "materials": [{"type": "lambertian", "name": "m"}], "surfaces": [
    {"type": "sphere", "name": "ball", "material": "m"},
    {"type": "quad", "name": "floor", "material": "m"},
    {"type": "triangle", "name": "tri", "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "material": "m"},
    {"type": "mesh", "name": "obj", "filename": "tri.obj", "material": "m"},
    {"type": "group", "name": "g", "children": [{"type": "sphere", "name": "inner", "material": "m"}]},
    {"type": "point_light", "name": "lamp", "intensity": 1}]})");
  EXPECT_EQ(s.spheres.size(), 2u);
  EXPECT_EQ(s.triangles.size(), 4u);
  EXPECT_EQ(s.pointLights.size(), 1u);
}

TEST(DartsKeys, TriangleUvsAreItsTextureCoordinates) {
  Scene s = load_text("uvs.json", R"({"camera": {}, "surfaces": [{"type": "triangle", "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
    "uvs": [[0.1, 0.2], [0.9, 0.2], [0.1, 0.8]], "material": {"type": "lambertian"}}]})");
  ASSERT_EQ(s.triangles.size(), 1u);
  ASSERT_NE(s.triangles[0].shading, WP_INVALID);
  const SceneTriangleShading& sh = s.triangleShading[s.triangles[0].shading];
  EXPECT_TRUE(sh.hasUvs);
  EXPECT_FALSE(sh.hasNormals);
  EXPECT_EQ(sh.uv[1], glm::vec2(0.9f, 0.2f));
  expect_error(R"({"surfaces": [{"type": "triangle", "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "uvs": [[0, 0], [1, 0]],
    "material": {"type": "lambertian"}}]})",
               {"/surfaces/0/uvs", "expected 3 vertex UVs"});
}

TEST(DartsKeys, MetalRoughnessIsClampedAsDartsClampsIt) {
  Scene s = load_text("metal.json", R"({"camera": {}, "materials": [{"type": "metal", "name": "a", "roughness": -0.1},
    {"type": "metal", "name": "b", "roughness": 1.5}, {"type": "metal", "name": "c", "roughness": 0.25}]})");
  ASSERT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(s.materials[0].record.params.x, 0.0f);
  EXPECT_EQ(s.materials[1].record.params.x, 1.0f);
  EXPECT_EQ(s.materials[2].record.params.x, 0.25f);
}

// wavepath's GGX materials in darts files: alpha = roughness^2, 0 below
// GGX_MIN_ALPHA (a smooth lobe); eta and k per channel; glTF's defaults for
// metal-rough; every value checked with its JSON path.
TEST(DartsKeys, MicrofacetMaterialsReadTheirParameters) {
  Scene s = load_text("ggx.json", R"({"camera": {}, "materials": [
    {"type": "rough_conductor", "name": "gold", "eta": [0.14, 0.37, 1.44], "k": [3.98, 2.38, 1.6], "roughness": 0.5},
    {"type": "rough_conductor", "name": "mirror", "eta": 0.2, "k": 3, "roughness": 0.01},
    {"type": "rough_dielectric", "name": "glass", "ior": 1.33, "roughness": 0.2},
    {"type": "metal_rough", "name": "default"},
    {"type": "metal_rough", "name": "plastic", "base_color": [0.5, 0.1, 0.1], "metallic": 0, "roughness": 0.6, "ior": 1.4,
     "metallic_roughness": {"type": "checker", "even": 1, "odd": 0.5}}]})");
  ASSERT_EQ(s.materials.size(), 5u);
  EXPECT_EQ(s.materials[0].kind, MAT_ROUGH_CONDUCTOR);
  EXPECT_EQ(s.materials[0].record.params, glm::vec4(0.25f, 0.14f, 0.37f, 1.44f));
  EXPECT_EQ(s.materials[0].record.params2, glm::vec4(3.98f, 2.38f, 1.6f, 0.0f));
  EXPECT_EQ(s.materials[1].record.params.x, 0.0f) << "alpha 1e-4 is below GGX_MIN_ALPHA: a mirror";
  EXPECT_EQ(s.materials[2].kind, MAT_ROUGH_DIELECTRIC);
  EXPECT_EQ(s.materials[2].record.params, glm::vec4(1.33f, 0.2f * 0.2f, 0.0f, 0.0f));
  EXPECT_EQ(s.materials[3].record.params, glm::vec4(1.0f, 1.0f, 1.5f, 0.0f)) << "glTF's defaults: roughness 1, metallic 1";
  EXPECT_EQ(s.materials[3].amount(), WP_INVALID);
  EXPECT_EQ(s.materials[4].record.params, glm::vec4(0.6f, 0.0f, 1.4f, 0.0f));
  EXPECT_NE(s.materials[4].amount(), WP_INVALID);
  const char* conductor = R"({"materials": [{"type": "rough_conductor", "name": "m", )";
  expect_error(std::string(conductor) + R"("k": 1}]})", {"/materials/0", "eta"});
  expect_error(std::string(conductor) + R"("eta": [1, -1, 1], "k": 1}]})", {"/materials/0/eta", "eta must lie in (0, 1000) in every channel"});
  expect_error(std::string(conductor) + R"("eta": 1, "k": -2}]})", {"/materials/0/k", "k must lie in [0, 1000) in every channel"});
  expect_error(std::string(conductor) + R"("eta": 1, "k": 1, "roughness": 1.5}]})", {"/materials/0/roughness", "[0, 1]"});
  expect_error(R"({"materials": [{"type": "metal_rough", "name": "m", "metallic": 2}]})", {"/materials/0/metallic", "[0, 1]"});
  expect_error(R"({"materials": [{"type": "rough_dielectric", "name": "m", "ior": 0}]})", {"/materials/0/ior"});
  expect_error(R"({"materials": [{"type": "rough_dielectric", "name": "m", "eta": 1.5}]})", {"/materials/0", "eta"});
  expect_error(R"({"materials": [{"type": "metal_roughh", "name": "m"}]})", {"/materials/0/type", "metal_rough"});
  expect_error(R"({"materials": [{"type": "metal_rough", "name": "m", "transmission": -0.5}]})", {"/materials/0/transmission", "[0, 1]"});
}

// CS184's microfacet conductor: alpha as given (no roughness squared), eta
// and k required, Smith's shadowing unless the skeleton's is asked for.
TEST(DartsKeys, BeckmannConductorReadsItsParameters) {
  Scene s = load_text("beckmann.json", R"({"camera": {}, "materials": [
    {"type": "beckmann_conductor", "name": "smith", "alpha": 0.3, "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1]},
    {"type": "beckmann_conductor", "name": "course", "alpha": 0.05, "eta": 1, "k": 2, "shadowing": "cs184"}]})");
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].kind, MAT_BECKMANN_CONDUCTOR);
  EXPECT_EQ(s.materials[0].record.params, glm::vec4(0.3f, 0.2f, 0.9f, 1.1f));
  EXPECT_EQ(s.materials[0].record.params2, glm::vec4(3.9f, 2.4f, 2.1f, 0.0f));
  EXPECT_EQ(s.materials[1].record.params2, glm::vec4(2.0f, 2.0f, 2.0f, 1.0f));
  const char* m = R"({"materials": [{"type": "beckmann_conductor", "name": "m", )";
  expect_error(std::string(m) + R"("eta": 1, "k": 1}]})", {"/materials/0", "alpha"});
  expect_error(std::string(m) + R"("alpha": 0, "eta": 1, "k": 1}]})", {"/materials/0/alpha"});
  expect_error(std::string(m) + R"("alpha": 0.2, "k": 1}]})", {"/materials/0", "eta"});
  expect_error(std::string(m) + R"("alpha": 0.2, "eta": 1, "k": 1, "shadowing": "ggx"}]})", {"/materials/0/shadowing", "cs184"});
}

// CS184's glass: ior, a transmittance (a texture) and a reflectance, and
// the refraction-only variant.
TEST(DartsKeys, Cs184GlassReadsItsParameters) {
  Scene s = load_text("glass.json", R"({"camera": {}, "materials": [
    {"type": "cs184_glass", "name": "glass", "ior": 1.4, "transmittance": [0.9, 0.8, 0.7], "reflectance": 0.5},
    {"type": "cs184_glass", "name": "refraction", "refraction_only": true}]})");
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].kind, MAT_CS184_GLASS);
  EXPECT_EQ(s.materials[0].record.params, glm::vec4(1.4f, 0.0f, 0.0f, 0.0f));
  EXPECT_EQ(s.materials[0].record.params2, glm::vec4(0.5f, 0.5f, 0.5f, 0.0f));
  EXPECT_EQ(s.textures[s.materials[0].albedo()].color, glm::vec3(0.9f, 0.8f, 0.7f));
  EXPECT_EQ(s.materials[1].record.params, glm::vec4(1.5f, 1.0f, 0.0f, 0.0f));
  EXPECT_EQ(s.materials[1].record.params2, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f));
  const char* m = R"({"materials": [{"type": "cs184_glass", "name": "m", )";
  expect_error(std::string(m) + R"("reflectance": 2}]})", {"/materials/0/reflectance", "[0, 1]"});
  expect_error(std::string(m) + R"("refraction_only": 1}]})", {"/materials/0/refraction_only", "true or false"});
  expect_error(std::string(m) + R"("ior": -1}]})", {"/materials/0/ior"});
}

TEST(DartsKeys, BackgroundDefaultsToDartsGrey) {
  EXPECT_EQ(load_text("bg.json", R"({"camera": {}})").background, glm::vec3(0.2f));
  EXPECT_EQ(load_text("bg0.json", R"({"camera": {}, "background": 0})").background, glm::vec3(0.0f));
}

// darts' checker: odd where sin(x / s) sin(y / s) sin(z / s) < 0, looked up
// at the hit point unless a mapping says otherwise (checker.json's reference).
TEST(DartsKeys, CheckerIsTheSignOfThreeSinesAtTheHitPoint) {
  Scene s = load_text("checker.json", R"({"camera": {}, "materials": [{"type": "lambertian", "name": "c",
    "albedo": {"type": "checker", "even": 0.25, "odd": 0.75, "scale": 0.1}}]})");
  CompiledScene cs = compile_scene(s, RenderOptions());
  shader::SceneView view = cs.view();
  const uint32_t tex = cs.materials[0].info.y;
  uint32_t state = 9;
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    glm::vec3 p(view.rng_next(state) * 4 - 2, view.rng_next(state) * 4 - 2, view.rng_next(state) * 4 - 2);
    double sines = std::sin(p.x / 0.1) * std::sin(p.y / 0.1) * std::sin(p.z / 0.1);
    if (std::fabs(sines) < 1e-3) continue;  // on a boundary, float and double may differ
    glm::vec3 c = view.texture_eval(tex, glm::vec4(0.5f), p);  // the UV must not matter
    EXPECT_EQ(c.x, sines < 0.0 ? 0.75f : 0.25f) << "at " << p.x << ", " << p.y << ", " << p.z;
    ++checked;
  }
  EXPECT_GT(checked, 1900);
}

TEST(DartsKeys, TyposGetASuggestionAndOtherWordsTheList) {
  expect_error(R"({"surfaces": [{"type": "sphere", "radus": 1, "material": {"type": "lambertian"}}]})",
               {"/surfaces/0/radus", "did you mean \"radius\""});
  expect_error(R"({"materials": [{"type": "lambertain", "name": "a"}]})", {"/materials/0/type", "did you mean \"lambertian\""});
  expect_error(R"({"surfaces": [{"type": "sphre", "material": {"type": "lambertian"}}]})", {"did you mean \"sphere\""});
  expect_error(R"({"camera": {"zoom": 2}})", {"/camera/zoom", "expected one of: transform, vfov"});
}

// wavepath's integrator key "spectral" renders the scene spectrally; the
// command line's --rgb (RenderOptions::spectral false) overrides it, and the
// preview integrators ignore it.
TEST(DartsKeys, SpectralIsAnIntegratorKey) {
  const Scene s = load_scene(write_scene("spectral-key.json", R"({"integrator": {"type": "path tracer mis", "spectral": true},
    "surfaces": [{"type": "sphere", "material": {"type": "lambertian"}}]})"));
  EXPECT_TRUE(s.integrator.spectral);
  EXPECT_TRUE(compile_scene(s, RenderOptions{}).spectral);
  EXPECT_NE(compile_scene(s, RenderOptions{}).params.counts.w & SCENE_FLAG_SPECTRAL, 0u);
  RenderOptions rgb;
  rgb.spectral = false;
  EXPECT_FALSE(compile_scene(s, rgb).spectral);
  RenderOptions normals;
  normals.integrator = IntegratorKind::Normals;
  EXPECT_FALSE(compile_scene(s, normals).spectral);
}

TEST(DartsKeys, WhatWavepathCannotHonourIsRefusedWithTheReason) {
  expect_error(R"({"type": "tests", "tests": []})", {"/type", "wavepath test"});
  expect_error(R"({"integrator": {"type": "path tracer mis", "spectral": "yes"}})", {"/integrator/spectral", "expected true or false"});
  expect_error(R"({"materials": [{"type": "rough_conductor", "name": "m", "metal": "Zn"}]})", {"/materials/0/metal", "\"Au\""});
  expect_error(R"({"materials": [{"type": "dielectric", "name": "g", "glass": "BK7", "ior": 1.6}]})", {"/materials/0/glass", "not both"});
  expect_error(R"({"camera": {"transform": {"matrix": 2}}})", {"/camera/transform/matrix", "16 numbers"});
}

// ---- test files ----------------------------------------------------------------

std::string write_tests(const std::string& name, const std::string& tests) {
  return write_scene(name, R"({"type": "tests", "tests": [)" + tests + "]}");
}

TEST(DartsTests, ReadEveryKindWithDartsDefaults) {
  std::string path = write_tests("kinds.json", R"(
    {"type": "scatter material", "name": "s", "material": {"type": "lambertian"}, "normal": [0, 0, 2]},
    {"type": "sample material", "name": "m", "material": {"type": "phong", "exponent": 5}, "normal": [0, 0, 1],
     "image size": [64, 32], "spp": 10, "up samples": 2, "super samples": 8},
    {"type": "sample surface", "name": "g", "surfaces": {"type": "group", "children": [
      {"type": "sphere", "radius": 1, "transform": {"translate": [0, 0, 4]}, "material": {"type": "lambertian"}},
      {"type": "quad", "transform": {"translate": [0, 0, -3]}, "material": {"type": "diffuse_light", "emit": 1}}]}},
    {"type": "intersection", "surface": {"type": "sphere", "material": {"type": "lambertian"}},
     "ray": {"origin": [0, 0, 5], "direction": [0, 0, -2]}, "t": 2, "p": [0, 0, 1], "gn": [0, 0, 1], "sn": [0, 0, 1]},
    {"type": "photon map", "name": "pm"},
    {"type": "sample surfce", "name": "typo"},
    {"type": "scatter material", "name": "huge", "material": {"type": "lambertian"}, "normal": [0, 0, 1], "image size": [8192, 4096]})");
  std::vector<DartsTest> t = import_darts_tests(path);
  ASSERT_EQ(t.size(), 7u);
  EXPECT_NE(t[6].loadError.find("/tests/6/image size: more than 2^23 cells"), std::string::npos) << t[6].loadError;
  EXPECT_EQ(t[0].kind, DartsTestKind::ScatterMaterial);
  EXPECT_EQ(t[0].imageSize, glm::ivec2(256, 128));
  EXPECT_EQ(t[0].samplesPerPixel, 1000u);
  EXPECT_EQ(t[0].upSamples, 4u);
  EXPECT_EQ(t[0].normal, glm::vec3(0, 0, 1));
  EXPECT_NEAR(glm::length(t[0].incoming - glm::normalize(glm::vec3(0.0f, 0.25f, -1.0f))), 0.0f, 1e-6f);
  EXPECT_EQ(t[1].kind, DartsTestKind::SampleMaterial);
  EXPECT_EQ(t[1].imageSize, glm::ivec2(64, 32));
  EXPECT_EQ(t[1].samplesPerPixel, 10u);
  EXPECT_EQ(t[1].upSamples, 2u);
  EXPECT_EQ(t[1].superSamples, 8u);
  EXPECT_NEAR(glm::length(t[1].incoming - glm::normalize(glm::vec3(0.25f, 0.0f, -1.0f))), 0.0f, 1e-6f);
  EXPECT_EQ(t[2].kind, DartsTestKind::SampleSurface);
  EXPECT_EQ(t[2].childMaterials.size(), 2u);
  EXPECT_EQ(t[2].superSamples, 32u);
  EXPECT_EQ(t[3].kind, DartsTestKind::Intersection);
  EXPECT_EQ(t[3].rayDirection, glm::vec3(0, 0, -2));
  EXPECT_EQ(t[3].threshold, 1e-5f);
  EXPECT_TRUE(t[3].shouldHit);
  EXPECT_TRUE(t[4].loadError.empty()) << t[4].loadError;
  EXPECT_EQ(t[4].kind, DartsTestKind::PhotonMap);
  EXPECT_EQ(t[4].name, "pm");
  EXPECT_EQ(t[4].searchRadius, 0.1f);  // darts' PhotonMapTest defaults
  EXPECT_EQ(t[4].searchCount, 50);
  EXPECT_NE(t[5].loadError.find("did you mean \"sample surface\""), std::string::npos) << t[5].loadError;
  for (size_t i = 0; i < 4; ++i) EXPECT_TRUE(t[i].loadError.empty()) << t[i].loadError;
}

// Small images so that the CPU runs them in a second or two.
const char* kSmall = R"("image size": [64, 32], "spp": 400)";

DartsTestResult run_one(const std::string& path, float planted = 0.0f) {
  DartsTestOptions o;
  o.cpu = true;
  o.plantedPdfError = planted;
  std::vector<DartsTestResult> r = run_darts_tests(path, o, nullptr);
  EXPECT_EQ(r.size(), 1u);
  return r.empty() ? DartsTestResult{} : r[0];
}

// A sphere of radius 1 at distance 2 subtends a cone of half-angle 30 degrees:
// its directions have density 1 / (2 pi (1 - cos 30)) inside, 0 outside.
TEST(DartsTests, SphereSurfaceSamplingMatchesTheSolidAngleDensity) {
  std::string path = write_tests("sphere.json", std::string(R"({"type": "sample surface", "name": "ball", )") + kSmall +
                                                    R"(, "surface": {"type": "sphere", "transform": {"translate": [0, 0, 2]},
                                                    "material": {"type": "diffuse_light", "emit": 1}}})");
  DartsTestResult r = run_one(path);
  EXPECT_TRUE(r.passed) << r.message;
  int w = 0, h = 0;
  std::string dir = std::filesystem::path(path).parent_path().string();
  std::vector<float> pdf = read_exr_red_channel(dir + "/ball-pdf.exr", w, h);
  std::vector<float> sampled = read_exr_red_channel(dir + "/ball-sampled.exr", w, h);
  ASSERT_EQ(w, 64 * 4);
  ASSERT_EQ(h, 32 * 4);
  const double inside = 1.0 / (2.0 * M_PI * (1.0 - std::cos(M_PI / 6.0)));
  // Cells wholly inside or outside the cone (theta below 26 or above 34 degrees).
  double pdfError = 0.0, histogramSum = 0.0, histogramCells = 0.0;
  for (int y = 0; y < h; y += 4)
    for (int x = 0; x < w; x += 4) {
      double theta0 = (y / 4) * M_PI / 32, theta1 = (y / 4 + 1) * M_PI / 32;
      double expected = theta1 < M_PI / 180 * 26 ? inside : theta0 > M_PI / 180 * 34 ? 0.0 : -1.0;
      if (expected < 0.0) continue;  // the edge runs through the cell
      pdfError = std::max(pdfError, std::fabs(pdf[size_t(y) * w + x] - expected));
      if (expected > 0.0 && theta0 > 0.1) {
        histogramSum += sampled[size_t(y) * w + x];
        histogramCells += 1.0;
      }
      if (expected == 0.0) {
        EXPECT_EQ(sampled[size_t(y) * w + x], 0.0f);
      }
    }
  EXPECT_LT(pdfError, 1e-4 * inside);
  // 819200 samples over the cone's cells: their mean density within 1 %.
  EXPECT_NEAR(histogramSum / histogramCells, inside, 0.01 * inside);
}

TEST(DartsTests, MaterialAndSurfaceTestsPassOnTheCpuReference) {
  for (const std::string& test :
       {std::string(R"({"type": "sample material", "name": "lambertian", "material": {"type": "lambertian", "albedo": 1},
                       "normal": [0.25, 0.5, 1], )") + kSmall + "}",
        std::string(R"({"type": "sample material", "name": "phong", "material": {"type": "phong", "exponent": 12},
                       "normal": [0, 0, 1], )") + kSmall + "}",
        std::string(R"({"type": "scatter material", "name": "metal", "material": {"type": "metal", "roughness": 0.4},
                       "normal": [0, 0, 1], )") + kSmall + "}",
        std::string(R"({"type": "sample surface", "name": "quad", "surface": {"type": "quad", "size": 1,
                       "transform": {"o": [0, 0, 1], "x": [1, 0, 0], "y": [0, 1, 1]}, "material": {"type": "diffuse_light", "emit": 1}}, )") +
            kSmall + "}"}) {
    DartsTestResult r = run_one(write_tests("pass.json", test));
    EXPECT_TRUE(r.passed) << r.name << ": " << r.message;
  }
}

// darts' photon map test, k nearest and fixed radius, on a disk placed as
// the course's file places its own (translated, scaled, rotated); photons
// carrying 3 % too much power fail it. The k-nearest estimate smears the
// disk's edge outwards, which the course's tolerance of 0.01 absorbs at its
// 150 neighbours (docs/scene-format.md).
TEST(DartsTests, PhotonMapDensityIntegratesToThePdfAndAPlantedPowerErrorFails) {
  const std::string knn = R"({"type": "photon map", "name": "knn", "image size": [128, 128], "spp": 100, "search radius": 0.1,
    "search count": 150, "transform": [{"translate": [1, 1, 0]}, {"scale": [0.5, 0.5, 1]}]})";
  const std::string radius = R"({"type": "photon map", "name": "radius", "image size": [48, 48], "spp": 50, "search radius": 0.02,
    "search count": 0, "transform": [{"translate": [2, 1, 0]}, {"scale": [0.4, 0.25, 1]}, {"rotate": [35, 0, 0, 1]}]})";
  for (const std::string& test : {knn, radius}) {
    DartsTestResult r = run_one(write_tests("photons.json", test));
    EXPECT_TRUE(r.passed) << r.name << ": " << r.message;
    DartsTestResult planted = run_one(write_tests("photons-planted.json", test), 0.03f);
    EXPECT_FALSE(planted.passed) << planted.name << ": 3 % more power went unnoticed";
    EXPECT_NE(planted.message.find("should match"), std::string::npos) << planted.message;
  }
}

TEST(DartsTests, APlantedPdfErrorFailsTheVerdict) {
  // A normal tilted by 1 degree; and a viewpoint moved by 0.02 for a sphere at distance 2.
  DartsTestResult m = run_one(write_tests("tilt.json", std::string(R"({"type": "sample material", "name": "tilted",
    "material": {"type": "phong", "exponent": 12}, "normal": [0, 0, 1], )") + kSmall + "}"),
                              float(M_PI / 180));
  EXPECT_FALSE(m.passed);
  EXPECT_EQ(m.name, "tilted");
  EXPECT_NE(m.message.find("chi-square"), std::string::npos) << m.message;
  DartsTestResult s = run_one(write_tests("moved.json", std::string(R"({"type": "sample surface", "name": "moved", )") + kSmall +
                                                             R"(, "surface": {"type": "sphere", "transform": {"translate": [0, 0, 2]},
                                                             "material": {"type": "diffuse_light", "emit": 1}}})"),
                              0.02f);
  EXPECT_FALSE(s.passed);
  EXPECT_NE(s.message.find("chi-square"), std::string::npos) << s.message;
}

TEST(DartsTests, DartsOwnChecksFailAsDartsFails) {
  // A delta lobe in a sampling test; a ray that should hit but misses; a wrong normal.
  DartsTestResult d = run_one(write_tests("delta.json", std::string(R"({"type": "sample material", "name": "mirror",
    "material": {"type": "metal", "roughness": 0}, "normal": [0, 0, 1], )") + kSmall + "}"));
  EXPECT_FALSE(d.passed);
  EXPECT_NE(d.message.find("is_specular"), std::string::npos) << d.message;
  const char* sphere = R"("surface": {"type": "sphere", "material": {"type": "lambertian"}})";
  DartsTestResult miss = run_one(write_tests("miss.json", std::string(R"({"type": "intersection", )") + sphere +
                                                              R"(, "ray": {"origin": [0, 3, 5], "direction": [0, 0, -1]}, "t": 1, "p": [0, 0, 0], "gn": [0, 0, 1], "sn": [0, 0, 1]})"));
  EXPECT_FALSE(miss.passed);
  EXPECT_NE(miss.message.find("should hit"), std::string::npos) << miss.message;
  DartsTestResult hit = run_one(write_tests("hit.json", std::string(R"({"type": "intersection", )") + sphere +
                                                            R"(, "ray": {"origin": [0, 0, 5], "direction": [0, 0, -2]}, "t": 2, "p": [0, 0, 1], "gn": [0, 0, 1], "sn": [0, 0, 1]})"));
  EXPECT_TRUE(hit.passed) << hit.message;
  DartsTestResult wrong = run_one(write_tests("wrong.json", std::string(R"({"type": "intersection", )") + sphere +
                                                                R"(, "ray": {"origin": [0, 0, 5], "direction": [0, 0, -2]}, "t": 2, "p": [0, 0, 1], "gn": [0, 1, 0], "sn": [0, 0, 1]})"));
  EXPECT_FALSE(wrong.passed);
  EXPECT_NE(wrong.message.find("Geometric normal"), std::string::npos) << wrong.message;
}

// darts' histogram weights: each sample adds cells / (2 pi^2 N sin theta), so
// the histogram integrates (over the sphere, by cells) to the valid share.
TEST(DirectionTest, HistogramIntegratesToTheValidShare) {
  const glm::ivec2 size(32, 16);
  DirectionHistogram hist(size, 1000);
  hist.keep_counts_after(300);  // what a chi-square of the first 300 samples sees
  shader::ShaderMath m;
  uint32_t state = 3;
  for (int i = 0; i < 1000; ++i) {
    if (i % 4 == 0) {
      hist.add_invalid();
      continue;
    }
    hist.add(m.square_to_uniform_sphere(glm::vec2(m.rng_next(state), m.rng_next(state))));
  }
  EXPECT_EQ(hist.valid(), 750u);
  EXPECT_EQ(hist.kept_samples(), 300u);
  EXPECT_DOUBLE_EQ(std::accumulate(hist.kept_counts().begin(), hist.kept_counts().end(), 0.0), 225.0);
  double integral = 0.0;
  for (int y = 0; y < size.y; ++y) {
    double solidAngle = (std::cos(y * M_PI / size.y) - std::cos((y + 1) * M_PI / size.y)) * 2.0 * M_PI / size.x;
    for (int x = 0; x < size.x; ++x) integral += hist.density()[size_t(y) * size.x + x] * solidAngle;
  }
  EXPECT_NEAR(integral, 0.75, 0.05);  // the 1 / sin(theta) weights are exact only on average over a cell
  glm::dvec3 d = glm::normalize(glm::dvec3(0.3, -0.5, 0.2));
  glm::dvec3 back = cell_to_direction(direction_to_cell(d, size), size);
  EXPECT_NEAR(glm::length(back - d), 0.0, 1e-12);
}

// darts weighs a sample by 1 / sin theta computed in floats from the
// normalised float direction, at least 1e-8 (src/tests/test.cpp:134-135):
// a direction 1e-4 rad from the pole has z = 1 in floats and weighs 1e8
// times a sample's share; one 0.3 rad away weighs 1 / sin(0.3).
TEST(DirectionTest, HistogramWeighsSamplesAsDartsDoesInFloats) {
  const glm::ivec2 size(32, 16);
  const double share = double(size.x * size.y) / (2.0 * M_PI * M_PI * 1000.0);
  DirectionHistogram hist(size, 1000);
  hist.add(glm::vec3(std::sin(1e-4f), 0.0f, std::cos(1e-4f)));
  hist.add(glm::vec3(std::sin(0.3f), 0.0f, std::cos(0.3f)) * 3.0f);
  const std::vector<double>& d = hist.density();
  const double pole = std::accumulate(d.begin(), d.begin() + size.x, 0.0);
  EXPECT_NEAR(pole / (share * 1e8), 1.0, 1e-6) << "z = 1 in floats: sin theta floored at 1e-8";
  const double second = std::accumulate(d.begin() + size.x, d.begin() + 2 * size.x, 0.0);
  EXPECT_NEAR(second / (share / std::sin(0.3)), 1.0, 1e-5);
}

}  // namespace
}  // namespace wp::test
