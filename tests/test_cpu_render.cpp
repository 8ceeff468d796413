// The CPU reference renderer on scenes whose answer is known exactly.
#include "test_support.h"

#include <gtest/gtest-spi.h>

#include "stats/compare.h"
#include "util/error.h"

namespace wp::test {
namespace {

TEST(CpuReference, FurnaceBoxIsAnalyticForEveryIntegratorAndDepth) {
  expect_furnace_is_analytic([](const CompiledScene& cs) {
    Progress quiet("", 0, false);
    return render_cpu(cs, 0, quiet);
  });
}

// The analytic check itself must notice a 2 % error: plant one in the
// render and expect the mean test to fail.
TEST(CpuReference, FurnaceCheckCatchesAPlantedBiasOfTwoPercent) {
  Scene scene = load_scene(source_path("tests/data/furnace.json"));
  RenderOptions o;
  o.maxBounces = 2;
  o.spp = 32;
  Progress quiet("", 0, false);
  ImageStats img = render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
  plant_bias(img, 1.02);
  EXPECT_NONFATAL_FAILURE(expect_mean(img, 0.875, "planted"), "planted");
}

// KHR_materials_dispersion: a flint ball (dispersion 4) refracts a small
// light off to its side into a spectrum, each channel's image at its own
// place, green between red and blue, where red, bending least, lies farthest
// out (the light's image sits at the ball's left rim). Without dispersion
// (and the small ball's tint) the three channels of every pixel are equal,
// since every path carries all three alike.
TEST(CpuReference, DispersionSpreadsTheColoursInTheOrderOfTheirIndices) {
  auto centroids = [](Scene s) {
    s.background = glm::vec3(0.0f);
    RenderOptions o;
    o.spp = 64;
    Progress quiet("", 0, false);
    ImageStats img = render_cpu(compile_scene(s, reference_options(o)), 0, quiet);
    glm::dvec3 sum(0.0), sumX(0.0);
    bool equal = true;
    for (size_t p = 0; p < img.pixels(); ++p) {
      const glm::dvec3 m = img.mean(p);
      sum += m;
      sumX += m * double(p % size_t(img.width));
      equal = equal && m.x == m.y && m.y == m.z;
    }
    return std::make_pair(sumX / sum, equal);
  };
  Scene scene = load_scene(write_scene("flint-ball.json", R"({
    "camera": { "transform": { "from": [0, 0, 3], "at": [0, 0, 0], "up": [0, 1, 0] }, "vfov": 30, "resolution": [64, 64] },
    "integrator": { "type": "path tracer mis", "max bounces": 12 },
    "materials": [
      { "type": "metal_rough", "name": "flint", "base_color": [1, 1, 1], "metallic": 0, "roughness": 0, "transmission": 1, "ior": 1.6,
        "volume": { "dispersion": 4 } },
      { "type": "metal_rough", "name": "frosted flint", "base_color": [1, 1, 1], "metallic": 0, "roughness": 0.3, "transmission": 1,
        "ior": 1.5, "volume": { "attenuation_color": [0.9, 0.95, 0.8], "attenuation_distance": 1, "dispersion": 2 } }
    ],
    "surfaces": [
      { "type": "sphere", "radius": 0.7, "material": "flint" },
      { "type": "sphere", "radius": 0.25, "material": "frosted flint", "transform": { "translate": [-0.45, -0.5, 0.8] } },
      { "type": "quad", "size": [0.25, 0.25], "material": { "type": "diffuse_light", "emit": 6 }, "transform": [ { "translate": [0.9, 0.2, -2] } ] }
    ]
  })"));
  auto [x, equal] = centroids(scene);
  EXPECT_FALSE(equal);
  EXPECT_LT(x.x + 0.3, x.y) << "red " << x.x << ", green " << x.y;
  EXPECT_LT(x.y + 0.3, x.z) << "green " << x.y << ", blue " << x.z;
  for (SceneMaterial& m : scene.materials)  // no dispersion, and not the small ball's tint (metal_rough.cpp's record)
    if (m.kind == MAT_METAL_ROUGH) m.record.extra[MR_VOLUME] = glm::vec4(0.0f, 0.0f, 0.0f, m.record.extra[MR_VOLUME].w > 0.0f ? 1.0f : 0.0f);
  auto [x0, equal0] = centroids(scene);
  EXPECT_TRUE(equal0) << "without dispersion the channels differ";
}

// The same glass, clear, in a white furnace: however a path splits the
// colours (in the spectral mode, its wavelengths), each channel still sees
// exactly 1 (a lossless boundary under a uniform sky), so the weight of the
// channel a path keeps is right.
TEST(CpuReference, DispersiveGlassInAWhiteFurnaceStaysWhite) {
  const std::string path = write_scene("dispersive-furnace.json", R"({
    "camera": { "transform": { "from": [0, 0, 3], "at": [0, 0, 0], "up": [0, 1, 0] }, "vfov": 30, "resolution": [32, 32] },
    "background": [1, 1, 1],
    "integrator": { "type": "path tracer mis", "max bounces": 64 },
    "surfaces": [ { "type": "sphere", "radius": 0.7, "material": { "type": "metal_rough", "base_color": 1, "metallic": 0, "roughness": 0,
                    "transmission": 1, "ior": 1.6, "volume": { "dispersion": 4 } } } ]
  })");
  for (bool spectral : {false, true}) {
    RenderOptions o;
    o.spectral = spectral;
    ImageStats img = render_reference(path, o, 256);
    glm::dvec3 sum(0.0);
    for (size_t p = 0; p < img.pixels(); ++p) sum += img.mean(p);
    sum /= double(img.pixels());
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], 1.0, 0.01) << "channel " << c << (spectral ? ", spectral" : "");
    expect_mean(img, 1.0, spectral ? "dispersive glass in a white furnace, spectral" : "dispersive glass in a white furnace");
  }
}

