// Every BSDF lobe (and a blend of lobes) against its pdf: chi-square over
// several incident directions and normals, energy (mean f cos / pdf <= 1.01),
// sample weight == eval / pdf, pdf normalisation where the lobe lies wholly
// above the surface; the delta lobes (mirror, dielectric) by their discrete
// probabilities and exact directions. One planted error shows the test can fail.
#include "test_support.h"

namespace wp::test {
namespace {

using namespace shader;

struct Lobe {
  uint32_t type;
  glm::vec3 color;
  float param;  // params.x
  float weight;
  glm::vec4 params{0.0f};  // when param alone does not say it: params, then params2
  glm::vec4 params2{0.0f};
};

ShaderMath::Bsdf make_bsdf(glm::vec3 n, const std::vector<Lobe>& lobes, bool front = true) {
  ShaderMath::Bsdf b{};
  b.ns = n;
  b.ng = n;
  b.front = front;
  b.lobeCount = 0;
  for (const Lobe& l : lobes) {
    b.lobeType[b.lobeCount] = l.type;
    b.lobeColor[b.lobeCount] = glm::vec4(l.color, 0.0f);
    ShaderMath{}.bsdf_set_params(b, b.lobeCount, l.params == glm::vec4(0.0f) ? glm::vec4(l.param, 0.0f, 0.0f, 0.0f) : l.params,
                                 l.params2);
    b.lobeWeight[b.lobeCount] = l.weight;
    ++b.lobeCount;
  }
  return b;
}

struct Config {
  const char* name;
  std::vector<Lobe> lobes;
  bool front = true;  // wo on the outer side
};

// Gold's complex index of refraction at the red, green and blue primaries.
const glm::vec4 kGoldEta(0.0f, 0.143f, 0.374f, 1.442f);  // x: alpha goes here
const glm::vec4 kGoldK(3.983f, 2.385f, 1.603f, 0.0f);

// The smooth lobes, including both cases of the metal's fuzz sphere (radius
// below 1: it excludes the origin; above 1: it contains it) and a blend.
const std::vector<Config>& smooth_configs() {
  static const std::vector<Config> configs = {
      {"lambertian", {{MAT_LAMBERTIAN, glm::vec3(1.0f), 0.0f, 1.0f}}},
      {"metal roughness 0.3", {{MAT_METAL, glm::vec3(1.0f), 0.3f, 1.0f}}},
      {"metal roughness 1.5", {{MAT_METAL, glm::vec3(1.0f), 1.5f, 1.0f}}},
      {"phong 5", {{MAT_PHONG, glm::vec3(1.0f), 5.0f, 1.0f}}},
      {"phong 60", {{MAT_PHONG, glm::vec3(1.0f), 60.0f, 1.0f}}},
      {"blinn-phong 10", {{MAT_BLINN_PHONG, glm::vec3(1.0f), 10.0f, 1.0f}}},
      {"blinn-phong 200", {{MAT_BLINN_PHONG, glm::vec3(1.0f), 200.0f, 1.0f}}},
      {"blend lambertian 0.4 + phong 30 0.6",
       {{MAT_LAMBERTIAN, glm::vec3(1.0f), 0.0f, 0.4f}, {MAT_PHONG, glm::vec3(1.0f), 30.0f, 0.6f}}},
      // The GGX lobes (params: kinds.glsl); MicrofacetLobes.* tests the
      // narrow ones, whose lobes fit in a cell or two of this grid.
      {"rough conductor (gold) alpha 0.09",
       {{MAT_ROUGH_CONDUCTOR, glm::vec3(1.0f), 0.0f, 1.0f, kGoldEta + glm::vec4(0.09f, 0, 0, 0), kGoldK}}},
      {"rough conductor (gold) alpha 0.5",
       {{MAT_ROUGH_CONDUCTOR, glm::vec3(1.0f), 0.0f, 1.0f, kGoldEta + glm::vec4(0.5f, 0, 0, 0), kGoldK}}},
      {"rough dielectric ior 1.5 alpha 0.09", {{MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), 0.0f, 1.0f, {1.5f, 0.09f, 0, 0}}}},
      {"rough dielectric ior 1.5 alpha 0.4, from inside",
       {{MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), 0.0f, 1.0f, {1.5f, 0.4f, 0, 0}}},
       false},
      {"metal-rough alpha 0.09 metallic 0", {{MAT_METAL_ROUGH, glm::vec3(0.8f, 0.5f, 0.2f), 0.0f, 1.0f, {0.09f, 0.0f, 1.5f, 0}}}},
      {"metal-rough alpha 0.49 metallic 0.5", {{MAT_METAL_ROUGH, glm::vec3(0.8f, 0.5f, 0.2f), 0.0f, 1.0f, {0.49f, 0.5f, 1.5f, 0}}}},
      {"metal-rough alpha 1 metallic 1", {{MAT_METAL_ROUGH, glm::vec3(1.0f), 0.0f, 1.0f, {1.0f, 1.0f, 1.5f, 0}}}},
      {"Beckmann conductor (gold) alpha 0.15, Smith",
       {{MAT_BECKMANN_CONDUCTOR, glm::vec3(1.0f), 0.0f, 1.0f, kGoldEta + glm::vec4(0.15f, 0, 0, 0), kGoldK}}},
      {"Beckmann conductor (gold) alpha 0.5, the CS184 skeleton's shadowing",
       {{MAT_BECKMANN_CONDUCTOR, glm::vec3(1.0f), 0.0f, 1.0f, kGoldEta + glm::vec4(0.5f, 0, 0, 0), kGoldK + glm::vec4(0, 0, 0, 1)}}},
      {"metal-rough alpha 0.16 metallic 0.2 transmission 0.7",
       {{MAT_METAL_ROUGH, glm::vec3(0.9f, 0.7f, 0.5f), 0.0f, 1.0f, {0.16f, 0.2f, 1.5f, 0.7f}}}},
  };
  return configs;
}

