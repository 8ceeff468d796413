// The GGX microfacet lobes (microfacet.glsl and the rough_conductor,
// rough_dielectric and metal_rough kinds): visible-normal sampling against
// its pdf, narrow lobes on grids centred on their peaks, the pdf's integral
// against the fraction of samples a lobe keeps, the conductor's Fresnel
// term, the dielectric's reciprocity, a white furnace against single-
// scattering GGX computed independently, and a planted roughness error;
// CS184's Beckmann conductor's terms against its skeleton's formulas, and
// a planted alpha error. (Bsdf.* runs the wider lobes of both through the
// tests every lobe takes.)
#include <functional>
#include "test_support.h"

namespace wp::test {
namespace {

using namespace shader;

const glm::vec3 kNormal(0.0f, 0.0f, 1.0f);

glm::vec3 at_angle(float degrees) {
  float t = glm::radians(degrees);
  return glm::vec3(std::sin(t), 0.0f, std::cos(t));
}

ShaderMath::Bsdf one_lobe(uint32_t type, glm::vec3 color, glm::vec4 params, glm::vec4 params2 = glm::vec4(0.0f),
                          bool front = true) {
  ShaderMath::Bsdf b{};
  b.ns = kNormal;
  b.ng = kNormal;
  b.front = front;
  b.lobeCount = 1;
  b.lobeType[0] = type;
  b.lobeColor[0] = glm::vec4(color, 0.0f);
  ShaderMath{}.bsdf_set_params(b, 0, params, params2);
  b.lobeWeight[0] = 1.0f;
  return b;
}

// Gold at the red, green and blue primaries.
const glm::vec3 kGoldEta(0.143f, 0.374f, 1.442f);
const glm::vec3 kGoldK(3.983f, 2.385f, 1.603f);

ShaderMath::Bsdf conductor(float alpha) {
  return one_lobe(MAT_ROUGH_CONDUCTOR, glm::vec3(1.0f), glm::vec4(alpha, kGoldEta), glm::vec4(kGoldK, 0.0f));
}
ShaderMath::Bsdf dielectric(float alpha, bool front) {
  return one_lobe(MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), glm::vec4(1.5f, alpha, 0.0f, 0.0f), glm::vec4(0.0f), front);
}
ShaderMath::Bsdf metal_rough(float alpha, float metallic, glm::vec3 base) {
  return one_lobe(MAT_METAL_ROUGH, base, glm::vec4(alpha, metallic, 1.5f, 0.0f));
}

constexpr double kFamilyLevel = 0.01;

TEST(MicrofacetLobes, VisibleNormalsAreSampledWithTheirPdf) {
  const float alphas[] = {0.0025f, 0.09f, 0.5f, 1.0f};
  const float angles[] = {0.0f, 45.0f, 80.0f};
  const double level = sidak(kFamilyLevel, int(std::size(alphas) * std::size(angles)));
  ShaderMath m;
  uint32_t seed = 500;
  for (float alpha : alphas)
    for (float angle : angles) {
      glm::vec3 wo = at_angle(angle);
      DirectionalChi2 grid;
      grid.thetaRes = 48;
      grid.phiRes = 48;
      grid.integrationRes = 8;
      grid.polarPower = alpha < 0.01f ? 8 : alpha < 0.2f ? 3 : 1;  // narrow distributions get cells near the normal
      Chi2Result r = grid.run(
          200000, [&](glm::vec2 u, bool& ok) { ok = true; return m.ggx_sample_visible(wo, alpha, u); },
          [&](glm::vec3 h) { return double(m.ggx_visible_pdf(wo, h, kNormal, alpha)); }, seed++);
      EXPECT_TRUE(r.problem.empty()) << r.problem;
      EXPECT_GT(r.pValue, level) << "alpha " << alpha << ", wo at " << angle << " degrees: chi2 = " << r.statistic
                                 << " with " << r.dof << " dof";
    }
}

// A lobe of roughness 0.05 (alpha 0.0025) fits in a cell of a uniform grid,
// so its grid is centred on its peak (the mirror or the refracted
// direction) with cells crowded towards it.
struct NarrowCase {
  const char* name;
  ShaderMath::Bsdf bsdf;
  float angle;
  bool refracted;  // the peak is the refracted direction
};

glm::vec3 peak_of(const NarrowCase& c, glm::vec3 wo) {
  if (!c.refracted) return glm::vec3(-wo.x, -wo.y, wo.z);
  float eta = c.bsdf.front ? 1.5f : 1.0f / 1.5f;
  float cosT = std::sqrt(1.0f - (1.0f - wo.z * wo.z) / (eta * eta));
  return glm::normalize(kNormal * (wo.z / eta - cosT) - wo / eta);
}

TEST(MicrofacetLobes, NarrowLobesSampleTheirPdf) {
  const float a = 0.0025f;
  const NarrowCase cases[] = {
      {"conductor", conductor(a), 0.0f, false},
      {"conductor", conductor(a), 50.0f, false},
      {"conductor", conductor(a), 80.0f, false},
      {"metal-rough, metallic 1", metal_rough(a, 1.0f, glm::vec3(0.9f, 0.6f, 0.3f)), 30.0f, false},
      {"metal-rough, metallic 0.5", metal_rough(a, 0.5f, glm::vec3(0.9f, 0.6f, 0.3f)), 60.0f, false},
      {"dielectric, entering", dielectric(a, true), 0.0f, true},
      {"dielectric, entering", dielectric(a, true), 60.0f, true},
      {"dielectric, entering, reflection", dielectric(a, true), 60.0f, false},
      {"dielectric, leaving", dielectric(a, false), 30.0f, true},
  };
  const double level = sidak(kFamilyLevel, int(std::size(cases)));
  uint32_t seed = 600;
  for (const NarrowCase& c : cases) {
    glm::vec3 wo = at_angle(c.angle);
    DirectionalChi2 grid;
    grid.pole = peak_of(c, wo);
    grid.polarPower = 8;
    grid.thetaRes = 64;
    grid.phiRes = 48;
    grid.integrationRes = 8;
    // The dielectric's two peaks, one at a time: the other's cells here are coarse.
    bool dielectric = c.bsdf.lobeType[0] == MAT_ROUGH_DIELECTRIC;
    auto onPeakSide = [&](glm::vec3 wi) { return !dielectric || (wi.z < 0.0f) == c.refracted; };
    Chi2Result r = bsdf_chi2(grid, 300000, c.bsdf, c.bsdf, wo, seed++, onPeakSide);
    EXPECT_TRUE(r.problem.empty()) << c.name << ": " << r.problem;
    EXPECT_GT(r.pValue, level) << c.name << ", wo at " << c.angle << " degrees: chi2 = " << r.statistic << " with "
                               << r.dof << " dof";
  }
}

// A visible normal may send wi below the surface (or a refraction above it);
// the lobe drops those samples, and its pdf integrates to the fraction kept.
TEST(MicrofacetLobes, PdfIntegratesToTheFractionOfSamplesKept) {
  struct Case {
    const char* name;
    ShaderMath::Bsdf bsdf;
  };
  const Case cases[] = {
      {"conductor alpha 0.5", conductor(0.5f)},
      {"conductor alpha 1", conductor(1.0f)},
      {"dielectric alpha 0.4 entering", dielectric(0.4f, true)},
      {"dielectric alpha 0.4 leaving", dielectric(0.4f, false)},
      {"metal-rough alpha 1 metallic 0.5", metal_rough(1.0f, 0.5f, glm::vec3(0.5f))},
      {"metal-rough alpha 0.3 transmission 0.9",
       one_lobe(MAT_METAL_ROUGH, glm::vec3(0.8f), glm::vec4(0.3f, 0.0f, 1.5f, 0.9f))},
  };
  ShaderMath m;
  for (const Case& c : cases)
    for (float angle : {0.0f, 70.0f}) {
      glm::vec3 wo = at_angle(angle);
      DirectionalChi2 grid;
      grid.thetaRes = 400;
      grid.phiRes = 128;
      grid.integrationRes = 4;
      grid.run(1, [](glm::vec2, bool& ok) { ok = false; return kNormal; },
               [&](glm::vec3 wi) { return double(m.bsdf_pdf(c.bsdf, wo, wi)); }, 1);
      double integral = std::accumulate(grid.expected.begin(), grid.expected.end(), 0.0);
      uint32_t state = 9;
      const int n = 200000;
      int kept = 0;
      for (int i = 0; i < n; ++i) {
        glm::vec4 u(m.rng_next(state), m.rng_next(state), m.rng_next(state), m.rng_next(state));
        glm::vec3 wi;
        float pdf;
        bool isDelta;
        m.bsdf_sample(c.bsdf, wo, u, wi, pdf, isDelta);
        if (pdf > 0.0f) ++kept;
      }
      double fraction = double(kept) / n;
      double sigma = std::sqrt(fraction * (1.0 - fraction) / n);
      EXPECT_NEAR(integral, fraction, 4.0 * sigma + 2e-3) << c.name << ", wo at " << angle << " degrees";
      EXPECT_GT(fraction, 0.3) << c.name;
    }
}

TEST(MicrofacetLobes, ConductorFresnelReducesToKnownCases) {
  ShaderMath m;
  // Without absorption it is the dielectric's reflectance.
  for (float eta : {1.2f, 1.5f, 2.4f})
    for (float c : {1.0f, 0.7f, 0.3f, 0.05f}) {
      float fd = m.fresnel_dielectric(c, eta);
      glm::vec4 fc = m.fresnel_conductor(c, glm::vec4(eta), glm::vec4(0.0f));
      EXPECT_NEAR(fc.x, fd, 1e-5f) << "eta " << eta << ", cos " << c;
    }
  // At normal incidence ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2); at grazing 1.
  glm::vec3 f0(m.fresnel_conductor(1.0f, glm::vec4(kGoldEta, 1.0f), glm::vec4(kGoldK, 0.0f)));
  for (int i = 0; i < 3; ++i) {
    float e = kGoldEta[i], k = kGoldK[i];
    EXPECT_NEAR(f0[i], ((e - 1) * (e - 1) + k * k) / ((e + 1) * (e + 1) + k * k), 1e-5f);
  }
  glm::vec3 grazing(m.fresnel_conductor(0.0f, glm::vec4(kGoldEta, 1.0f), glm::vec4(kGoldK, 0.0f)));
  EXPECT_NEAR(grazing.x, 1.0f, 1e-5f);
  EXPECT_NEAR(grazing.z, 1.0f, 1e-5f);
  // Gold reflects red more than blue.
  EXPECT_GT(f0.x, 0.9f);
  EXPECT_LT(f0.z, 0.45f);
}

// Checks f(a, b) = ratio(b) f(b, a) for 2000 random pairs, a on the front
// and b anywhere, each seen from its own side (ns and ng face it, `front`
// says outside); bsdf(front) makes the BSDF seen from a side. Returns how
// many pairs transmitted.
int expect_reciprocal(const std::function<ShaderMath::Bsdf(bool)>& bsdf, float transmittedRatio, uint32_t seed) {
  ShaderMath m;
  uint32_t state = seed;
  int transmissions = 0;
  for (int i = 0; i < 2000; ++i) {
    glm::vec3 a = m.square_to_uniform_sphere(glm::vec2(m.rng_next(state), m.rng_next(state)));
    glm::vec3 b = m.square_to_uniform_sphere(glm::vec2(m.rng_next(state), m.rng_next(state)));
    if (a.z < 0.0f) a = -a;
    ShaderMath::Bsdf fromA = bsdf(true);
    ShaderMath::Bsdf fromB = bsdf(b.z > 0.0f);
    fromB.ns = fromB.ng = b.z > 0.0f ? kNormal : -kNormal;
    glm::vec3 fab = m.bsdf_eval(fromA, a, b) / std::abs(b.z);
    glm::vec3 fba = m.bsdf_eval(fromB, b, a) / std::abs(a.z);
    float ratio = b.z > 0.0f ? 1.0f : transmittedRatio;
    if (b.z < 0.0f && fab.x > 0.0f) ++transmissions;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(fab[c], ratio * fba[c], 1e-4f * std::max(1.0f, fab[c]))
          << "a = (" << a.x << ", " << a.y << ", " << a.z << "), b = (" << b.x << ", " << b.y << ", " << b.z << ")";
  }
  return transmissions;
}

// Reflection is symmetric in wo and wi. Transmission, in the radiance
// convention, obeys f(wo, wi) / eta_i^2 = f(wi, wo) / eta_o^2 (each side's
// index); wavepath's dielectrics do not scale radiance by eta^2 on crossing
// (as darts), which multiplies f(wo, wi) by (eta_i / eta_o)^2, so here
// f(wo, wi) = (eta_i / eta_o)^2 f(wi, wo).
TEST(MicrofacetLobes, RoughDielectricIsReciprocal) {
  EXPECT_GT(expect_reciprocal([](bool front) { return dielectric(0.5f, front); }, 1.5f * 1.5f, 31), 200);
}

// glTF's transmission without a volume is thin-walled: the GGX lobe mirrored
// through the surface, which keeps the BSDF symmetric across it (no ratio of
// indices: the light leaves into the medium it came from).
TEST(MicrofacetLobes, ThinWalledTransmissionIsReciprocal) {
  const glm::vec4 params(0.3f, 0.25f, 1.5f, 0.8f);  // alpha, metallic, ior, transmission
  auto bsdf = [&](bool front) { return one_lobe(MAT_METAL_ROUGH, glm::vec3(0.9f, 0.6f, 0.4f), params, glm::vec4(0.0f), front); };
  EXPECT_GT(expect_reciprocal(bsdf, 1.0f, 37), 200);
}

// A metal of base colour 1 (F = 1) keeps exactly what single-scattering GGX
// keeps: E(mu) above, which loses energy where microfacets shadow each
// other or reflect below the horizon (EXPECTED_LOSS below).
TEST(MicrofacetLobes, WhiteFurnaceLosesWhatSingleScatteringGgxLoses) {
  ShaderMath m;
  struct Case {
    float roughness;
    float angle;
  };
  for (Case c : {Case{0.05f, 0.0f}, Case{0.5f, 0.0f}, Case{1.0f, 0.0f}, Case{0.5f, 60.0f}, Case{1.0f, 80.0f}}) {
    const float alpha = c.roughness * c.roughness;
    glm::vec3 wo = at_angle(c.angle);
    ShaderMath::Bsdf b = metal_rough(alpha, 1.0f, glm::vec3(1.0f));
    uint32_t state = 17;
    const int n = 400000;
    double sum = 0.0, sumSq = 0.0;
    for (int i = 0; i < n; ++i) {
      glm::vec4 u(m.rng_next(state), m.rng_next(state), m.rng_next(state), m.rng_next(state));
      glm::vec3 wi;
      float pdf;
      bool isDelta;
      double w = m.bsdf_sample(b, wo, u, wi, pdf, isDelta).x;
      sum += w;
      sumSq += w * w;
    }
    double mean = sum / n, sigma = std::sqrt(std::max(sumSq / n - mean * mean, 0.0) / n);
    double expected = ggx_albedo(alpha, std::max(double(wo.z), 1e-6));
    EXPECT_NEAR(mean, expected, 4.0 * sigma + 1e-3) << "roughness " << c.roughness << " at " << c.angle << " degrees";
    std::printf("roughness %.2f at %2.0f degrees: E = %.4f, sampled %.4f\n", c.roughness, c.angle, expected, mean);
  }
}

// The furnace through the renderer: a sphere of that metal under a white sky,
// seen head-on through a narrow field of view, shows E(1) in every pixel.
TEST(MicrofacetLobes, WhiteFurnaceSphereRendersTheSingleScatteringAlbedo) {
  const std::string scene = write_scene("furnace.json", R"({
    "camera": {"transform": {"from": [0, 0, 100], "at": [0, 0, 0], "up": [0, 1, 0]}, "vfov": 0.05, "resolution": [4, 4]},
    "sampler": {"samples": 4096},
    "integrator": {"type": "path tracer mis", "max bounces": 8},
    "background": 1,
    "materials": [{"type": "metal_rough", "name": "white metal", "base_color": 1, "metallic": 1, "roughness": 1}],
    "surfaces": [{"type": "sphere", "radius": 1, "material": "white metal"}]
  })");
  ImageStats img = render_reference(scene, RenderOptions{});
  auto [mean, error] = image_mean(img);
  EXPECT_NEAR(mean, ggx_albedo(1.0, 1.0), 4.0 * error + 2e-3);
}