// A convex diffuse sphere (albedo 0.5) under a white sky: every ray leaving it
// escapes, so it shows exactly 0.5. A self-intersection would darken it.
TEST(CpuReference, SphereUnderWhiteSkyIsExactlyHalf) {
  ImageStats img = render_reference(source_path("tests/data/sphere-sky.json"), RenderOptions{}, 64);
  double sum = 0.0;
  int n = 0;
  for (int y = 8; y < 16; ++y)
    for (int x = 8; x < 16; ++x) {
      glm::dvec3 m = img.mean(size_t(y * img.width + x));
      sum += m.x + m.y + m.z;
      n += 3;
      EXPECT_NEAR(m.x, 0.5, 1e-5) << x << "," << y;  // no variance: every path gives 0.5
    }
  EXPECT_NEAR(sum / n, 0.5, 1e-6);
  glm::dvec3 corner = img.mean(0);
  EXPECT_NEAR(corner.x, 1.0, 1e-6);  // the sky itself
}

// The thin lens: the camera rays of one pixel start anywhere on the lens disk
// (radius `aperture`) yet meet again on the plane in focus (at `fdist` along
// the view axis) inside that pixel's footprint, and are spread by the lens
// elsewhere. With no aperture every ray starts at the eye.
TEST(Camera, ThinLensRaysMeetOnThePlaneInFocus) {
  Scene scene = load_scene(source_path("tests/data/features/camera.json"));
  const float aperture = 0.25f, focus = 4.0f;
  ASSERT_EQ(scene.camera.apertureRadius, aperture);
  ASSERT_EQ(scene.camera.focusDistance, focus);
  for (bool lens : {true, false}) {
    Scene s = scene;
    s.camera.width = 480;  // pixels small against the lens, so a blur shows
    s.camera.height = 240;
    if (!lens) s.camera.apertureRadius = 0.0f;
    CompiledScene cs = compile_scene(s, RenderOptions{});
    shader::SceneView view = cs.view();
    glm::vec3 eye(s.camera.toWorld * glm::vec4(0, 0, 0, 1));
    glm::vec3 forward = glm::normalize(glm::vec3(s.camera.toWorld * glm::vec4(0, 0, -1, 0)));
    // The pixel's footprint on a plane at distance z: its diagonal.
    float pixelWidth = 2.0f * std::tan(glm::radians(s.camera.vfovDegrees) * 0.5f) / float(cs.height);
    const uint32_t pixel = 100 * uint32_t(cs.width) + 310;
    auto spread_at = [&](float z, float& maxFromEye) {
      glm::vec3 lo(INFINITY), hi(-INFINITY);
      maxFromEye = 0.0f;
      for (uint32_t sample = 0; sample < 256; ++sample) {
        shader::PathState p;
        view.path_begin(p, pixel, sample);
        maxFromEye = std::max(maxFromEye, glm::distance(p.origin, eye));
        float t = (z - glm::dot(p.origin - eye, forward)) / glm::dot(p.dir, forward);
        glm::vec3 q = p.origin + p.dir * t;
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
      }
      return glm::length(hi - lo);
    };
    float fromEye = 0.0f;
    float inFocus = spread_at(focus, fromEye);
    EXPECT_LE(inFocus, std::sqrt(2.0f) * pixelWidth * focus * 1.001f) << "lens " << lens;
    if (lens) {
      EXPECT_LE(fromEye, aperture * 1.0001f);
      EXPECT_GT(fromEye, 0.9f * aperture);  // the samples reach the rim of the lens
      float near = spread_at(0.5f * focus, fromEye);
      EXPECT_GT(near, 0.8f * aperture);  // half way to the focus the lens blurs by about its radius
      // The focus test has the power to see a focus distance 10 % off.
      float off = spread_at(1.1f * focus, fromEye);
      EXPECT_GT(off, 2.0f * std::sqrt(2.0f) * pixelWidth * 1.1f * focus);
    } else {
      EXPECT_LT(fromEye, 1e-5f);
      EXPECT_LE(spread_at(0.5f * focus, fromEye), std::sqrt(2.0f) * pixelWidth * 0.5f * focus * 1.001f);
    }
  }
}

