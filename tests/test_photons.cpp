// The photon mapper (photons.glsl, src/render/photon_pass.cpp) on the CPU
// reference: the kernels' gather against the host's photon map, searches of
// both kinds; a closed diffuse sphere lit from inside against its closed
// form, with a planted bias caught; darts' keys and the scenes it refuses.
// The GPU's agreement is a feature case of test_gpu.cpp (features/photons.json).
#include "test_support.h"

#include <gtest/gtest-spi.h>

#include <random>

#include "render/photon_pass.h"

namespace wp::test {
namespace {

// Random photons in a box, all arriving from the +z side; queries on a
// white Lambertian facing +z: the gather is (1 / pi) times the power the
// host's search finds, over its disc.
TEST(Photons, TheKernelsGatherFindsWhatTheHostsPhotonMapFinds) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  PhotonMap map;
  shader::SceneView math;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 from = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, 0.2f + u(rng)));
    map.add(glm::vec3(u(rng), u(rng), 0.2f * u(rng)), glm::vec3(u(rng), u(rng), u(rng)), math.pack_unit_vector(from));
  }
  map.build();
  const std::vector<shader::Photon> packed = pack_photon_map(map);
  shader::SceneView v;
  v.photonTexels = reinterpret_cast<const glm::uvec4*>(packed.data());
  shader::ShaderMath::Bsdf b{};
  b.ns = b.ng = glm::vec3(0.0f, 0.0f, 1.0f);
  b.front = true;
  b.lobeCount = 1;
  b.lobeType[0] = MAT_LAMBERTIAN;
  b.lobeColor[0] = glm::vec4(1.0f);
  b.lobeWeight[0] = 1.0f;
  const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 0.1f, 1.0f));
  const float radius = 0.05f;
  for (uint32_t k : {0u, 1u, 20u, 128u}) {
    v.scene.photons = glm::uvec4(uint32_t(map.size()), k, glm::floatBitsToUint(radius * radius), 0u);
    for (int q = 0; q < 300; ++q) {
      const glm::vec3 x(u(rng), u(rng), 0.1f);
      const PhotonMap::Gathered g = k == 0 ? map.gather_within(x, radius * radius) : map.gather_nearest(x, radius * radius, k);
      const glm::vec3 expected = g.power / (float(M_PI) * g.area);
      const glm::vec3 got = v.photon_radiance(x, b, wo);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(got[c], expected[c], 1e-4f * (1.0f + expected[c])) << "k " << k << " query " << q << " channel " << c;
    }
  }
  // Photons from the other side of the surface do not count.
  b.ns = b.ng = -b.ng;
  EXPECT_EQ(v.photon_radiance(glm::vec3(0.5f, 0.5f, 0.1f), b, -wo), glm::vec3(0.0f));
}

TEST(Photons, UnitVectorsSurvivePacking) {
  shader::SceneView math;
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 10000; ++i) {
    const glm::vec3 d = math.square_to_uniform_sphere(glm::vec2(u(rng), u(rng)));
    ASSERT_GT(glm::dot(math.unpack_unit_vector(math.pack_unit_vector(d)), d), 0.99999f) << d.x << " " << d.y << " " << d.z;
  }
}

// A white-walled (albedo a) sphere of radius 1 closed around a small sphere
// light of power Phi at its centre: every point of the wall leaves radiance
// L = a Phi / (4 pi^2 (1 - a)) (direct irradiance Phi / 4 pi, then the
// wall's own light; the light's shadow on the wall's view of itself is
// below 0.1 %). The photon mapper (direct light by NEE, the rest from 200k
// photons) gets it within 2 %; photons 5 % too strong are caught.
TEST(Photons, AClosedDiffuseSphereLitInsideMatchesItsClosedForm) {
  const float a = 0.8f, r = 0.02f, le = 62.5f;
  Scene scene = load_scene(write_scene("sphere.json", R"({
    "camera": { "transform": { "from": [0, 0, 0.3], "at": [0, 0, 1], "up": [0, 1, 0] }, "vfov": 50, "resolution": [16, 16] },
    "background": 0,
    "integrator": { "type": "photon mapper", "max bounces": 64, "photons": 200000, "search radius": 0.2, "search count": 40 },
    "surfaces": [
      { "type": "sphere", "radius": 1, "material": { "type": "lambertian", "albedo": 0.8 } },
      { "type": "sphere", "radius": 0.02, "material": { "type": "diffuse_light", "emit": 62.5 } }
    ]
  })"));
  const double phi = double(le) * M_PI * 4.0 * M_PI * r * r;
  const double expected = a * phi / (4.0 * M_PI * M_PI * (1.0 - a));
  RenderOptions o;
  o.spp = 64;
  CompiledScene cs = compile_scene(scene, o);
  ASSERT_GT(cs.photons.size(), 100000u);
  Progress quiet("", 0, false);
  auto mean = [&](const CompiledScene& c) { return image_mean(render_cpu(c, 0, quiet)).first; };
  const double got = mean(cs);
  EXPECT_NEAR(got, expected, 0.02 * expected) << "photon mapper";
  for (shader::Photon& p : cs.photons) p.power *= 1.05f;
  EXPECT_GT(std::fabs(mean(cs) - expected), 0.02 * expected) << "photons 5 % too strong went unnoticed";
}

