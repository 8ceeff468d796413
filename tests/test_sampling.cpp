// Every sampling routine against its pdf (chi-square), energy conservation,
// pdf normalisation, and one planted error to show the test can fail.
#include "test_support.h"

namespace wp::test {
namespace {

using namespace shader;

constexpr int kSamples = 1000000;
// Family-wise level 0.01 over every chi-square test in this file.
const double kLevel = sidak(0.01, 12);

void expect_fit(const Chi2Result& r, const char* what) {
  EXPECT_TRUE(r.problem.empty()) << what << ": " << r.problem;
  EXPECT_GT(r.pValue, kLevel) << what << ": chi2 = " << r.statistic << " with " << r.dof << " dof";
}

// 2D warps into a square domain [lo, hi]^2: histogram against the pdf
// integrated per cell with a 64x64 midpoint rule (cells cut by the domain's
// boundary need the fine rule).
Chi2Result square_chi2(int res, float lo, float hi, const std::function<glm::vec2(glm::vec2)>& warp,
                       const std::function<double(glm::vec2)>& pdf, uint32_t seed) {
  std::vector<double> obs(size_t(res * res), 0.0), expc(size_t(res * res), 0.0);
  ShaderMath m;
  uint32_t state = seed;
  float w = (hi - lo) / float(res);
  for (int s = 0; s < kSamples; ++s) {
    glm::vec2 p = warp(glm::vec2(m.rng_next(state), m.rng_next(state)));
    int i = std::clamp(int((p.x - lo) / w), 0, res - 1), j = std::clamp(int((p.y - lo) / w), 0, res - 1);
    obs[size_t(j * res + i)] += 1.0;
  }
  const int k = 64;
  for (int j = 0; j < res; ++j)
    for (int i = 0; i < res; ++i) {
      double sum = 0.0;
      for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b)
          sum += pdf(glm::vec2(lo + (float(i) + (float(a) + 0.5f) / k) * w, lo + (float(j) + (float(b) + 0.5f) / k) * w));
      expc[size_t(j * res + i)] = sum / (k * k) * double(w) * double(w) * kSamples;
    }
  return chi2_test(obs, expc, kSamples);
}

TEST(Sampling, ConcentricDiskMatchesPdf) {
  ShaderMath m;
  auto r = square_chi2(
      40, -1.0f, 1.0f, [&](glm::vec2 u) { return m.square_to_disk_concentric(u); },
      [&](glm::vec2 p) { return double(m.square_to_disk_concentric_pdf(p)); }, 1);
  expect_fit(r, "concentric disk");
}

TEST(Sampling, TriangleBarycentricsAreUniform) {
  ShaderMath m;
  auto r = square_chi2(
      40, 0.0f, 1.0f, [&](glm::vec2 u) { return m.square_to_triangle_barycentric(u); },
      [](glm::vec2 b) { return b.x + b.y <= 1.0f ? 2.0 : 0.0; }, 2);
  expect_fit(r, "triangle barycentrics");
}

TEST(Sampling, CosineHemisphereMatchesPdf) {
  ShaderMath m;
  DirectionalChi2 chi;
  auto r = chi.run(
      kSamples, [&](glm::vec2 u, bool&) { return m.square_to_cosine_hemisphere(u); },
      [&](glm::vec3 w) { return double(m.square_to_cosine_hemisphere_pdf(w)); }, 3);
  expect_fit(r, "cosine hemisphere");
}

TEST(Sampling, UniformSphereMatchesPdf) {
  ShaderMath m;
  DirectionalChi2 chi;
  auto r = chi.run(
      kSamples, [&](glm::vec2 u, bool&) { return m.square_to_uniform_sphere(u); },
      [&](glm::vec3 w) { return double(m.square_to_uniform_sphere_pdf(w)); }, 4);
  expect_fit(r, "uniform sphere");
}

// The same harness must reject a warp whose pdf is wrong: cosine-distributed
// samples judged against the uniform hemisphere pdf.
TEST(Sampling, ChiSquareCatchesAPlantedWrongPdf) {
  ShaderMath m;
  DirectionalChi2 chi;
  auto r = chi.run(
      kSamples, [&](glm::vec2 u, bool&) { return m.square_to_cosine_hemisphere(u); },
      [](glm::vec3 w) { return w.z > 0.0f ? 1.0 / (2.0 * M_PI) : 0.0; }, 5);
  EXPECT_LT(r.pValue, kLevel) << "a wrong pdf was not detected";
  // A subtler error: a warp 2% too concentrated towards the pole.
  auto r2 = chi.run(
      kSamples,
      [&](glm::vec2 u, bool&) {
        glm::vec3 v = m.square_to_cosine_hemisphere(glm::vec2(std::pow(u.x, 1.02f), u.y));
        return glm::normalize(v);
      },
      [&](glm::vec3 w) { return double(m.square_to_cosine_hemisphere_pdf(w)); }, 6);
  EXPECT_LT(r2.pValue, kLevel) << "a 2% distortion of the warp was not detected";
}

Material lambertian(glm::vec3 albedo) {
  Material mat{};
  mat.albedo = glm::vec4(albedo, 0.0f);
  mat.info.x = MAT_LAMBERTIAN;
  return mat;
}

const glm::vec3 kNormals[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0.48f, -0.6f, 0.64f}};