// div_mod divides without integer division (integrator.glsl): exact at and
// around every multiple of divisors small and large, up to its limit of
// quotients below 2^21.
TEST(DivMod, ExactWithoutIntegerDivision) {
  shader::SceneView view;
  const uint32_t divisors[] = {1, 2, 3, 7, 10, 63, 64, 65, 255, 511, 1000, 4093, 16384, 65521, 262139, 1u << 20, 511u << 20};
  uint64_t wrong = 0, checked = 0;
  for (uint32_t b : divisors) {
    const uint64_t limit = std::min<uint64_t>(uint64_t(b) << 21, 1ull << 30);  // a below both bounds
    // Every multiple for the small quotients, then a geometric walk up to the limit.
    for (uint64_t q = 0; q * b < limit; q = q < 4096 ? q + 1 : q + q / 64) {
      for (int64_t d = -2; d <= 2; ++d) {
        const int64_t a = int64_t(q * b) + d;
        if (a < 0 || uint64_t(a) >= limit) continue;
        const glm::uvec2 qr = view.div_mod(uint32_t(a), b);
        ++checked;
        if (qr.x != uint64_t(a) / b || qr.y != uint64_t(a) % b) {
          if (++wrong <= 5) ADD_FAILURE() << a << " / " << b << ": " << qr.x << " rest " << qr.y;
        }
      }
    }
  }
  EXPECT_EQ(wrong, 0u) << "of " << checked;
}

// pixel_xy splits a pixel index without integer division (integrator.glsl):
// exact for every width up to the 16384 limit, at every row boundary of the
// tallest image, where a float quotient is most likely to land one row off.
TEST(Camera, PixelIndexSplitsIntoColumnAndRowExactly) {
  shader::SceneView view;
  const uint32_t widths[] = {1, 2, 3, 5, 7, 15, 16, 17, 31, 33, 100, 333, 511, 512, 640,
                             1023, 1024, 1920, 4095, 4097, 9999, 16383, 16384};
  const uint32_t height = 16384;
  uint64_t wrong = 0, checked = 0;
  for (uint32_t width : widths) {
    view.scene.image.x = width;
    for (uint32_t row = 0; row < height; ++row) {
      const uint64_t start = uint64_t(row) * width;
      for (int64_t d = -2; d <= 2; ++d) {
        const int64_t pixel = int64_t(start) + d;
        if (pixel < 0 || pixel >= int64_t(uint64_t(width) * height)) continue;
        const glm::uvec2 xy = view.pixel_xy(uint32_t(pixel));
        ++checked;
        if (xy.x != uint32_t(pixel) % width || xy.y != uint32_t(pixel) / width) {
          if (++wrong <= 5) ADD_FAILURE() << "width " << width << ", pixel " << pixel << ": " << xy.x << ", " << xy.y;
        }
      }
    }
  }
  EXPECT_EQ(wrong, 0u) << "of " << checked;
}

TEST(CpuReference, TruncatedTraversalIsAnErrorNotAnImage) {
  RenderOptions o;
  o.traversalStepCap = 2;
  EXPECT_THROW(render_reference(source_path("scenes/cornell-box.json"), o, 1), RenderError);
}

