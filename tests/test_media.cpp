// Participating media (media.glsl) on the CPU reference, against answers
// known in closed form: Beer-Lambert transmittance through a slab, single
// scattering in a slab, a lossless medium in a white furnace; the density of
// delta tracking's collisions. Each check is shown once to catch a planted
// error. The GPU's agreement with these renders is in test_gpu.cpp.
#include "test_support.h"

#include "stats/compare.h"

#include <gtest/gtest-spi.h>

#include <sstream>

namespace wp::test {
namespace {

// The mean of each channel over the image and its standard error.
struct ChannelMeans {
  glm::dvec3 mean{0.0};
  glm::dvec3 se{0.0};
};

ChannelMeans channel_means(const ImageStats& img) {
  ChannelMeans r;
  glm::dvec3 var(0.0);
  for (size_t p = 0; p < img.pixels(); ++p) {
    r.mean += img.mean(p);
    var += img.variance(p) / std::max(img.count[p], 1.0);
  }
  const double n = double(img.pixels());
  r.mean /= n;
  r.se = glm::sqrt(var) / n;
  return r;
}

// Each channel within 5 standard errors of its expected value (one failure
// for all channels).
void expect_channels(const ImageStats& img, glm::dvec3 expected, const char* what) {
  const ChannelMeans m = channel_means(img);
  std::ostringstream off;
  for (int c = 0; c < 3; ++c) {
    if (!(std::fabs(m.mean[c] - expected[c]) < 5.0 * m.se[c] + 1e-6))
      off << " channel " << c << ": " << m.mean[c] << " +- " << m.se[c] << ", expected " << expected[c] << ";";
  }
  EXPECT_TRUE(off.str().empty()) << what << ":" << off.str();
  EXPECT_EQ(img.nonFinite, 0u) << what;
}

std::string vec(glm::vec3 v) {
  std::ostringstream s;
  s << "[" << v.x << ", " << v.y << ", " << v.z << "]";
  return s.str();
}

// A slab of medium between z = -d and z = 0, bounded by two interface
// quads, seen head-on by a camera of a narrow field at z = 5 (rays within
// 0.5 degrees of the slab's normal: their way through it is d within
// 4e-5). `behind` and `lights` are more surfaces.
std::string slab_scene(float d, glm::vec3 albedo, glm::vec3 total, float realFraction, float g, int maxBounces,
                       const std::string& behind) {
  std::ostringstream s;
  s << R"({
    "camera": { "transform": { "from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0] }, "vfov": 1, "resolution": [8, 8] },
    "background": 0,
    "integrator": { "type": "path tracer mis", "max bounces": )"
    << maxBounces << R"( },
    "media": [ { "type": "homogeneous", "name": "slab", "albedo": )"
    << vec(albedo) << R"(, "total": )" << vec(total) << R"(, "real fraction": )" << realFraction
    << R"(, "phase function": { "type": "henyey-greenstein", "g": )" << g << R"( } } ],
    "surfaces": [
      { "type": "quad", "size": 100, "material": null, "interior": "slab" },
      { "type": "quad", "size": 100, "material": null, "interior": "slab", "transform": [ { "rotate": [180, 1, 0, 0] }, { "translate": [0, 0, )"
    << -d << R"(] } ] })"
    << behind << R"(
    ]
  })";
  return s.str();
}

ImageStats render_text(const std::string& name, const std::string& text, int spp) {
  return render_reference(write_scene(name, text), RenderOptions{}, spp);
}

// An emitter of radiance 1 behind an absorbing slab (albedo 0) shows
// exp(-sigma_t d) in each channel: the camera's ray is delta-tracked
// through it, with null collisions where the real fraction is below 1 and
// in the channels below the majorant. A sigma 5 % off is rejected.
TEST(Media, AnAbsorbingSlabTransmitsBeerLambert) {
  const float d = 0.5f;
  const glm::vec3 total(1.0f, 2.0f, 3.0f);
  const std::string lamp = R"(,
      { "type": "quad", "size": 100, "material": { "type": "diffuse_light", "emit": 1 }, "transform": { "translate": [0, 0, -3] } })";
  for (float real : {1.0f, 0.5f}) {
    ImageStats img = render_text("absorbing.json", slab_scene(d, glm::vec3(0.0f), total, real, 0.0f, 0, lamp), 1024);
    const glm::dvec3 expected = glm::exp(-glm::dvec3(total) * double(real) * double(d));
    expect_channels(img, expected, real < 1.0f ? "absorbing slab, real fraction 0.5" : "absorbing slab");
    EXPECT_NONFATAL_FAILURE(expect_channels(img, glm::exp(-glm::dvec3(total) * 1.05 * double(real) * double(d)), "planted"), "planted");
  }
}

// Single scattering: light of irradiance E travelling into a slab along its
// normal, seen from the side it comes from after one scattering event (max
// bounces 1): L = sigma_s E p(-1) (1 - exp(-2 sigma_t d)) / (2 sigma_t),
// with p(-1) the phase function straight back. The light's shadow rays
// pass the interface and are ratio-tracked (null particles: real fraction
// 0.6); the camera's rays are delta-tracked. Chromatic coefficients.
TEST(Media, SingleScatteringInASlabMatchesItsClosedForm) {
  const float d = 0.7f, g = 0.4f, real = 0.6f, irradiance = 2.0f;
  const glm::vec3 albedo(0.9f, 0.6f, 0.3f), total(0.8f, 1.6f, 2.4f);
  const std::string sun = R"(,
      { "type": "directional_light", "direction": [0, 0, -1], "irradiance": )" + std::to_string(irradiance) + " }";
  ImageStats img = render_text("single.json", slab_scene(d, albedo, total, real, g, 1, sun), 2048);
  shader::ShaderMath m;
  const double p = m.henyey_greenstein_pdf(-1.0f, g);
  auto expected = [&](double scale) {
    glm::dvec3 l;
    for (int c = 0; c < 3; ++c) {
      const double sigmaT = double(total[c]) * real * scale, sigmaS = sigmaT * albedo[c];
      l[c] = sigmaS * irradiance * p * (1.0 - std::exp(-2.0 * sigmaT * d)) / (2.0 * sigmaT);
    }
    return l;
  };
  expect_channels(img, expected(1.0), "single scattering");
  EXPECT_NONFATAL_FAILURE(expect_channels(img, expected(1.05), "planted"), "planted");
}

// A lossless medium (albedo 1, chromatic, forward scattering) in a ball
// under a white sky stays exactly white, however many times light scatters
// in it; albedo 0.97 is caught.
TEST(Media, ALosslessMediumInAWhiteFurnaceStaysWhite) {
  auto furnace = [](float albedo) {
    return R"({
      "camera": { "transform": { "from": [0, 0, 3], "at": [0, 0, 0], "up": [0, 1, 0] }, "vfov": 30, "resolution": [24, 24] },
      "background": 1,
      "integrator": { "type": "path tracer mis", "max bounces": 1000 },
      "media": [ { "type": "homogeneous", "name": "cloud", "albedo": )" +
           std::to_string(albedo) + R"(, "total": [1, 2, 4], "phase function": { "type": "henyey-greenstein", "g": 0.3 } } ],
      "surfaces": [ { "type": "sphere", "radius": 0.7, "material": null, "interior": "cloud" } ]
    })";
  };
  expect_channels(render_text("furnace.json", furnace(1.0f), 256), glm::dvec3(1.0), "lossless medium in a white furnace");
  ImageStats lossy = render_text("lossy.json", furnace(0.97f), 256);
  EXPECT_NONFATAL_FAILURE(expect_channels(lossy, glm::dvec3(1.0), "planted"), "planted");
}

// KHR_materials_volume_scatter, in the darts vocabulary (metal-rough's
// volume.multiscatter_color): a glass ball whose particles show white after
// many bounces (single-scattering albedo 1) loses nothing, through its
// refracting boundary and however often light scatters inside, and stays
// white under a white sky (a smooth boundary: a rough one's microfacets lose
// what their single scattering leaves out, 6 % at roughness 0.3 here);
// particles showing 0.5 after many bounces are caught.
TEST(Media, AScatteringGlassVolumeInAWhiteFurnaceStaysWhite) {
  auto furnace = [](float multiscatter) {
    return R"({
      "camera": { "transform": { "from": [0, 0, 3], "at": [0, 0, 0], "up": [0, 1, 0] }, "vfov": 30, "resolution": [24, 24] },
      "background": 1,
      "integrator": { "type": "path tracer mis", "max bounces": 1000 },
      "materials": [ { "type": "metal_rough", "name": "milky glass", "base_color": 1, "metallic": 0, "roughness": 0,
        "transmission": 1, "ior": 1.3, "volume": { "attenuation_color": [0.4, 0.6, 0.8], "attenuation_distance": 0.5,
        "multiscatter_color": )" + std::to_string(multiscatter) + R"(, "scatter_anisotropy": 0.4 } } ],
      "surfaces": [ { "type": "sphere", "radius": 0.7, "material": "milky glass" } ]
    })";
  };
  expect_channels(render_text("scatter-furnace.json", furnace(1.0f), 256), glm::dvec3(1.0), "scattering glass in a white furnace");
  ImageStats lossy = render_text("scatter-lossy.json", furnace(0.5f), 256);
  EXPECT_NONFATAL_FAILURE(expect_channels(lossy, glm::dvec3(1.0), "planted"), "planted");
}

// Delta tracking's real collisions in a homogeneous medium with null
// particles are exponentially distributed with the real coefficient: a
// chi-square test of the free-flight distances over [0, tmax) and the share
// that reaches tmax. A majorant that leaves out the null particles (pbrt-v4
// issue 189's kind of error) is caught.
TEST(Media, DeltaTrackingSamplesTheFreeFlightDensity) {
  auto run = [](float nullCoefficient, float majorantScale) {
    shader::SceneView v;
    shader::Medium m{};
    m.info = glm::uvec4(MEDIUM_HOMOGENEOUS, 0u, 0u, 0u);
    const float sigmaS = 0.8f, tmax = 2.0f;
    m.sigmaA = glm::vec4(0.0f);
    m.sigmaS = glm::vec4(sigmaS, sigmaS, sigmaS, (sigmaS + nullCoefficient) * majorantScale);
    m.sigmaN = glm::vec4(glm::vec3(nullCoefficient), 0.0f);
    const int bins = 32, n = 400000;
    std::vector<double> obs(bins + 1, 0.0), expc(bins + 1, 0.0);
    uint32_t rng = 77;
    for (int i = 0; i < n; ++i) {
      shader::Spectrum throughput(1.0f);
      float t;
      uint32_t event = v.medium_free_flight(m, v.medium_coefficients(m, glm::vec4(0.0f)), glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), tmax, rng,
                                            throughput, t);
      if (majorantScale == 1.0f) {
        EXPECT_EQ(glm::vec3(throughput), glm::vec3(1.0f));  // grey: every weight is 1
      }
      obs[event == MEDIUM_EVENT_SCATTER ? std::min(int(t / tmax * bins), bins - 1) : bins] += 1.0;
    }
    for (int b = 0; b < bins; ++b) {
      const double t0 = double(tmax) * b / bins, t1 = double(tmax) * (b + 1) / bins;
      expc[b] = n * (std::exp(-sigmaS * t0) - std::exp(-sigmaS * t1));
    }
    expc[bins] = n * std::exp(-double(sigmaS) * tmax);
    return chi2_test(obs, expc, n);
  };
  for (float nullCoefficient : {0.0f, 1.5f}) {
    Chi2Result r = run(nullCoefficient, 1.0f);
    EXPECT_TRUE(r.problem.empty()) << r.problem;
    EXPECT_GT(r.pValue, 0.001) << "null " << nullCoefficient << ": chi2 " << r.statistic << " with " << r.dof << " dof";
  }
  // The majorant below the real coefficient: collisions come too seldom.
  EXPECT_LT(run(0.0f, 0.8f).pValue, 1e-6);
}

