// Every sampling routine against its pdf (chi-square), energy conservation,
// pdf normalisation, and one planted error to show the test can fail.
#include "test_support.h"

#include <random>

namespace wp::test {
namespace {

using namespace shader;

constexpr int kSamples = 1000000;
// Family-wise level 0.01 over every chi-square test in this file.
const double kLevel = sidak(0.01, 18);

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

// MIS weights of two strategies sum to one for every exponent, at ordinary
// and extreme densities: what keeps multiple importance sampling unbiased.
// Weights of mismatched exponents (a planted fault) do not.
TEST(Sampling, MisWeightsSumToOneForEveryExponent) {
  ShaderMath m;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> logPdf(-20.0f, 20.0f);
  float worstPlanted = 0.0f;
  for (int i = 0; i < 10000; ++i) {
    float a = std::exp(logPdf(rng)), b = std::exp(logPdf(rng));
    for (float beta : {0.0f, 0.5f, 1.0f, 2.0f, 3.0f, 16.0f}) {
      float sum = m.power_heuristic(a, b, beta) + m.power_heuristic(b, a, beta);
      ASSERT_NEAR(sum, 1.0f, 1e-5f) << "pdfs " << a << ", " << b << ", beta " << beta;
    }
    worstPlanted = std::max(worstPlanted, std::abs(m.power_heuristic(a, b, 2.0f) + m.power_heuristic(b, a, 1.0f) - 1.0f));
  }
  EXPECT_GT(worstPlanted, 0.1f) << "mixing exponents should break the sum";
  EXPECT_EQ(m.power_heuristic(0.0f, 1.0f, 1.0f), 0.0f);
  EXPECT_EQ(m.power_heuristic(1.0f, 0.0f, 1.0f), 1.0f);
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

// A warp from the square to directions against its pdf.
Chi2Result direction_chi2(const std::function<glm::vec3(glm::vec2)>& warp, const std::function<double(glm::vec3)>& pdf,
                          uint32_t seed) {
  DirectionalChi2 chi;
  return chi.run(kSamples, [&](glm::vec2 u, bool&) { return warp(u); }, pdf, seed);
}

TEST(Sampling, CosineHemisphereMatchesPdf) {
  ShaderMath m;
  expect_fit(direction_chi2([&](glm::vec2 u) { return m.square_to_cosine_hemisphere(u); },
                            [&](glm::vec3 w) { return double(m.square_to_cosine_hemisphere_pdf(w)); }, 3),
             "cosine hemisphere");
}

TEST(Sampling, UniformHemisphereMatchesPdf) {
  ShaderMath m;
  expect_fit(direction_chi2([&](glm::vec2 u) { return m.square_to_uniform_hemisphere(u); },
                            [&](glm::vec3 w) { return double(m.square_to_uniform_hemisphere_pdf(w)); }, 7),
             "uniform hemisphere");
}

TEST(Sampling, UniformSphereMatchesPdf) {
  ShaderMath m;
  expect_fit(direction_chi2([&](glm::vec2 u) { return m.square_to_uniform_sphere(u); },
                            [&](glm::vec3 w) { return double(m.square_to_uniform_sphere_pdf(w)); }, 4),
             "uniform sphere");
}

// Henyey-Greenstein for back, near-isotropic, forward and strongly peaked
// asymmetries (the media of issue 40 will scatter with it), and a planted
// asymmetry 4 % off caught.
TEST(Sampling, HenyeyGreensteinMatchesItsPdf) {
  ShaderMath m;
  uint32_t seed = 20;
  for (float g : {-0.99f, -0.9f, -0.3f, 0.0f, 0.0005f, 0.5f, 0.95f, 0.99f}) {
    const std::string what = "Henyey-Greenstein, g = " + std::to_string(g);
    // Cells crowded towards the lobe's peak, where a peaked lobe needs them.
    DirectionalChi2 grid;
    grid.pole = glm::vec3(0.0f, 0.0f, g < 0.0f ? -1.0f : 1.0f);
    grid.polarPower = std::abs(g) > 0.97f ? 8 : std::abs(g) > 0.6f ? 4 : 1;
    grid.integrationRes = 8;
    expect_fit(grid.run(kSamples, [&](glm::vec2 u, bool&) { return m.square_to_henyey_greenstein(u, g); },
                        [&](glm::vec3 w) { return double(m.henyey_greenstein_pdf(w.z, g)); }, seed++),
               what.c_str());
  }
  DirectionalChi2 chi;
  auto planted = chi.run(
      kSamples, [&](glm::vec2 u, bool&) { return m.square_to_henyey_greenstein(u, 0.52f); },
      [&](glm::vec3 w) { return double(m.henyey_greenstein_pdf(w.z, 0.5f)); }, 30);
  EXPECT_LT(planted.pValue, kLevel) << "an asymmetry 4% off was not detected";
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

TEST(Sampling, AliasTablePicksInProportionToWeight) {
  std::vector<double> weights = {1.0, 2.0, 3.0, 0.5, 10.0, 0.0, 4.0};
  std::vector<Emitter> table = build_alias_table(weights);
  SceneView view;
  view.emitterTexels = reinterpret_cast<const glm::uvec4*>(table.data());
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

// Next-event estimation from a point: the directions sample_emitter produces
// (area-sampled triangles, cone-sampled sphere) against the density
// emitters_pdf_direction reports, and each sample's own pdf against it.
TEST(Sampling, EmitterSamplingMatchesItsDirectionalDensity) {
  Scene scene = load_scene(source_path("tests/data/quad-light.json"));
  CompiledScene cs = compile_scene(scene, RenderOptions{});
  SceneView view = cs.view();
  ASSERT_EQ(cs.params.counts.x, 3u);  // two lamp triangles and the small sphere
  const glm::vec3 refs[] = {{0.2f, 0.3f, 0.4f}, {1.0f, 0.8f, 0.9f}};
  uint32_t seed = 40;
  for (glm::vec3 ref : refs) {
    uint32_t extra = view.rng_seed(seed, 1u, 2u);  // a stream unrelated to the harness's
    DirectionalChi2 chi;
    chi.integrationRes = 8;
    chi.refineEdges = true;  // the density has sharp edges
    Chi2Result r = chi.run(
        kSamples,
        [&](glm::vec2 u, bool& ok) {
          SceneView::LightSample ls;
          ok = view.sample_emitter(ref, glm::vec3(view.rng_next(extra), u.x, u.y), ls);
          if (ok) {
            EXPECT_NEAR(ls.pdf, view.emitters_pdf_direction(ref, ls.wi, false), 2e-3f * ls.pdf);
          }
          return ok ? ls.wi : glm::vec3(0, 0, 1);
        },
        [&](glm::vec3 w) { return double(view.emitters_pdf_direction(ref, w, false)); }, seed++);
    expect_fit(r, "emitter directions");
  }
}

// CMJ: every pattern stratifies both 1D projections into N strata (one sample
// each) and the m x n grid cells (one sample each); over many patterns the
// points are uniform.
TEST(Sampling, CorrelatedMultiJitteredPatternsAreStratifiedAndUniform) {
  ShaderMath m;
  for (uint32_t count : {1u, 7u, 12u, 16u, 64u, 100u}) {
    for (uint32_t pattern = 0; pattern < 50; ++pattern) {
      uint32_t p = m.pcg_hash(pattern);
      std::vector<int> xs(count, 0), ys(count, 0);
      for (uint32_t s = 0; s < count; ++s) {
        glm::vec2 u = m.cmj_sample(s, count, p);
        ASSERT_GE(u.x, 0.0f);
        ASSERT_LT(u.x, 1.0f);
        ASSERT_GE(u.y, 0.0f);
        ASSERT_LT(u.y, 1.0f);
        ys[size_t(u.y * float(count))]++;
        xs[std::min(size_t(count - 1), size_t(u.x * float(count)))]++;
      }
      for (uint32_t k = 0; k < count; ++k) {
        ASSERT_EQ(ys[k], 1) << "y stratum " << k << " of " << count;
        // With count = m * n exactly, the x projection is stratified too.
        uint32_t mm = std::max(1u, uint32_t(std::sqrt(float(count))));
        if (count % mm == 0) {
          ASSERT_EQ(xs[k], 1) << "x stratum " << k << " of " << count;
        }
      }
    }
  }
  std::vector<double> obs(256, 0.0), expc(256, 0.0);
  int total = 0;
  for (uint32_t pattern = 0; pattern < 4000; ++pattern) {
    for (uint32_t s = 0; s < 64; ++s) {
      glm::vec2 u = m.cmj_sample(s, 64, m.pcg_hash(pattern + 12345u));
      obs[size_t(int(u.y * 16.0f) * 16 + int(u.x * 16.0f))] += 1.0;
      ++total;
    }
  }
  for (double& e : expc) e = total / 256.0;
  expect_fit(chi2_test(obs, expc, total), "cmj uniformity");
}

// The environment map's importance sampling: directions against
// environment_pdf, which must also integrate to 1 and match each sample's pdf.
// In wavepath's lat-long layout and in CS184's.
TEST(Sampling, EnvironmentMapSamplingMatchesItsPdf) {
  for (bool cs184 : {false, true}) {
  SCOPED_TRACE(cs184 ? "CS184's layout" : "wavepath's layout");
  Scene scene = load_scene(source_path("tests/data/features/environment.json"));
  scene.cs184LatLong = cs184;
  CompiledScene cs = compile_scene(scene, RenderOptions{});
  SceneView view = cs.view();
  ASSERT_NE(cs.params.environment.x, WP_INVALID);
  uint32_t extra = view.rng_seed(60u, 1u, 2u);
  int pdfMismatches = 0;  // samples whose direction rounds into the neighbouring cell
  DirectionalChi2 chi;
  chi.integrationRes = 8;
  chi.refineEdges = true;  // piecewise constant over the map's cells
  Chi2Result r = chi.run(
      kSamples,
      [&](glm::vec2 u, bool& ok) {
        float pdf;
        glm::vec3 d = view.environment_sample(glm::vec2(u.x, view.rng_next(extra)), pdf);
        ok = pdf > 0.0f;
        if (ok && std::fabs(pdf - view.environment_pdf(d)) > 1e-3f * pdf) ++pdfMismatches;
        return d;
      },
      [&](glm::vec3 w) { return double(view.environment_pdf(w)); }, 61);
  expect_fit(r, "environment map directions");
  EXPECT_LE(pdfMismatches, 10) << "of " << kSamples << " samples";
  double integral = std::accumulate(chi.expected.begin(), chi.expected.end(), 0.0) / kSamples;
  EXPECT_NEAR(integral, 1.0, 2e-3);
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