// MIS, NEE alone, BSDF sampling alone and the one-sample mixture estimate the
// same image, with area lights and with an environment map (the scenes have no
// point lights, which only NEE can reach, and lights large enough for BSDF
// sampling alone to find them at 256 spp). Not "path tracer hemisphere": on
// glossy lobes its uniform directions make per-pixel distributions so heavy
// tailed at 256 spp that the per-pixel test misjudges them (its image mean
// agreed to 0.02%); the furnace checks it analytically, Gpu.EveryFeature...
// against the GPU.
TEST(CpuRender, AllPathTracersAgreeOnOneScene) {
  for (const char* file : {"tests/data/features/integrators.json", "tests/data/features/environment.json",
                           "tests/data/features/microfacet.json"}) {
    Scene scene = load_scene(source_path(file));
    auto render = [&](IntegratorKind kind, uint32_t seed, float bias) {
      RenderOptions o;
      o.integrator = kind;
      o.spp = 256;
      o.seed = seed;
      Progress quiet("", 0, false);
      ImageStats image = render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
      plant_bias(image, bias);
      return image;
    };
    ImageStats mis = render(IntegratorKind::PathMis, 1, 1.0f);
    for (auto [kind, name] : {std::pair{IntegratorKind::PathNee, "nee"}, std::pair{IntegratorKind::PathMats, "mats"},
                              std::pair{IntegratorKind::PathMixture, "mixture"}}) {
      CompareResult r = compare_images(render(kind, 2, 1.0f), mis);
      EXPECT_TRUE(r.passed()) << file << ": " << name << " vs mis: " << r.summary();
    }
    // A planted 4% bias in one of them is seen.
    EXPECT_FALSE(compare_images(render(IntegratorKind::PathNee, 3, 1.04f), mis).passed()) << file;
  }
}

// darts' integrator "power": the exponent of the MIS heuristic. Every
// exponent weighs BSDF and light samples by weights that sum to one, so the
// balance heuristic (1) and the power heuristic (2) estimate the same image,
// with other noise; a planted 4 % bias in one is seen.
TEST(CpuRender, MisExponentsEstimateTheSameImageWithOtherNoise) {
  for (const char* file : {"tests/data/features/integrators.json", "tests/data/quad-light.json"}) {
    auto render = [&](float power, uint32_t seed) {
      Scene scene = load_scene(source_path(file));
      scene.integrator.misPower = power;
      RenderOptions o;
      o.spp = 256;
      o.seed = seed;
      Progress quiet("", 0, false);
      return render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
    };
    ImageStats power2 = render(2.0f, 1), balance = render(1.0f, 2), sameSeed = render(1.0f, 1);
    CompareResult r = compare_images(balance, power2);
    EXPECT_TRUE(r.passed()) << file << ": balance vs power heuristic: " << r.summary();
    EXPECT_NE(sameSeed.sum, power2.sum) << file << ": the exponent changed nothing";
    plant_bias(balance, 1.04);
    EXPECT_FALSE(compare_images(balance, power2).passed()) << file << ": planted bias";
  }
}

TEST(AdaptiveSampling, StopsWhenTheConfidenceIntervalIsWithinTolerance) {
  // 1.96 * sigma / sqrt(n) <= tol * mu.
  EXPECT_FALSE(pixel_converged(1, 1.0, 1.0, 0.05f));  // one sample says nothing
  EXPECT_TRUE(pixel_converged(32, 32.0, 32.0, 0.05f));  // constant: sigma = 0
  // mu = 1, sigma = 1: the interval is 1.96 / sqrt(n); within 5% from n = 1537.
  auto stats = [](double n) { return std::pair{n, 2.0 * n}; };  // E[y] = 1, E[y^2] = 2
  auto [n1, s2a] = stats(1536);
  EXPECT_FALSE(pixel_converged(n1, n1, s2a, 0.05f));
  auto [n2, s2b] = stats(1600);
  EXPECT_TRUE(pixel_converged(n2, n2, s2b, 0.05f));
  EXPECT_TRUE(pixel_converged(64, 0.0, 0.0, 0.05f));  // black: mu = sigma = 0
}