// One bsdf_sample call with four fresh random numbers from `state`.
struct Sample {
  glm::vec3 weight;
  glm::vec3 wi;
  float pdf;
  bool isDelta;
};
Sample sample_of(const ShaderMath::Bsdf& b, glm::vec3 wo, uint32_t& state) {
  ShaderMath m;
  glm::vec4 u(m.rng_next(state), m.rng_next(state), m.rng_next(state), m.rng_next(state));
  Sample r{};
  r.weight = m.bsdf_sample(b, wo, u, r.wi, r.pdf, r.isDelta);
  return r;
}

ShaderMath::Bsdf bsdf_of(const Config& c, glm::vec3 n) {
  return make_bsdf(n, c.lobes, c.front);
}

const auto& kGeometries = kBsdfGeometries;

constexpr int kChi2Samples = 300000;
const int kChi2Tests = int(std::size(kGeometries)) * 18;  // smooth_configs().size() configurations
const double kLevel = sidak(0.01, kChi2Tests);

glm::vec3 unit(glm::vec3 v) { return glm::normalize(v); }

// Chi-square of the directions `sampled` produces from wo against the pdf
// `claimed` reports (the same BSDF, unless an error is planted).
Chi2Result lobe_chi2(const ShaderMath::Bsdf& sampled, const ShaderMath::Bsdf& claimed, glm::vec3 wo, uint32_t seed) {
  DirectionalChi2 chi;
  chi.thetaRes = 48;
  chi.phiRes = 96;
  chi.integrationRes = 10;
  return bsdf_chi2(chi, kChi2Samples, sampled, claimed, wo, seed);
}