// The same sphere in the spectral mode, lit in colour: each photon leaves
// with its own wavelengths and is stored in RGB, and a camera path uplifts
// what it gathers. A grey wall multiplies every wavelength alike, so each
// channel's closed form holds within the uplift's round trip (2 %), and
// photons 5 % too strong in red alone are caught.
TEST(Photons, TheSpectralModeLightsAColouredSphereAsItsClosedFormSays) {
  const float a = 0.8f, r = 0.02f;
  const glm::vec3 le(80.0f, 50.0f, 25.0f);
  Scene scene = load_scene(write_scene("sphere-spectral.json", R"({
    "camera": { "transform": { "from": [0, 0, 0.3], "at": [0, 0, 1], "up": [0, 1, 0] }, "vfov": 50, "resolution": [16, 16] },
    "background": 0,
    "integrator": { "type": "photon mapper", "max bounces": 64, "photons": 200000, "search radius": 0.2, "search count": 40, "spectral": true },
    "surfaces": [
      { "type": "sphere", "radius": 1, "material": { "type": "lambertian", "albedo": 0.8 } },
      { "type": "sphere", "radius": 0.02, "material": { "type": "diffuse_light", "emit": [80, 50, 25] } }
    ]
  })"));
  RenderOptions o;
  o.spp = 64;
  CompiledScene cs = compile_scene(scene, o);
  ASSERT_TRUE(cs.spectral);
  ASSERT_GT(cs.photons.size(), 100000u);
  Progress quiet("", 0, false);
  auto channel_means = [&](const CompiledScene& c) {
    const ImageStats img = render_cpu(c, 0, quiet);
    glm::dvec3 sum(0.0);
    for (size_t p = 0; p < size_t(img.pixels()); ++p) sum += img.mean(p);
    return sum / double(img.pixels());
  };
  const glm::dvec3 got = channel_means(cs);
  for (int c = 0; c < 3; ++c) {
    const double phi = double(le[c]) * M_PI * 4.0 * M_PI * r * r;
    const double expected = a * phi / (4.0 * M_PI * M_PI * (1.0 - a));
    EXPECT_NEAR(got[c], expected, 0.02 * expected) << "channel " << c;
  }
  for (shader::Photon& p : cs.photons) p.power.x *= 1.05f;
  const double phiRed = double(le.x) * M_PI * 4.0 * M_PI * r * r, red = a * phiRed / (4.0 * M_PI * M_PI * (1.0 - a));
  EXPECT_GT(std::fabs(channel_means(cs).x - red), 0.02 * red) << "photons 5 % too strong in red went unnoticed";
}

TEST(Photons, DartsKeysAndTheScenesThePhotonMapperRefuses) {
  Scene s = load_scene(write_scene("s.json", R"({
    "camera": { "transform": { "from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0] }, "resolution": [4, 4] },
    "background": 0,
    "integrator": { "type": "photon mapper", "photons": 1000, "search radius": 0.3, "search count": 7, "photon seed": 4 },
    "surfaces": [ { "type": "sphere", "radius": 1, "material": { "type": "diffuse_light", "emit": 1 } } ]
  })"));
  EXPECT_EQ(s.integrator.kind, IntegratorKind::PhotonMapper);
  EXPECT_EQ(s.integrator.photons, 1000u);
  EXPECT_FLOAT_EQ(s.integrator.searchRadius, 0.3f);
  EXPECT_EQ(s.integrator.searchCount, 7u);
  EXPECT_EQ(s.integrator.photonSeed, 4u);
  auto scene = [](const std::string& integrator, const std::string& extra = R"("background": 0)") {
    return R"({ "camera": { "transform": { "from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0] } }, )" + extra +
           R"(, "integrator": )" + integrator + R"(,
      "surfaces": [ { "type": "sphere", "radius": 1, "material": { "type": "lambertian" } },
                    { "type": "sphere", "radius": 0.1, "material": { "type": "diffuse_light", "emit": 1 }, "transform": { "translate": [0, 2, 0] } } ] })";
  };
  expect_error(scene(R"({ "type": "photon mapper", "search count": 500 })"), {"/integrator/search count"});
  expect_error(scene(R"({ "type": "photon mapper", "search radius": -1 })"), {"/integrator/search radius", "positive"});
  expect_error(scene(R"({ "type": "path tracer mis", "photons": 5 })"), {"/integrator/photons"});
  auto refused = [&](const std::string& text, const char* why) {
    Scene bad = load_scene(write_scene("bad.json", text));
    try {
      compile_scene(bad, RenderOptions{});
      ADD_FAILURE() << "no error for " << why;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused(scene(R"({ "type": "photon mapper" })", R"("background": 0.5)"), "background");
  refused(R"({ "camera": { "transform": { "from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0] }, "medium": "fog" },
    "background": 0, "integrator": { "type": "photon mapper" }, "media": [ { "type": "homogeneous", "name": "fog" } ],
    "surfaces": [ { "type": "sphere", "radius": 0.1, "material": { "type": "diffuse_light", "emit": 1 } } ] })",
          "participating media");
}

}  // namespace
}  // namespace wp::test