// The CPU reference with adaptive sampling: flat background pixels stop after
// one batch, noisy lit ones take more; every count is a whole number of
// batches or the maximum.
TEST(AdaptiveSampling, SpendsSamplesWhereTheNoiseIs) {
  Scene scene = load_scene(source_path("tests/data/features/integrators.json"));
  RenderOptions o = adaptive_options(256);
  Progress quiet("", 0, false);
  CompiledScene cs = compile_scene(scene, reference_options(o));
  ImageStats img = render_cpu(cs, 0, quiet);
  double fewest = 1e9, most = 0.0;
  for (size_t p = 0; p < img.pixels(); ++p) {
    double n = img.count[p];
    EXPECT_TRUE(std::fmod(n, 32.0) == 0.0 || n == 256.0) << "pixel " << p << ": " << n;
    fewest = std::min(fewest, n);
    most = std::max(most, n);
  }
  EXPECT_EQ(fewest, 32.0);  // the background (top rows) is constant
  EXPECT_EQ(most, 256.0);   // some lit pixels never reach 5%
}

// Several light samples per vertex (CS184's -l) estimate the same image as
// one, with the multi-sample MIS weights and with NEE alone.
TEST(CpuRender, SeveralLightSamplesPerVertexAgreeWithOne) {
  Scene scene = load_scene(source_path("tests/data/features/integrators.json"));
  for (IntegratorKind kind : {IntegratorKind::PathMis, IntegratorKind::PathNee}) {
    RenderOptions o;
    o.integrator = kind;
    o.spp = 128;
    o.seed = 1;
    Progress quiet("", 0, false);
    ImageStats one = render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
    o.seed = 2;
    o.lightSamples = 4;
    ImageStats four = render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
    CompareResult r = compare_images(four, one);
    EXPECT_TRUE(r.passed()) << "4 light samples vs 1: " << r.summary();
  }
  RenderOptions bad;
  bad.lightSamples = int(MAX_LIGHT_SAMPLES) + 1;
  EXPECT_THROW(compile_scene(scene, bad), InputError);
}

// Punctual lights against their closed forms: a Lambertian floor of albedo
// 0.5 seen straight down through a narrow field, lit by one light, shows
// L = 0.5 / pi * E, E the irradiance there: a directional light's E cos;
// a spot's I / d^2 at the centre of its cone, I times the square of glTF's
// ramp between its cones, and nothing outside them.
TEST(CpuRender, PunctualLightsGiveTheirClosedFormRadiance) {
  struct Case {
    const char* what;
    const char* light;
    glm::vec2 at;      // the floor point the camera looks at
    double expected;   // the floor's radiance there
  };
  const double a = 0.5 / M_PI;
  const double c25 = std::cos(glm::radians(25.0)), c20 = std::cos(glm::radians(20.0)), c30 = std::cos(glm::radians(30.0));
  const double ramp = (c25 - c30) / (c20 - c30);
  const double d25 = 2.0 / c25;  // distance from a spot 2 above the floor to a point 25 degrees off its axis
  const Case cases[] = {
      {"directional at 45 degrees", R"({"type": "directional_light", "direction": [0, -1, -1], "irradiance": 2})", {0, 0},
       a * 2.0 * std::sqrt(0.5)},
      {"spot, on its axis", R"({"type": "spot_light", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": 4, "inner_angle": 20, "outer_angle": 30})",
       {0, 0}, a * 4.0 / 4.0},
      {"spot, between its cones", R"({"type": "spot_light", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": 4, "inner_angle": 20, "outer_angle": 30})",
       {float(2.0 * std::tan(glm::radians(25.0))), 0}, a * 4.0 * ramp * ramp * c25 / (d25 * d25)},
      {"spot, outside its cones", R"({"type": "spot_light", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": 4, "inner_angle": 20, "outer_angle": 30})",
       {float(2.0 * std::tan(glm::radians(35.0))), 0}, 0.0},
  };
  for (const Case& c : cases) {
    const std::string x = std::to_string(c.at.x), z = std::to_string(c.at.y);
    const std::string scene = write_scene("punctual.json", std::string(R"({
      "camera": {"transform": {"from": [)") + x + ", 50, " + z + "], \"at\": [" + x + ", 0, " + z + R"(], "up": [0, 0, -1]},
                 "vfov": 0.001, "resolution": [2, 2]},
      "sampler": {"samples": 16}, "background": 0, "integrator": {"type": "path tracer mis", "max bounces": 1},
      "surfaces": [{"type": "quad", "size": 100, "transform": {"rotate": [-90, 1, 0, 0]}, "material": {"type": "lambertian", "albedo": 0.5}},
                   )" + c.light + "]}");
    ImageStats img = render_reference(scene, RenderOptions{});
    auto [mean, error] = image_mean(img);
    EXPECT_NEAR(mean, c.expected, 1e-4 + 1e-4 * c.expected) << c.what;
  }
}

}  // namespace
}  // namespace wp::test