// MIS, NEE alone and phase and BSDF sampling alone estimate the same image
// of a fog ball behind an interface, lit by a
// sphere light outside it: paths that scatter in the fog and pass the
// interface before they meet the light weigh their MIS from the point where
// they scattered (PathState.travelled), which a light sampled there would
// have had to reach. A 4 % bias planted in one of them is seen. (The
// mixture, which samples phase functions alone in media, agrees at 65536
// spp; at 16384 its skewed pixels still trip the per-pixel test now and
// then, so it is left out here.)
TEST(Media, EveryPathIntegratorEstimatesTheSameImageThroughAnInterface) {
  Scene scene = load_scene(write_scene("fog-ball.json", R"({
    "camera": { "transform": { "from": [0, 1, 3.5], "at": [0, 0.6, 0], "up": [0, 1, 0] }, "vfov": 40, "resolution": [16, 12] },
    "background": 0,
    "integrator": { "type": "path tracer mis", "max bounces": 6 },
    "media": [ { "type": "homogeneous", "name": "fog", "albedo": [0.9, 0.8, 0.7], "total": [1.5, 2, 2.5],
                 "phase function": { "type": "henyey-greenstein", "g": 0.3 } } ],
    "surfaces": [
      { "type": "quad", "size": 6, "material": { "type": "lambertian", "albedo": 0.5 }, "transform": { "rotate": [-90, 1, 0, 0] } },
      { "type": "sphere", "radius": 0.6, "material": null, "interior": "fog", "transform": { "translate": [-0.2, 0.6, 0] } },
      { "type": "sphere", "radius": 0.45, "material": { "type": "diffuse_light", "emit": 3 }, "transform": { "translate": [1.0, 1.3, -0.3] } }
    ]
  })"));
  auto render = [&](IntegratorKind kind, uint32_t seed) {
    RenderOptions o;
    o.integrator = kind;
    o.spp = 16384;  // phase sampling alone finds the light seldom: at a few thousand spp its pixels' skew misleads the per-pixel test
    o.seed = seed;
    Progress quiet("", 0, false);
    return render_cpu(compile_scene(scene, reference_options(o)), 0, quiet);
  };
  ImageStats mis = render(IntegratorKind::PathMis, 1);
  for (auto [kind, name] : {std::pair{IntegratorKind::PathNee, "nee"}, std::pair{IntegratorKind::PathMats, "mats"}}) {
    CompareResult r = compare_images(render(kind, 2), mis);
    EXPECT_TRUE(r.passed()) << name << " vs mis: " << r.summary();
  }
  ImageStats planted = render(IntegratorKind::PathNee, 3);
  plant_bias(planted, 1.04);
  EXPECT_FALSE(compare_images(planted, mis).passed()) << "planted bias";
}