std::string str(glm::vec3 v) {
  return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

TEST(Bsdf, EverySmoothLobeSamplesItsPdf) {
  ASSERT_EQ(smooth_configs().size() * std::size(kGeometries), size_t(kChi2Tests));
  uint32_t seed = 100;
  for (const Config& c : smooth_configs()) {
    for (const BsdfGeometry& g : kGeometries) {
      glm::vec3 n = unit(g.n);
      glm::vec3 wo = unit(g.wo);
      if (glm::dot(wo, n) <= 0.0f) wo = -wo;
      ShaderMath::Bsdf b = bsdf_of(c, n);
      Chi2Result r = lobe_chi2(b, b, wo, seed++);
      // Entering glass head-on, the transmitted lobe narrows around the pole
      // to less than this grid's cells there: NarrowLobesSampleTheirPdf
      // tests that case on a grid centred on it.
      if (c.lobes[0].type == MAT_ROUGH_DIELECTRIC && c.front && glm::dot(wo, n) > 0.999f) continue;
      // Below radius 1 the metal's density grows without bound at the rim of
      // its cone, which no grid of cells integrates well enough: RoughMetal
      // tests it in the variable where its distribution is known in closed form.
      if (c.lobes[0].type == MAT_METAL && c.lobes[0].param < 1.0f) continue;
      EXPECT_TRUE(r.problem.empty()) << c.name << ": " << r.problem;
      EXPECT_GT(r.pValue, kLevel) << c.name << ", n = " << str(n) << ", wo = " << str(wo)
                                  << ": chi2 = " << r.statistic << " with " << r.dof << " dof";
    }
  }
}

// A lobe whose pdf is off by 5% in its exponent must fail the same test.
TEST(Bsdf, ChiSquareCatchesAPlantedExponentError) {
  glm::vec3 n(0, 0, 1);
  glm::vec3 wo = unit(glm::vec3(0.3f, 0.0f, 0.9f));
  ShaderMath::Bsdf sampled = make_bsdf(n, {{MAT_PHONG, glm::vec3(1.0f), 40.0f, 1.0f}});
  ShaderMath::Bsdf claimed = make_bsdf(n, {{MAT_PHONG, glm::vec3(1.0f), 42.0f, 1.0f}});
  Chi2Result r = lobe_chi2(sampled, claimed, wo, 4);
  EXPECT_LT(r.pValue, kLevel) << "a 5% error in the Phong exponent was not detected";
}

TEST(Bsdf, SmoothLobesConserveEnergyAndWeightIsEvalOverPdf) {
  ShaderMath m;
  uint32_t state = 77;
  for (const Config& c : smooth_configs()) {
    for (int d = 0; d < 10; ++d) {
      glm::vec3 n = m.square_to_uniform_sphere(glm::vec2(m.rng_next(state), m.rng_next(state)));
      glm::vec3 wo = m.square_to_uniform_sphere(glm::vec2(m.rng_next(state), m.rng_next(state)));
      if (glm::dot(wo, n) < 0.0f) wo = -wo;
      ShaderMath::Bsdf b = bsdf_of(c, n);
      double sum = 0.0;
      const int samples = 16384;
      for (int s = 0; s < samples; ++s) {
        Sample r = sample_of(b, wo, state);
        ASSERT_FALSE(r.isDelta) << c.name;
        ASSERT_TRUE(std::isfinite(r.weight.x)) << c.name;
        if (r.pdf <= 0.0f) continue;
        glm::vec3 ratio = m.bsdf_eval(b, wo, r.wi) / r.pdf;
        ASSERT_NEAR(ratio.x, r.weight.x, 1e-3f * std::max(1.0f, r.weight.x)) << c.name;
        sum += r.weight.x;
      }
      // glTF's dielectric layer weighs its base by 1 - F(wo.h), which at
      // grazing incidence adds up to more than it receives (Appendix B's
      // model, kept as specified; docs/scene-format.md): a white base at 89
      // degrees returns about 1.84x.
      const Lobe& l = c.lobes[0];
      // The CS184 skeleton's shadowing term (pi for sqrt(pi)) can exceed 1:
      // its conductor returns up to about 1.4x (beckmann_conductor.glsl).
      const bool skeleton = l.type == MAT_BECKMANN_CONDUCTOR && l.params2.w > 0.5f;
      const double bound = l.type == MAT_METAL_ROUGH && l.params.y < 1.0f ? 1.9 : skeleton ? 1.45 : 1.01;
      EXPECT_LT(sum / samples, bound) << c.name << ", direction " << d;
    }
  }
}

// At normal incidence the lobes lie above the surface and their pdfs integrate
// to 1, except Blinn-Phong, whose half vectors beyond 45 degrees send wi below
// the surface: it integrates to 1 - cos(45)^(n + 1).
TEST(Bsdf, PdfIntegratesToOneWhenTheLobeIsAboveTheSurface) {
  ShaderMath m;
  for (const Config& c : smooth_configs()) {
    if (c.lobes[0].type == MAT_METAL) continue;  // radius above 1 reaches below the surface; below 1, RoughMetal
    if (c.lobes[0].params != glm::vec4(0.0f)) continue;  // GGX loses samples below the surface: MicrofacetLobes
    glm::vec3 n(0, 0, 1);
    ShaderMath::Bsdf b = bsdf_of(c, n);
    DirectionalChi2 grid;
    grid.thetaRes = 400;
    grid.phiRes = 64;
    grid.integrationRes = 4;
    grid.run(1, [](glm::vec2, bool& ok) { ok = false; return glm::vec3(0, 0, 1); },
             [&](glm::vec3 wi) { return double(m.bsdf_pdf(b, n, wi)); }, 1);
    double integral = std::accumulate(grid.expected.begin(), grid.expected.end(), 0.0);
    double expected = 1.0;
    if (c.lobes[0].type == MAT_BLINN_PHONG) expected -= std::pow(std::sqrt(0.5), c.lobes[0].param + 1.0);
    EXPECT_NEAR(integral, expected, 5e-3) << c.name;
  }
}

// darts' rough metal: wi = normalize(r + rho s), s uniform on the unit
// sphere, r the mirror direction. For rho < 1 the cosine c = wi . r has the
// distribution F(c) = c sqrt(c^2 - (1 - rho^2)) / rho on [sqrt(1 - rho^2), 1]
// (integrating the pdf over the azimuth gives its derivative), and the
// azimuth around r is uniform. Chi-square over (c, azimuth) cells whose
// probabilities F gives exactly; the pdf against F', and a planted error in
// rho is caught.
double metal_cdf(double c, double rho) {
  double k = 1.0 - rho * rho;
  return c * std::sqrt(std::max(c * c - k, 0.0)) / rho;
}

Chi2Result metal_chi2(float rho, float claimedRho, uint32_t seed) {
  const glm::vec3 n(0, 0, 1), wo(0, 0, 1);  // the mirror direction is +Z; the whole lobe lies above the surface
  ShaderMath::Bsdf b = make_bsdf(n, {{MAT_METAL, glm::vec3(1.0f), rho, 1.0f}});
  const int cBins = 40, phiBins = 16;
  const double cMin = std::sqrt(1.0 - double(claimedRho) * claimedRho);
  std::vector<double> observed(cBins * phiBins, 0.0), expected(cBins * phiBins, 0.0);
  uint32_t state = seed;
  for (int i = 0; i < kChi2Samples; ++i) {
    Sample smp = sample_of(b, wo, state);
    if (smp.pdf <= 0.0f) continue;
    double c = smp.wi.z, phi = std::atan2(smp.wi.y, smp.wi.x) + M_PI;
    int ci = std::clamp(int((c - cMin) / (1.0 - cMin) * cBins), 0, cBins - 1);
    int pi = std::clamp(int(phi / (2.0 * M_PI) * phiBins), 0, phiBins - 1);
    observed[size_t(ci * phiBins + pi)] += 1.0;
  }
  for (int ci = 0; ci < cBins; ++ci) {
    double lo = cMin + (1.0 - cMin) * ci / cBins, hi = cMin + (1.0 - cMin) * (ci + 1) / cBins;
    double p = metal_cdf(hi, claimedRho) - metal_cdf(lo, claimedRho);
    for (int pi = 0; pi < phiBins; ++pi) expected[size_t(ci * phiBins + pi)] = p / phiBins * kChi2Samples;
  }
  return chi2_test(observed, expected, kChi2Samples);
}

TEST(Bsdf, RoughMetalSamplesItsPdfAroundTheMirrorDirection) {
  ShaderMath m;
  const double level = sidak(0.01, 3);
  uint32_t seed = 500;
  for (float rho : {0.1f, 0.3f, 0.7f}) {
    Chi2Result r = metal_chi2(rho, rho, seed++);
    EXPECT_TRUE(r.problem.empty()) << "roughness " << rho << ": " << r.problem;
    EXPECT_GT(r.pValue, level) << "roughness " << rho << ": chi2 = " << r.statistic << " with " << r.dof << " dof";
    // The pdf, integrated over the azimuth, is F'(c).
    for (double c : {0.2, 0.5, 0.8, 0.95, 0.999}) {
      double cMin = std::sqrt(1.0 - double(rho) * rho);
      double cc = cMin + (1.0 - cMin) * c;
      double h = 1e-4 * (1.0 - cMin);
      double derivative = (metal_cdf(cc + h, rho) - metal_cdf(cc - h, rho)) / (2.0 * h);
      glm::vec3 wi(float(std::sqrt(1.0 - cc * cc)), 0.0f, float(cc));
      EXPECT_NEAR(2.0 * M_PI * m.fuzzed_direction_pdf(wi, glm::vec3(0, 0, 1), rho), derivative, 2e-3 * derivative) << rho << " " << cc;
    }
    EXPECT_NEAR(metal_cdf(1.0, rho), 1.0, 1e-12);  // the distribution is normalised
  }
  // Radius 1 is the cosine lobe around the mirror direction.
  EXPECT_NEAR(m.fuzzed_direction_pdf(glm::normalize(glm::vec3(0.3f, 0.4f, 0.8f)), glm::vec3(0, 0, 1), 1.0f),
              glm::normalize(glm::vec3(0.3f, 0.4f, 0.8f)).z / M_PI, 1e-6);
}

TEST(Bsdf, RoughMetalChiSquareCatchesAPlantedRoughnessError) {
  Chi2Result r = metal_chi2(0.3f, 0.3f * 1.03f, 77);
  EXPECT_LT(r.pValue, 1e-6) << "chi2 = " << r.statistic;
}

TEST(Bsdf, FresnelReflectanceMatchesKnownValues) {
  ShaderMath m;
  // Normal incidence: ((eta - 1) / (eta + 1))^2.
  EXPECT_NEAR(m.fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);
  EXPECT_NEAR(m.fresnel_dielectric(1.0f, 1.0f / 1.5f), 0.04f, 1e-6f);
  // Grazing: total reflection; past the critical angle from inside: total.
  EXPECT_NEAR(m.fresnel_dielectric(0.0f, 1.5f), 1.0f, 1e-6f);
  float critical = std::sqrt(1.0f - 1.0f / (1.5f * 1.5f));  // cos of the critical angle
  EXPECT_EQ(m.fresnel_dielectric(critical * 0.99f, 1.0f / 1.5f), 1.0f);
  EXPECT_LT(m.fresnel_dielectric(critical * 1.01f, 1.0f / 1.5f), 1.0f);
  // Brewster's angle: tan(theta) = eta, where rp vanishes and F = rs^2 / 2.
  float thetaB = std::atan(1.5f);
  float cosI = std::cos(thetaB), cosT = std::cos(std::asin(std::sin(thetaB) / 1.5f));
  float rs = (cosI - 1.5f * cosT) / (cosI + 1.5f * cosT);
  EXPECT_NEAR(m.fresnel_dielectric(cosI, 1.5f), 0.5f * rs * rs, 1e-6f);
}

// The dielectric reflects with probability F and refracts by Snell's law,
// from either side; the weight is white either way.
// CS184's glass (cs184_glass.glsl): reflection with Schlick's probability
// R0 + (1 - R0)(1 - cos)^5 weighted by the reflectance, refraction by Snell
// weighted by the transmittance times eta^2 (transmitted over incident
// index); total internal reflection reflects, or, for the refraction-only
// BSDF, is absorbed, which otherwise never reflects.
TEST(Bsdf, Cs184GlassPicksBySchlickAndScalesByEtaSquared) {
  const float ior = 1.5f;
  const glm::vec3 n(0, 0, 1), transmittance(0.9f, 0.8f, 0.7f), reflectance(0.6f, 0.7f, 0.8f);
  const float r0 = 0.04f;  // ((1 - 1.5) / (1 + 1.5))^2
  uint32_t state = 12;
  for (bool refractionOnly : {false, true}) {
    for (bool front : {true, false}) {
      for (float cosO : {0.95f, 0.6f, 0.3f}) {
        const glm::vec3 wo(std::sqrt(1.0f - cosO * cosO), 0.0f, cosO);
        const glm::vec4 params(ior, refractionOnly ? 1.0f : 0.0f, 0.0f, 0.0f);
        ShaderMath::Bsdf b = make_bsdf(n, {{MAT_CS184_GLASS, transmittance, ior, 1.0f, params, glm::vec4(reflectance, 0.0f)}}, front);
        const float eta = front ? ior : 1.0f / ior;
        const bool tir = (1.0f - cosO * cosO) / (eta * eta) >= 1.0f;
        const double r = tir ? 1.0 : r0 + (1.0 - r0) * std::pow(1.0 - cosO, 5.0);
        int reflected = 0;
        const int samples = 100000;
        for (int s = 0; s < samples; ++s) {
          Sample x = sample_of(b, wo, state);
          ASSERT_TRUE(x.isDelta);
          if (x.wi.z > 0.0f) {
            ++reflected;
            ASSERT_EQ(x.weight, refractionOnly ? glm::vec3(0.0f) : reflectance);
            ASSERT_NEAR(x.wi.x, -wo.x, 1e-5f);
          } else {
            ASSERT_NEAR(std::sqrt(x.wi.x * x.wi.x + x.wi.y * x.wi.y) * eta, wo.x, 1e-5f);  // Snell
            ASSERT_NEAR(glm::distance(x.weight, transmittance * eta * eta), 0.0f, 1e-5f);
          }
        }
        const double expected = refractionOnly ? (tir ? 1.0 : 0.0) : r;
        const double sd = std::sqrt(expected * (1.0 - expected) / samples);
        EXPECT_NEAR(double(reflected) / samples, expected, 5.0 * sd + 1e-9)
            << "front " << front << " cos " << cosO << " refraction only " << refractionOnly;
        if (!front && cosO == 0.3f) {
          EXPECT_TRUE(tir) << "the case meant to reflect totally does not";
        }
      }
    }
  }
}

TEST(Bsdf, DielectricReflectsWithFresnelProbabilityAndRefractsBySnell) {
  ShaderMath m;
  const float ior = 1.5f;
  glm::vec3 n(0, 0, 1);
  uint32_t state = 9;
  for (bool front : {true, false}) {
    for (float cosI : {0.95f, 0.6f, 0.3f}) {
      glm::vec3 wo(std::sqrt(1.0f - cosI * cosI), 0.0f, cosI);
      ShaderMath::Bsdf b = make_bsdf(n, {{MAT_DIELECTRIC, glm::vec3(1.0f), ior, 1.0f}}, front);
      float eta = front ? ior : 1.0f / ior;
      double f = m.fresnel_dielectric(cosI, eta);
      int reflected = 0;
      const int samples = 200000;
      for (int s = 0; s < samples; ++s) {
        Sample r = sample_of(b, wo, state);
        glm::vec3 wi = r.wi;
        ASSERT_TRUE(r.isDelta);
        ASSERT_EQ(r.weight, glm::vec3(1.0f));
        ASSERT_NEAR(glm::length(wi), 1.0f, 1e-5f);
        if (wi.z > 0.0f) {
          ++reflected;
          ASSERT_NEAR(wi.x, -wo.x, 1e-5f);
          ASSERT_NEAR(wi.z, wo.z, 1e-5f);
        } else {
          // Snell: sin(theta_t) * eta = sin(theta_i), in the plane of incidence, on the far side.
          float sinT = std::sqrt(wi.x * wi.x + wi.y * wi.y);
          ASSERT_NEAR(sinT * eta, wo.x, 1e-5f);
          ASSERT_LT(wi.x, 0.0f);
        }
      }
      // Binomial: 5 standard deviations.
      double sd = std::sqrt(f * (1.0 - f) / samples);
      EXPECT_NEAR(double(reflected) / samples, f, 5.0 * sd + 1e-9) << "front " << front << " cos " << cosI;
    }
  }
}

TEST(Bsdf, MirrorMetalReflectsExactlyAndHasNoDensity) {
  ShaderMath m;
  glm::vec3 n = unit(glm::vec3(0.2f, 0.3f, 0.9f));
  glm::vec3 wo = unit(glm::vec3(0.5f, -0.2f, 0.7f));
  ShaderMath::Bsdf b = make_bsdf(n, {{MAT_METAL, glm::vec3(0.9f, 0.5f, 0.2f), 0.0f, 1.0f}});
  glm::vec3 wi;
  float pdf;
  bool isDelta;
  glm::vec3 w(m.bsdf_sample(b, wo, glm::vec4(0.3f, 0.6f, 0.2f, 0.9f), wi, pdf, isDelta));
  EXPECT_TRUE(isDelta);
  EXPECT_EQ(w, glm::vec3(0.9f, 0.5f, 0.2f));
  EXPECT_NEAR(glm::dot(wi, n), glm::dot(wo, n), 1e-6f);
  EXPECT_NEAR(glm::length(glm::cross(wi + wo, n)), 0.0f, 1e-5f);
  EXPECT_FALSE(m.bsdf_has_smooth_lobe(b));
  EXPECT_EQ(m.bsdf_pdf(b, wo, wi), 0.0f);
  EXPECT_EQ(glm::vec3(m.bsdf_eval(b, wo, wi)), glm::vec3(0.0f));
}

// A blend of a delta and a smooth lobe: the delta lobe is taken with its
// weight's probability, and eval / pdf see only the smooth part.
TEST(Bsdf, BlendOfDeltaAndSmoothLobesPicksEachByWeight) {
  glm::vec3 n(0, 0, 1);
  glm::vec3 wo = unit(glm::vec3(0.3f, 0.1f, 0.9f));
  ShaderMath::Bsdf b = make_bsdf(n, {{MAT_LAMBERTIAN, glm::vec3(0.5f), 0.0f, 0.7f}, {MAT_METAL, glm::vec3(1.0f), 0.0f, 0.3f}});
  uint32_t state = 21;
  int delta = 0;
  const int samples = 100000;
  double smoothWeight = 0.0;
  for (int s = 0; s < samples; ++s) {
    Sample r = sample_of(b, wo, state);
    if (r.isDelta) {
      ++delta;
      ASSERT_EQ(r.weight, glm::vec3(1.0f));
    } else {
      ASSERT_NEAR(r.pdf, 0.7f * glm::dot(r.wi, n) / float(M_PI), 1e-5f);
      smoothWeight += r.weight.x;
    }
  }
  double sd = std::sqrt(0.3 * 0.7 / samples);
  EXPECT_NEAR(double(delta) / samples, 0.3, 5.0 * sd);
  // The smooth part's weight is albedo (0.5) / selection probability (0.7) times 0.7.
  EXPECT_NEAR(smoothWeight / (samples - delta), 0.5, 1e-4);
}

TEST(Sampling, ConeAndPowerWarpsMatchTheirPdfs) {
  ShaderMath m;
  const double level = sidak(0.01, 3);
  // Cone edges on cell boundaries (cells are 1/16 of 1 - cos wide), so the midpoint rule is exact.
  for (float oneMinusCos : {0.0625f, 0.5f}) {
    DirectionalChi2 chi;
    chi.integrationRes = 8;
    Chi2Result r = chi.run(
        kChi2Samples, [&](glm::vec2 u, bool&) { return m.square_to_uniform_cone(u, oneMinusCos); },
        [&](glm::vec3 w) { return 1.0f - w.z <= oneMinusCos ? double(m.uniform_cone_pdf(oneMinusCos)) : 0.0; }, 31);
    EXPECT_GT(r.pValue, level) << "cone " << oneMinusCos << ": chi2 " << r.statistic;
  }
  DirectionalChi2 chi;
  chi.integrationRes = 8;
  Chi2Result r = chi.run(
      kChi2Samples, [&](glm::vec2 u, bool&) { return m.square_to_cosine_power(u, 12.0f); },
      [&](glm::vec3 w) { return double(m.cosine_power_pdf(w.z, 12.0f)); }, 32);
  EXPECT_GT(r.pValue, level) << "cosine power: chi2 " << r.statistic;
}

}  // namespace
}  // namespace wp::test