TEST(Bsdf, LambertianSampleMatchesPdfForSeveralNormals) {
  ShaderMath m;
  Material mat = lambertian(glm::vec3(0.7f));
  uint32_t seed = 10;
  for (glm::vec3 n : kNormals) {
    n = glm::normalize(n);
    glm::vec3 wo = glm::normalize(n + glm::vec3(0.3f, 0.1f, -0.2f));
    DirectionalChi2 chi;
    chi.thetaRes = 24;
    chi.phiRes = 48;
    auto r = chi.run(
        kSamples / 2,
        [&](glm::vec2 u, bool& ok) {
          glm::vec3 wi;
          float pdf;
          m.bsdf_sample(mat, n, wo, u, wi, pdf);
          ok = pdf > 0.0f;
          return wi;
        },
        [&](glm::vec3 wi) { return double(m.bsdf_pdf(mat, n, wo, wi)); }, seed++);
    expect_fit(r, "lambertian bsdf_sample");
  }
}

TEST(Bsdf, LambertianConservesEnergyAndPdfIntegratesToOne) {
  ShaderMath m;
  Material white = lambertian(glm::vec3(1.0f));
  uint32_t state = 77;
  for (int d = 0; d < 10; ++d) {
    glm::vec3 n = m.square_to_uniform_sphere(glm::vec2(m.rng_next(state), m.rng_next(state)));
    glm::vec3 wo = m.square_to_uniform_sphere(glm::vec2(m.rng_next(state), m.rng_next(state)));
    if (glm::dot(wo, n) < 0.0f) wo = -wo;
    double sum = 0.0;
    const int n16k = 16384;
    for (int s = 0; s < n16k; ++s) {
      glm::vec3 wi;
      float pdf;
      glm::vec3 weight = m.bsdf_sample(white, n, wo, glm::vec2(m.rng_next(state), m.rng_next(state)), wi, pdf);
      if (pdf <= 0.0f) continue;
      // The returned weight must equal eval / pdf.
      glm::vec3 ratio = m.bsdf_eval(white, n, wo, wi) / pdf;
      EXPECT_NEAR(ratio.x, weight.x, 1e-3f);
      sum += weight.x;
    }
    EXPECT_LT(sum / n16k, 1.01) << "direction " << d;
    // Integrate the pdf over the sphere on a fine grid.
    DirectionalChi2 grid;
    grid.run(1, [](glm::vec2, bool& ok) { ok = false; return glm::vec3(0, 0, 1); },
             [&](glm::vec3 wi) { return double(m.bsdf_pdf(white, n, wo, wi)); }, 1);
    double integral = std::accumulate(grid.expected.begin(), grid.expected.end(), 0.0);
    EXPECT_NEAR(integral, 1.0, 2e-3) << "direction " << d;
  }
}

TEST(Sampling, AliasTablePicksInProportionToWeight) {
  std::vector<double> weights = {1.0, 2.0, 3.0, 0.5, 10.0, 0.0, 4.0};
  std::vector<Emitter> table = build_alias_table(weights);
  SceneView view;
  view.emitters = table.data();
  view.scene.counts.x = uint32_t(table.size());
  double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  std::vector<double> obs(weights.size(), 0.0), expc(weights.size(), 0.0);
  uint32_t state = 99;
  for (int s = 0; s < kSamples; ++s) {
    float pmf;
    uint32_t i = view.pick_emitter(view.rng_next(state), pmf);
    ASSERT_LT(i, weights.size());
    EXPECT_FLOAT_EQ(pmf, float(weights[i] / total));
    obs[i] += 1.0;
  }
  for (size_t i = 0; i < weights.size(); ++i) expc[i] = weights[i] / total * kSamples;
  expect_fit(chi2_test(obs, expc, kSamples), "alias table");
}

// sample_emitter's density must be the one emitter_pdf_area reports for the
// emitter it landed on, for triangles and spheres alike.
TEST(Sampling, EmitterSamplingDensityMatchesEmitterPdf) {
  Scene scene = load_scene(source_path("tests/data/quad-light.json"));
  CompiledScene cs = compile_scene(scene, RenderOptions{});
  SceneView view = cs.view();
  ASSERT_EQ(cs.params.counts.x, 3u);  // two lamp triangles and the small sphere
  uint32_t state = 5;
  for (int s = 0; s < 2000; ++s) {
    SceneView::LightSample ls;
    glm::vec3 u(view.rng_next(state), view.rng_next(state), view.rng_next(state));
    ASSERT_TRUE(view.sample_emitter(u, ls));
    // Find which emitter holds the point: shoot a ray at it from just off the surface.
    glm::vec3 o = ls.p + ls.n * 0.01f;
    Hit h;
    ASSERT_EQ(view.trace_ray(o, -ls.n, 1.0f, false, h), TRACE_OK);
    ASSERT_NE(h.prim, WP_INVALID);
    SceneView::SurfaceHit sh = view.surface_at(o, -ls.n, h);
    ASSERT_NE(sh.emitter, WP_INVALID);
    EXPECT_NEAR(view.emitter_pdf_area(sh.emitter), ls.pdfArea, 1e-4f * ls.pdfArea);
  }
}

TEST(Rng, SequencesAreReproducibleAndUniform) {
  ShaderMath m;
  uint32_t a = m.rng_seed(5, 6, 7), b = m.rng_seed(5, 6, 7), c = m.rng_seed(5, 6, 8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  std::vector<double> obs(64, 0.0), expc(64, kSamples / 64.0);
  uint32_t state = m.rng_seed(1, 2, 3);
  for (int s = 0; s < kSamples; ++s) {
    float x = m.rng_next(state);
    ASSERT_GE(x, 0.0f);
    ASSERT_LT(x, 1.0f);
    obs[size_t(x * 64.0f)] += 1.0;
  }
  expect_fit(chi2_test(obs, expc, kSamples), "rng_next");
}

}  // namespace
}  // namespace wp::test