// An interface around nothing (a ball of vacuum, "material": null) changes
// nothing: shadow rays pass it twice and still reach the light. (Their ends
// once crept into the light by the offsets off each interface, and the
// floor behind such a ball lost 12 % of its direct light.)
TEST(Media, AnInterfaceAroundNothingChangesNothing) {
  const std::string scene = R"({
    "camera": { "transform": { "from": [0, 1, 3.5], "at": [0, 0.6, 0], "up": [0, 1, 0] }, "vfov": 40, "resolution": [32, 24] },
    "background": 0,
    "integrator": { "type": "path tracer nee", "max bounces": 3 },
    "surfaces": [
      { "type": "quad", "size": 6, "material": { "type": "lambertian", "albedo": 0.5 }, "transform": { "rotate": [-90, 1, 0, 0] } },
      BALL
      { "type": "sphere", "radius": 0.45, "material": { "type": "diffuse_light", "emit": 3 }, "transform": { "translate": [1.0, 1.3, -0.3] } }
    ]
  })";
  auto with = [&](const std::string& ball) {
    std::string text = scene;
    text.replace(text.find("BALL"), 4, ball);
    return text;
  };
  RenderOptions o;
  o.seed = 2;
  Progress quiet("", 0, false);
  ImageStats plain = render_text("plain.json", with(""), 1024);
  Scene s = load_scene(write_scene("ball.json", with(R"({ "type": "sphere", "radius": 0.6, "material": null, "transform": { "translate": [-0.2, 0.6, 0] } },)")));
  o.spp = 1024;
  ImageStats ball = render_cpu(compile_scene(s, reference_options(o)), 0, quiet);
  CompareResult r = compare_images(ball, plain);
  EXPECT_TRUE(r.passed()) << r.summary();
}