// A 5% error in alpha between sampling and the claimed pdf must fail the chi-square.
// χ² of `sampled`'s directions against `claimed`'s pdf, wo at 35 degrees.
Chi2Result planted_chi2(const ShaderMath::Bsdf& sampled, const ShaderMath::Bsdf& claimed, uint32_t seed) {
  DirectionalChi2 grid;
  grid.thetaRes = 48;
  grid.phiRes = 96;
  grid.integrationRes = 10;
  return bsdf_chi2(grid, 300000, sampled, claimed, at_angle(35.0f), seed);
}

TEST(MicrofacetLobes, ChiSquareCatchesAPlantedRoughnessError) {
  Chi2Result r = planted_chi2(metal_rough(0.25f, 1.0f, glm::vec3(0.9f)), metal_rough(0.25f * 1.05f, 1.0f, glm::vec3(0.9f)), 3);
  EXPECT_LT(r.pValue, 1e-4) << "a 5% error in GGX's alpha was not detected";
}

// CS184's microfacet conductor (beckmann_conductor.glsl) as its skeleton
// writes it: the course's Lambda (with pi, erf from the shared
// approximation) against std::erf in double precision; its Fresnel
// approximation against the exact conductor term at normal incidence,
// where the two agree; the half vectors' density D cos integrating to 1.
TEST(MicrofacetLobes, Cs184MicrofacetTermsAreTheSkeletons) {
  ShaderMath m;
  for (float alpha : {0.05f, 0.25f, 0.5f})
    for (float c : {0.05f, 0.3f, 0.7f, 0.95f, 0.9999f}) {
      const double theta = std::acos(std::clamp(double(c), -1.0 + 1e-5, 1.0 - 1e-5));
      const double a = 1.0 / (alpha * std::tan(theta));
      const double skeleton = 0.5 * (std::erf(a) - 1.0 + std::exp(-a * a) / (a * M_PI));
      const double smith = 0.5 * (std::erf(a) - 1.0 + std::exp(-a * a) / (a * std::sqrt(M_PI)));
      EXPECT_NEAR(m.cs184_lambda(alpha, c, true), skeleton, 2e-6 + 1e-5 * std::fabs(skeleton)) << alpha << ", " << c;
      EXPECT_NEAR(m.cs184_lambda(alpha, c, false), smith, 2e-6 + 1e-5 * std::fabs(smith)) << alpha << ", " << c;
    }
  const glm::vec3 fNormal(m.cs184_fresnel(glm::vec4(kGoldEta, 1.0f), glm::vec4(kGoldK, 0.0f), 1.0f));
  const glm::vec3 exact(m.fresnel_conductor(1.0f, glm::vec4(kGoldEta, 1.0f), glm::vec4(kGoldK, 0.0f)));
  EXPECT_NEAR(glm::distance(fNormal, exact), 0.0f, 1e-5f);
  for (float alpha : {0.1f, 0.6f}) {
    double integral = 0.0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {  // over cos(theta_h), d omega = 2 pi d cos
      const float c = (float(i) + 0.5f) / float(n);
      integral += double(m.beckmann_d(alpha, c)) * c * 2.0 * M_PI / n;
    }
    EXPECT_NEAR(integral, 1.0, 1e-3) << "alpha " << alpha;
  }
}

TEST(MicrofacetLobes, ChiSquareCatchesAPlantedBeckmannAlphaError) {
  auto lobe = [](float alpha) {
    return one_lobe(MAT_BECKMANN_CONDUCTOR, glm::vec3(1.0f), glm::vec4(alpha, kGoldEta), glm::vec4(kGoldK, 0.0f));
  };
  Chi2Result r = planted_chi2(lobe(0.3f), lobe(0.3f * 1.05f), 4);
  EXPECT_LT(r.pValue, 1e-4) << "a 5% error in Beckmann's alpha was not detected";
}

}  // namespace
}  // namespace wp::test