// darts' vocabulary, read as the course's HomogeneousMedium reads it
// (src/media/homogeneous.cpp:45-50): sigma_a = total (1 - albedo) real,
// sigma_s = total albedo real, sigma_n = total (1 - real); named and inline
// phase functions, the camera's medium, interior and exterior on a surface.
TEST(Media, DartsMediaAreReadAsTheCourseDefinesThem) {
  Scene s = load_scene(write_scene("media.json", R"({
    "camera": { "medium": "air" },
    "materials": [ { "type": "henyey-greenstein", "name": "forward", "g": 0.7 }, { "type": "lambertian", "name": "white", "albedo": 0.5 } ],
    "media": [
      { "type": "homogeneous", "name": "air", "albedo": 0.5, "total": [1, 2, 4], "real fraction": 0.25, "phase function": "forward" },
      { "type": "homogeneous", "name": "ink", "phase function": { "type": "isotropic" } },
      { "type": "vacuum", "name": "nothing" }
    ],
    "surfaces": [
      { "type": "sphere", "material": "white", "interior": "ink", "exterior": "air" },
      { "type": "quad", "material": null, "interior": "nothing", "exterior": "air" }
    ]
  })"));
  ASSERT_EQ(s.media.size(), 3u);
  EXPECT_EQ(s.cameraMedium, 0u);
  const SceneMedium& air = s.media[0];
  EXPECT_EQ(air.sigmaA, glm::vec3(0.125f, 0.25f, 0.5f));
  EXPECT_EQ(air.sigmaS, glm::vec3(0.125f, 0.25f, 0.5f));
  EXPECT_EQ(air.sigmaN, glm::vec3(0.75f, 1.5f, 3.0f));
  EXPECT_FLOAT_EQ(air.g, 0.7f);
  // darts' defaults: albedo 0.8, total 1, real fraction 1.
  EXPECT_NEAR(s.media[1].sigmaS.x, 0.8f, 1e-6f);
  EXPECT_NEAR(s.media[1].sigmaA.x, 0.2f, 1e-6f);
  EXPECT_EQ(s.media[1].g, 0.0f);
  EXPECT_EQ(s.media[2].kind, MEDIUM_VACUUM);
  const SceneMaterial& ball = s.materials[s.spheres[0].material];
  EXPECT_EQ(ball.kind, MAT_LAMBERTIAN);
  EXPECT_TRUE(ball.boundsMedia);
  EXPECT_EQ(ball.interior, 1u);
  EXPECT_EQ(ball.exterior, 0u);
  const SceneMaterial& window = s.materials[s.triangles[0].material];
  EXPECT_EQ(window.kind, MAT_INTERFACE);
  EXPECT_EQ(window.interior, 2u);
  CompiledScene cs = compile_scene(s, RenderOptions{});
  EXPECT_TRUE(cs.params.kinds.w & KIND_BIT(FEATURE_MEDIA));
  EXPECT_EQ(cs.params.media.x, 1u);  // the compiled media start with the vacuum
  EXPECT_EQ(cs.materials[s.spheres[0].material].media, glm::uvec4(2u, 1u, 0u, 0u));
  EXPECT_FLOAT_EQ(cs.media[1].sigmaS.w, 4.0f);  // the majorant: the largest total
}

TEST(Media, BadMediaAreRefusedWithTheirPlace) {
  const std::string ok = R"({ "type": "homogeneous", "name": "fog" })";
  auto scene = [](const std::string& medium, const std::string& surface = R"("interior": "fog")") {
    return R"({ "media": [ )" + medium + R"( ], "surfaces": [ { "type": "sphere", "material": null, )" + surface + " } ] }";
  };
  expect_error(scene(R"({ "type": "homogeneous", "name": "fog", "total": -1 })"), {"/media/0/total", "not negative"});
  expect_error(scene(R"({ "type": "homogeneous", "name": "fog", "albedo": 1.5 })"), {"/media/0/albedo", "[0, 1]"});
  expect_error(scene(R"({ "type": "homogeneous", "name": "fog", "real fraction": 2 })"), {"/media/0/real fraction", "[0, 1]"});
  expect_error(scene(R"({ "type": "homogenous", "name": "fog" })"), {"/media/0/type", "did you mean \"homogeneous\""});
  expect_error(scene(R"({ "type": "nanovdb", "name": "fog", "filename": "smoke.nvdb" })"), {"smoke.nvdb", "cannot open the NanoVDB file", "/media/0"});
  expect_error(scene(R"({ "type": "homogeneous", "name": "fog", "phase function": { "type": "henyey-greenstein", "g": 1 } })"),
               {"/media/0/phase function/g", "between -1 and 1"});
  expect_error(scene(R"({ "type": "homogeneous", "name": "fog", "phase function": { "type": "henyey_greenstein" } })"),
               {"/media/0/phase function/type", "did you mean \"henyey-greenstein\""});
  expect_error(scene(R"({ "type": "homogeneous", "name": "fog", "phase function": "hg" })"), {"/media/0/phase function", "no phase function"});
  expect_error(scene(ok, R"("interior": "fogg")"), {"/surfaces/0/interior", "no medium named \"fogg\"", "did you mean \"fog\""});
  expect_error(scene(ok + R"(, { "type": "vacuum", "name": "unused" })"), {"/media/1/name", "named by no surface"});
  expect_error(scene(ok + ", " + ok), {"/media/1/name", "defined twice"});
  expect_error(scene(ok, R"("interior": "fog", "exteriour": "fog")"), {"/surfaces/0", "exteriour"});
}

}  // namespace
}  // namespace wp::test
