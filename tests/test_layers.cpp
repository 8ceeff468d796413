// glTF's layers and lobe parameters as wavepath builds them: the clear coat
// (KHR_materials_clearcoat), the sheen (KHR_materials_sheen) and the tinted
// specular layer of metal-rough (KHR_materials_specular). Each through
// bsdf_at, as the renderers see it: chi-square of the sampled directions
// against the pdf, white furnaces whose loss the extensions' albedo terms
// predict, the sheen's albedo table against its lobe, and a sphere under one
// directional light whose pixels the extensions' formulas, evaluated here
// independently of the shared code, predict. Each statistical test is shown
// once to catch a planted error.
#include "test_support.h"

namespace wp::test {
namespace {

using namespace shader;

// A darts material (JSON) on a unit sphere at the origin, compiled: the
// BSDF bsdf_at builds where the sphere's normal is n, seen from wo.
struct LayeredSphere {
  CompiledScene cs;
  mutable SceneView view;

  explicit LayeredSphere(const std::string& material, const std::string& extra = "") {
    const std::string text = R"({"camera": {"transform": {"from": [0, 0, 100], "at": [0, 0, 0], "up": [0, 1, 0]}, "vfov": 1.3,
      "resolution": [64, 64]}, "background": 0, "materials": [)" +
                             material + R"(], "surfaces": [{"type": "sphere", "radius": 1, "material": "m"})" + extra + "]}";
    cs = compile_scene(load_scene(write_scene("layered.json", text)), RenderOptions{});
    view = cs.view();
  }

  SceneView::Bsdf bsdf(glm::vec3 n, glm::vec3 wo) const {
    const glm::vec3 o = 3.0f * n;
    Hit h;
    EXPECT_EQ(view.trace_ray(o, -n, WP_INF, false, h), TRACE_OK);
    EXPECT_NEAR(h.t, 2.0f, 1e-4f);
    return view.bsdf_at(view.surface_at(o, -n, h), wo);
  }
};

// The materials under test, each named "m".
const char* const kClearcoatOverPlastic =
    R"({"type": "clearcoat", "name": "m", "roughness": 0.4, "base": {"type": "metal_rough", "base_color": [0.7, 0.2, 0.1], "metallic": 0, "roughness": 0.6}})";
const char* const kPatchyCoatOverMetal =
    R"({"type": "clearcoat", "name": "m", "factor": 0.7, "roughness": 0.5, "ior": 1.7, "base": {"type": "metal_rough", "base_color": [0.9, 0.7, 0.3], "metallic": 1, "roughness": 0.5}})";
const char* const kSheenOverLambertian =
    R"({"type": "sheen", "name": "m", "color": [0.9, 0.5, 0.7], "roughness": 0.3, "base": {"type": "lambertian", "albedo": [0.3, 0.2, 0.1]}})";
const char* const kRoughSheenOverMetalRough =
    R"({"type": "sheen", "name": "m", "color": 1, "roughness": 0.8, "base": {"type": "metal_rough", "base_color": [0.2, 0.4, 0.6], "metallic": 0.5, "roughness": 0.4}})";
const char* const kCoatOverSheen =
    R"({"type": "clearcoat", "name": "m", "factor": 0.8, "roughness": 0.35, "base": {"type": "sheen", "color": [0.5, 0.8, 0.6], "roughness": 0.6,
        "base": {"type": "metal_rough", "base_color": [0.3, 0.3, 0.3], "metallic": 0, "roughness": 0.7}}})";
const char* const kTintedSpecular =
    R"({"type": "metal_rough", "name": "m", "base_color": [0.2, 0.3, 0.6], "metallic": 0.3, "roughness": 0.45, "specular": 0.6, "specular_color": [2.5, 1.2, 0.3]})";

const char* const kRoughGlass =
    R"({"type": "metal_rough", "name": "m", "base_color": [0.9, 0.8, 0.7], "metallic": 0.1, "roughness": 0.5, "transmission": 0.8,
        "ior": 1.4, "volume": {"attenuation_color": [0.5, 0.6, 0.7], "attenuation_distance": 2}})";

const char* const kIridescent =
    R"({"type": "metal_rough", "name": "m", "base_color": [0.3, 0.3, 0.35], "metallic": 0.4, "roughness": 0.35,
        "iridescence": {"factor": 0.9, "ior": 1.45, "thickness_minimum": 200, "thickness_maximum": 450}})";

const char* const kBrushed =
    R"({"type": "metal_rough", "name": "m", "base_color": [0.9, 0.8, 0.6], "metallic": 0.8, "roughness": 0.3,
        "anisotropy": {"strength": 0.8, "rotation": 0.5}})";

// KHR_materials_diffuse_transmission: thin, and under a rough glass's
// transmission into a volume (which takes its share first).
const char* const kTranslucent =
    R"({"type": "metal_rough", "name": "m", "base_color": [0.6, 0.8, 0.3], "metallic": 0.1, "roughness": 0.5,
        "diffuse_transmission": 0.6, "diffuse_transmission_color": [0.9, 0.5, 0.2]})";
const char* const kTranslucentGlass =
    R"({"type": "metal_rough", "name": "m", "base_color": [0.9, 0.9, 0.8], "metallic": 0, "roughness": 0.5, "transmission": 0.4,
        "ior": 1.4, "diffuse_transmission": 0.7, "volume": {"attenuation_color": [0.8, 0.6, 0.5], "attenuation_distance": 2}})";

const char* const kChi2Materials[] = {kClearcoatOverPlastic, kPatchyCoatOverMetal, kSheenOverLambertian, kRoughSheenOverMetalRough,
                                      kCoatOverSheen,        kTintedSpecular,      kRoughGlass,          kIridescent,
                                      kBrushed,              kTranslucent,         kTranslucentGlass};

const auto& kGeometries = kBsdfGeometries;

const int kChi2Tests = int(std::size(kChi2Materials) * std::size(kGeometries));
const double kLevel = sidak(0.01, kChi2Tests);

Chi2Result layered_chi2(const SceneView::Bsdf& sampled, const SceneView::Bsdf& claimed, glm::vec3 wo, uint32_t seed) {
  DirectionalChi2 grid;
  grid.thetaRes = 48;
  grid.phiRes = 96;
  grid.integrationRes = 10;
  return bsdf_chi2(grid, 300000, sampled, claimed, wo, seed);
}

glm::vec3 unit(glm::vec3 v) { return glm::normalize(v); }

TEST(Layers, EveryLayeredMaterialSamplesItsPdf) {
  uint32_t seed = 300;
  for (const char* material : kChi2Materials) {
    const LayeredSphere sphere(material);
    for (const BsdfGeometry& g : kGeometries) {
      const glm::vec3 n = unit(g.n), wo = unit(g.wo);
      const SceneView::Bsdf b = sphere.bsdf(n, wo);
      EXPECT_GE(b.lobeCount, 1u);
      const Chi2Result r = layered_chi2(b, b, wo, seed++);
      // Refracting head-on: RefractionIntoAndOutOfAVolumeSamplesItsPdf.
      if ((material == kRoughGlass || material == kTranslucentGlass) && wo.z > 0.999f) continue;
      EXPECT_TRUE(r.problem.empty()) << material << ": " << r.problem;
      EXPECT_GT(r.pValue, kLevel) << material << ", wo = " << wo.x << " " << wo.y << " " << wo.z << ": chi2 = " << r.statistic << " with "
                                  << r.dof << " dof";
    }
  }
}

// KHR_materials_volume's refraction into the volume head-on, and out of it
// head-on, obliquely and beyond the critical angle (where nothing leaves and
// the samples that would are lost). Head-on, the transmitted lobe narrows
// around the pole to a cell or two of the grid above, which cannot
// integrate it: a grid four times as fine, and more samples.
TEST(Layers, RefractionIntoAndOutOfAVolumeSamplesItsPdf) {
  const LayeredSphere sphere(kRoughGlass);
  uint32_t seed = 400;
  for (glm::vec3 wo : {glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0.5f, 0.0f, -0.85f), glm::vec3(0.85f, 0.0f, -0.5f)}) {
    wo = unit(wo);
    const SceneView::Bsdf b = sphere.bsdf({0, 0, 1}, wo);
    EXPECT_EQ(b.front, wo.z > 0.0f);
    DirectionalChi2 grid;
    grid.thetaRes = 192;
    grid.phiRes = 384;
    grid.integrationRes = 10;
    const Chi2Result r = bsdf_chi2(grid, 1000000, b, b, wo, seed++);
    EXPECT_TRUE(r.problem.empty()) << r.problem;
    EXPECT_GT(r.pValue, sidak(0.01, 4)) << "wo = " << wo.x << " " << wo.y << " " << wo.z << ": chi2 = " << r.statistic << " with " << r.dof << " dof";
  }
}

// The same test with the coat's roughness 5 % off in the claimed pdf fails
// (at an oblique view, where the coat reflects a fifth of the light).
TEST(Layers, ChiSquareCatchesAPlantedCoatRoughnessError) {
  auto with = [](const char* r) {
    return std::string(R"({"type": "clearcoat", "name": "m", "roughness": )") + r + R"(, "base": {"type": "lambertian", "albedo": 0.5}})";
  };
  const LayeredSphere sampled(with("0.3")), claimed(with("0.315"));
  const glm::vec3 n(0, 0, 1), wo = unit(glm::vec3(0.95f, 0.0f, 0.3f));
  const Chi2Result r = layered_chi2(sampled.bsdf(n, wo), claimed.bsdf(n, wo), wo, 5);
  EXPECT_LT(r.pValue, kLevel) << "a 5 % error in the coat's roughness was not detected";
}

// Mean weights of bsdf_sample at wo (red channel) that leave on wo's side
// (x) and through the surface (y), and the standard error of their sum (z).
glm::dvec3 sampled_split(const SceneView::Bsdf& b, glm::vec3 wo, int n, uint32_t seed) {
  ShaderMath m;
  uint32_t state = m.rng_seed(seed, 3u, 4u);
  double back = 0.0, through = 0.0, sumSq = 0.0;
  for (int i = 0; i < n; ++i) {
    const glm::vec4 u(m.rng_next(state), m.rng_next(state), m.rng_next(state), m.rng_next(state));
    glm::vec3 wi;
    float pdf;
    bool isDelta;
    const double w = m.bsdf_sample(b, wo, u, wi, pdf, isDelta).x;
    EXPECT_TRUE(std::isfinite(w));
    (glm::dot(wi, b.ng) < 0.0f ? through : back) += w;
    sumSq += w * w;
  }
  const double mean = (back + through) / n;
  return {back / n, through / n, std::sqrt(std::max(sumSq / n - mean * mean, 0.0) / n)};
}

// Mean and standard error of bsdf_sample's weight (red channel) at wo.
std::pair<double, double> sampled_albedo(const SceneView::Bsdf& b, glm::vec3 wo, int n, uint32_t seed) {
  const glm::dvec3 s = sampled_split(b, wo, n, seed);
  return {s.x + s.y, s.z};
}

glm::vec3 at_cosine(double c) { return glm::vec3(float(std::sqrt(1.0 - c * c)), 0.0f, float(c)); }

// The sheen lobe alone (over a black base) reflects E(cos_o, r), the table
// scripts/make-sheen-table.py computed, up to the table's bilinear error;
// the same comparison against the table one roughness step off fails.
TEST(Layers, SheenLobeReflectsItsAlbedoTable) {
  ShaderMath table;
  struct Case {
    double r, cosO;
  };
  for (Case c : {Case{0.5, 0.3}, Case{0.5, 0.7}, Case{0.25, 0.5}, Case{0.9, 1.0}, Case{0.35, 0.15}}) {
    char material[200];
    std::snprintf(material, sizeof material, R"({"type": "sheen", "name": "m", "color": 1, "roughness": %g, "base": {"type": "lambertian", "albedo": 0}})", c.r);
    const LayeredSphere sphere(material);
    const glm::vec3 wo = at_cosine(c.cosO);
    const auto [mean, se] = sampled_albedo(sphere.bsdf({0, 0, 1}, wo), wo, 400000, 7);
    const double expected = table.sheen_albedo(float(c.cosO), float(c.r));
    EXPECT_NEAR(mean, expected, 4.0 * se + 0.01 * expected) << "r " << c.r << ", cos " << c.cosO;
    const double planted = table.sheen_albedo(float(c.cosO), float(c.r + 1.0 / 31.0));
    EXPECT_GT(std::fabs(mean - planted), 4.0 * se + 0.01 * expected) << "a table one roughness step off passes: r " << c.r << ", cos " << c.cosO;
  }
}

// White furnaces: the layered material over a white Lambertian base keeps
// what the extension's layering says it keeps, and never more than 1.
//   sheen: s E(mu_o) + integral of cos_i / pi (1 - s max(E(mu_o), E(mu_i))),
//   clear coat: 1 - c F_c(mu_o) (1 - E_ggx(mu_o)), F_c Schlick's at N.V.
TEST(Layers, WhiteFurnaceLossMatchesTheLayering) {
  const double sheenRoughness = 0.5;
  LayeredSphere sheen(R"({"type": "sheen", "name": "m", "color": 1, "roughness": 0.5, "base": {"type": "lambertian", "albedo": 1}})");
  auto sheen_expected = [&](double cosO, double r) {
    auto e = [&](double mu) { return std::min(double(sheen.view.sheen_albedo(float(mu), float(r))), 1.0); };
    const double eo = e(cosO);
    double integral = 0.0;
    const int n = 2000;
    for (int i = 0; i < n; ++i) {
      const double mu = (i + 0.5) / n;
      integral += 2.0 * mu * (1.0 - std::max(eo, e(mu))) / n;
    }
    return eo + integral;
  };
  for (double cosO : {1.0, 0.6, 0.2}) {
    const glm::vec3 wo = at_cosine(cosO);
    const auto [mean, se] = sampled_albedo(sheen.bsdf({0, 0, 1}, wo), wo, 400000, 11);
    EXPECT_NEAR(mean, sheen_expected(cosO, sheenRoughness), 4.0 * se + 1e-3) << "sheen at cos " << cosO;
    EXPECT_LT(mean, 1.0 + 4.0 * se) << "sheen at cos " << cosO;
    // Planted: the base scaled by 1 - s E(mu_o) alone (the extension's
    // cheaper variant) keeps everything over a white base, and the furnace
    // tells it from the model where that differs by more than 1 %.
    if (std::fabs(sheen_expected(cosO, sheenRoughness) - 1.0) > 0.01) {
      EXPECT_GT(std::fabs(mean - 1.0), 4.0 * se + 1e-3) << "the E(mu_o)-only scaling passes at cos " << cosO;
    }
  }
  for (double roughness : {0.0, 0.5}) {
    char material[200];
    std::snprintf(material, sizeof material, R"({"type": "clearcoat", "name": "m", "factor": 0.9, "roughness": %g, "base": {"type": "lambertian", "albedo": 1}})",
                  roughness);
    const LayeredSphere coat(material);
    for (double cosO : {1.0, 0.5, 0.15}) {
      const glm::vec3 wo = at_cosine(cosO);
      const auto [mean, se] = sampled_albedo(coat.bsdf({0, 0, 1}, wo), wo, 400000, 13);
      const double fc = 0.04 + 0.96 * std::pow(1.0 - cosO, 5.0);
      const double alpha = std::max(roughness * roughness, double(GGX_MIN_ALPHA));
      const double expected = 1.0 - 0.9 * fc * (1.0 - ggx_albedo(alpha, cosO));
      EXPECT_NEAR(mean, expected, 4.0 * se + 2e-3) << "coat roughness " << roughness << " at cos " << cosO;
      EXPECT_LT(mean, 1.0 + 4.0 * se);
    }
  }
}

// KHR_materials_diffuse_transmission moves light from the diffuse BRDF to
// the BTDF and changes nothing else (README.md:212 at 603619ef). In a white
// furnace, a white base transmitting white keeps the opaque material's
// total at every factor and sends factor times the diffuse base through;
// transmitting black loses that share, which the furnace tells apart.
TEST(Layers, DiffuseTransmissionMovesTheDiffuseBaseThrough) {
  auto material = [](double dt, double colour) {
    char text[240];
    std::snprintf(text, sizeof text, R"({"type": "metal_rough", "name": "m", "base_color": 1, "metallic": 0, "roughness": 0.5,
      "diffuse_transmission": %g, "diffuse_transmission_color": %g})", dt, colour);
    return std::string(text);
  };
  const LayeredSphere opaque(material(0.0, 1.0)), half(material(0.4, 1.0)), through(material(1.0, 1.0)), black(material(1.0, 0.0));
  uint32_t seed = 40;
  for (double cosO : {1.0, 0.5, 0.2}) {
    const glm::vec3 wo = at_cosine(cosO);
    const glm::dvec3 o = sampled_split(opaque.bsdf({0, 0, 1}, wo), wo, 300000, seed++);
    const glm::dvec3 h = sampled_split(half.bsdf({0, 0, 1}, wo), wo, 300000, seed++);
    const glm::dvec3 t = sampled_split(through.bsdf({0, 0, 1}, wo), wo, 300000, seed++);
    const glm::dvec3 k = sampled_split(black.bsdf({0, 0, 1}, wo), wo, 300000, seed++);
    EXPECT_EQ(o.y, 0.0) << "an opaque material transmits nothing";
    // (Not bounded by 1: glTF's base under 1 - max3 F(wo.h) is not energy-conserving at grazing angles.)
    EXPECT_NEAR(h.x + h.y, o.x, 4.0 * (h.z + o.z) + 1e-3) << "factor 0.4 at cos " << cosO;
    EXPECT_NEAR(t.x + t.y, o.x, 4.0 * (t.z + o.z) + 1e-3) << "factor 1 at cos " << cosO;
    EXPECT_NEAR(h.y, 0.4 * t.y, 4.0 * (h.z + t.z) + 1e-3) << "the share through at cos " << cosO;
    EXPECT_GT(t.y, 0.5) << "most of a white base goes through";
    // Black transmission: the specular layer alone, what factor 1 kept on wo's side.
    EXPECT_NEAR(k.x + k.y, t.x, 4.0 * (k.z + t.z) + 1e-3) << "black at cos " << cosO;
    EXPECT_GT(o.x - (k.x + k.y), 4.0 * (o.z + k.z) + 1e-3) << "the furnace cannot tell a lost share at cos " << cosO;
  }
}

// Its lobe against the extension's formula (README.md:200-240), written here
// in double precision: through the surface, (1 - m)(1 - max3 F_d)(1 - t) dt
// dtColor |cos_i| / pi; on wo's side, the opaque material's reflection less
// dt of its diffuse base. F_d is Schlick's at wo.h, h the half vector of wo
// and wi mirrored to wo's side.
TEST(Layers, DiffuseTransmissionEvaluatesTheExtensionsFormula) {
  const double metallic = 0.3, dt = 0.7, roughness = 0.6;
  const glm::dvec3 base(0.5, 0.4, 0.3), colour(0.9, 0.3, 0.2);
  const LayeredSphere translucent(R"({"type": "metal_rough", "name": "m", "base_color": [0.5, 0.4, 0.3], "metallic": 0.3, "roughness": 0.6,
      "diffuse_transmission": 0.7, "diffuse_transmission_color": [0.9, 0.3, 0.2]})");
  const LayeredSphere opaque(R"({"type": "metal_rough", "name": "m", "base_color": [0.5, 0.4, 0.3], "metallic": 0.3, "roughness": 0.6})");
  (void)roughness;
  ShaderMath m;
  int checked = 0;
  for (double cosO : {0.95, 0.6, 0.25})
    for (double cosI : {0.9, 0.5, 0.15})
      for (double phi : {0.0, 2.0}) {
        const glm::vec3 wo = at_cosine(cosO);
        const double sinI = std::sqrt(1.0 - cosI * cosI);
        const glm::dvec3 below(sinI * std::cos(phi), sinI * std::sin(phi), -cosI), mirrored(below.x, below.y, cosI);
        const double c = glm::dot(glm::dvec3(wo), glm::normalize(glm::dvec3(wo) + mirrored));
        const double fd = 0.04 + 0.96 * std::pow(1.0 - c, 5.0);
        const double weight = (1.0 - metallic) * (1.0 - fd) * cosI / M_PI;
        const SceneView::Bsdf b = translucent.bsdf({0, 0, 1}, wo), a = opaque.bsdf({0, 0, 1}, wo);
        const glm::dvec3 through = m.bsdf_eval(b, wo, glm::vec3(below));
        const glm::dvec3 back = m.bsdf_eval(b, wo, glm::vec3(mirrored)), opaqueBack = m.bsdf_eval(a, wo, glm::vec3(mirrored));
        const glm::dvec3 expectedThrough = colour * (weight * dt), expectedBack = opaqueBack - base * (weight * dt);
        for (int ch = 0; ch < 3; ++ch) {
          EXPECT_NEAR(through[ch], expectedThrough[ch], 1e-4 * expectedThrough[ch] + 1e-6) << cosO << " " << cosI << " " << phi;
          EXPECT_NEAR(back[ch], expectedBack[ch], 1e-4 * opaqueBack[ch] + 1e-6) << cosO << " " << cosI << " " << phi;
        }
        ++checked;
      }
  EXPECT_EQ(checked, 18);
}

// A pane lit from behind by a sun along its normal, seen head-on, direct
// light only: it shows the light its diffuse transmission lets through,
// (1 - F0) dt dtColor E / pi with F0 = 0.04, and nothing of its base colour.
TEST(Layers, ABacklitPaneShowsWhatItsDiffuseTransmissionLetsThrough) {
  const double irradiance = 2.0, dt = 0.6;
  const glm::dvec3 colour(0.9, 0.5, 0.1);
  Scene scene = load_scene(write_scene("pane.json", R"({"camera": {"transform": {"from": [0, 0, 5], "at": [0, 0, 0], "up": [0, 1, 0]},
      "vfov": 10, "resolution": [16, 16]}, "background": 0, "sampler": {"samples": 64},
      "integrator": {"type": "path tracer nee", "max bounces": 1},
      "materials": [{"type": "metal_rough", "name": "leaf", "base_color": [0.1, 0.6, 0.1], "metallic": 0, "roughness": 0.5,
                     "diffuse_transmission": 0.6, "diffuse_transmission_color": [0.9, 0.5, 0.1]}],
      "surfaces": [{"type": "quad", "size": 4, "material": "leaf"},
                   {"type": "directional_light", "direction": [0, 0, 1], "irradiance": 2}]})"));
  RenderOptions o;
  const CompiledScene cs = compile_scene(scene, reference_options(o));
  EXPECT_TRUE(cs.params.kinds.w & KIND_BIT(FEATURE_DIFFUSE_TRANSMISSION));
  Progress quiet("", 0, false);
  const ImageStats img = render_cpu(cs, 0, quiet);
  const glm::dvec3 expected = colour * (0.96 * dt * irradiance / M_PI);
  for (size_t i = 0; i < 16 * 16; ++i) {
    const glm::dvec3 got = img.mean(i);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], expected[ch], 2e-3 * expected[ch] + 1e-5) << "pixel " << i << ", channel " << ch;
  }
}

// ---- the extensions' formulas, evaluated here without the shared code ----

double schlick5(double c) { return std::pow(1.0 - std::clamp(c, 0.0, 1.0), 5.0); }

// GGX D and the height-correlated G2 (glTF 2.0 Appendix B).
double ggx_d(double nh, double a) {
  const double t = nh * nh * (a * a - 1.0) + 1.0;
  return nh > 0.0 ? a * a / (M_PI * t * t) : 0.0;
}
double ggx_g2(double no, double ni, double a) {
  auto lambda = [&](double c) { return 0.5 * (std::sqrt(1.0 + a * a * (1.0 - c * c) / (c * c)) - 1.0); };
  return 1.0 / (1.0 + lambda(no) + lambda(ni));
}
double specular_brdf(glm::dvec3 n, glm::dvec3 v, glm::dvec3 l, double a) {
  const glm::dvec3 h = glm::normalize(v + l);
  const double nv = glm::dot(n, v), nl = glm::dot(n, l);
  return ggx_d(glm::dot(n, h), a) * ggx_g2(nv, nl, a) / (4.0 * nv * nl);
}

// KHR_materials_sheen: Charlie D, its Lambda fit (sheen README, "Sheen visibility").
double sheen_brdf(glm::dvec3 n, glm::dvec3 v, glm::dvec3 l, double r) {
  const double a = r * r, nv = glm::dot(n, v), nl = glm::dot(n, l);
  const double nh = glm::dot(n, glm::normalize(v + l));
  const double d = (2.0 + 1.0 / a) * std::pow(std::max(1.0 - nh * nh, 0.0), 0.5 / a) / (2.0 * M_PI);
  auto lfit = [&](double x) {
    const double t = (1.0 - a) * (1.0 - a);
    auto mix = [&](double p, double q) { return p + (q - p) * t; };
    return mix(21.5473, 25.3245) / (1.0 + mix(3.82987, 3.32435) * std::pow(x, mix(0.19823, 0.16801))) + mix(-1.97760, -1.27393) * x +
           mix(-4.32054, -4.85967);
  };
  auto lambda = [&](double c) { return c < 0.5 ? std::exp(lfit(c)) : std::exp(2.0 * lfit(0.5) - lfit(1.0 - c)); };
  return d / ((1.0 + lambda(nv) + lambda(nl)) * 4.0 * nv * nl);
}

// The material of the single-scattering test, by the extensions' formulas:
// metal-rough (metallic m, roughness rb, base colour base) whose dielectric
// Fresnel KHR_materials_specular tints (fresnel_mix), under a sheen
// (albedo scaling with the table's E), under a clear coat (fresnel_coat).
struct Stack {
  glm::dvec3 base{0.2, 0.4, 0.7};
  double metallic = 0.25, roughness = 0.5;
  double specular = 0.8;
  glm::dvec3 specularColor{1.5, 1.0, 0.5};
  glm::dvec3 sheenColor{0.6, 0.5, 0.4};
  double sheenRoughness = 0.6;
  double coat = 0.7, coatRoughness = 0.3;
};

glm::dvec3 stack_brdf(const Stack& s, ShaderMath table, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l) {
  const glm::dvec3 h = glm::normalize(v + l);
  const double w = schlick5(glm::dot(v, h));
  const double a = s.roughness * s.roughness;
  const double spec = specular_brdf(n, v, l, a);
  const glm::dvec3 f0 = glm::min(0.04 * s.specularColor, glm::dvec3(1.0)) * s.specular;
  const glm::dvec3 fr = f0 + (glm::dvec3(s.specular) - f0) * w;
  const double frMax = std::max({fr.x, fr.y, fr.z});
  const glm::dvec3 dielectric = (1.0 - frMax) * s.base / M_PI + fr * spec;
  const glm::dvec3 metal = (s.base + (1.0 - s.base) * w) * spec;
  const glm::dvec3 material = (1.0 - s.metallic) * dielectric + s.metallic * metal;
  const double sheenMax = std::max({s.sheenColor.x, s.sheenColor.y, s.sheenColor.z});
  auto e = [&](double mu) { return std::min(double(table.sheen_albedo(float(mu), float(s.sheenRoughness))), 1.0); };
  const double scaling = std::min(1.0 - sheenMax * e(glm::dot(n, v)), 1.0 - sheenMax * e(glm::dot(n, l)));
  const glm::dvec3 sheened = s.sheenColor * sheen_brdf(n, v, l, s.sheenRoughness) + material * scaling;
  const double fc = 0.04 + 0.96 * schlick5(glm::dot(n, v));
  const double coatA = s.coatRoughness * s.coatRoughness;
  return sheened * (1.0 - s.coat * fc) + glm::dvec3(s.coat * fc * specular_brdf(n, v, l, coatA));
}

std::string stack_json(const Stack& s) {
  char text[1024];
  std::snprintf(text, sizeof text,
                R"({"type": "clearcoat", "name": "m", "factor": %g, "roughness": %g, "base": {"type": "sheen", "color": [%g, %g, %g],
                    "roughness": %g, "base": {"type": "metal_rough", "base_color": [%g, %g, %g], "metallic": %g, "roughness": %g,
                    "specular": %g, "specular_color": [%g, %g, %g]}}})",
                s.coat, s.coatRoughness, s.sheenColor.x, s.sheenColor.y, s.sheenColor.z, s.sheenRoughness, s.base.x, s.base.y, s.base.z,
                s.metallic, s.roughness, s.specular, s.specularColor.x, s.specularColor.y, s.specularColor.z);
  return text;
}

// A sphere under one directional light, seen from far away through a
// narrow field of view, rendered with direct light only: each pixel is
// f(wo, wi) cos(wi) E at the point its centre sees (up to the pixel's
// footprint). The CPU reference's pixels against the formulas above.
TEST(Layers, SingleScatteringMatchesTheExtensionsFormulas) {
  const Stack stack;
  const glm::dvec3 toLight = glm::normalize(glm::dvec3(0.5, 0.6, 0.62));
  const double irradiance = 2.0;
  char light[256];
  std::snprintf(light, sizeof light, R"(, {"type": "directional_light", "direction": [%g, %g, %g], "irradiance": %g})", -toLight.x, -toLight.y,
                -toLight.z, irradiance);
  const LayeredSphere sphere(stack_json(stack), light);
  Scene scene = load_scene(write_scene("layered.json", std::string(R"({"camera": {"transform": {"from": [0, 0, 100], "at": [0, 0, 0],
      "up": [0, 1, 0]}, "vfov": 1.3, "resolution": [64, 64]}, "background": 0, "sampler": {"samples": 64},
      "integrator": {"type": "path tracer nee", "max bounces": 1}, "materials": [)") + stack_json(stack) +
                                                            R"(], "surfaces": [{"type": "sphere", "radius": 1, "material": "m"})" + light + "]}"));
  RenderOptions o;
  const CompiledScene cs = compile_scene(scene, reference_options(o));
  Progress quiet("", 0, false);
  const ImageStats img = render_cpu(cs, 0, quiet);
  const double tanHalf = std::tan(glm::radians(1.3 / 2.0));
  const glm::dvec3 eye(0, 0, 100);
  int checked = 0;
  for (int y = 4; y < 64; y += 5) {
    for (int x = 4; x < 64; x += 5) {
      // The centre's ray and where it meets the sphere.
      const glm::dvec3 d = glm::normalize(glm::dvec3((2.0 * (x + 0.5) / 64 - 1.0) * tanHalf, (1.0 - 2.0 * (y + 0.5) / 64) * tanHalf, -1.0));
      const double b = glm::dot(eye, d), c = glm::dot(eye, eye) - 1.0, disc = b * b - c;
      if (disc <= 0.0) continue;
      const glm::dvec3 p = eye + d * (-b - std::sqrt(disc));
      const glm::dvec3 n = glm::normalize(p), v = -d;
      const double nl = glm::dot(n, toLight);
      if (glm::dot(n, v) < 0.35 || nl < 0.2) continue;  // away from the rim and the terminator
      const glm::dvec3 expected = stack_brdf(stack, sphere.view, n, v, toLight) * nl * irradiance;
      const glm::dvec3 got = img.mean(size_t(y) * 64 + size_t(x));
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(got[ch], expected[ch], 0.03 * expected[ch] + 1e-3) << "pixel " << x << ", " << y << ", channel " << ch;
      ++checked;
    }
  }
  EXPECT_GT(checked, 30);
}

// KHR_materials_iridescence's thin film, written here from the README
// (README.md:257-405 at acfcbe6) in double precision: the film's Airy sum to
// its second order against the eye's sensitivity.
glm::dvec3 film_reflectance(double filmIor, double thickness, glm::dvec3 baseF0, double c) {
  auto schlick = [](double f0, double cos) { return f0 + (1.0 - f0) * std::pow(1.0 - cos, 5.0); };
  double r12 = std::pow((filmIor - 1.0) / (filmIor + 1.0), 2.0);
  r12 = schlick(r12, c);
  const double t121 = 1.0 - r12;
  const double cos2 = std::sqrt(1.0 - (1.0 - c * c) / (filmIor * filmIor));
  const double opd = 2.0 * filmIor * thickness * cos2;
  glm::dvec3 intensity;
  for (int ch = 0; ch < 3; ++ch) {
    const double f0 = std::min(baseF0[ch], 0.9999), baseIor = (1.0 + std::sqrt(f0)) / (1.0 - std::sqrt(f0));
    const double r23 = schlick(std::pow((baseIor - filmIor) / (baseIor + filmIor), 2.0), cos2);
    const double r123 = std::clamp(r12 * r23, 1e-5, 0.9999), rs = t121 * t121 * r23 / (1.0 - r123);
    intensity[ch] = r12 + rs;
  }
  glm::dvec3 cm = glm::dvec3(0.0);
  for (int ch = 0; ch < 3; ++ch) {
    const double f0 = std::min(baseF0[ch], 0.9999), baseIor = (1.0 + std::sqrt(f0)) / (1.0 - std::sqrt(f0));
    const double r23 = schlick(std::pow((baseIor - filmIor) / (baseIor + filmIor), 2.0), cos2);
    const double r123 = std::clamp(r12 * r23, 1e-5, 0.9999);
    cm[ch] = t121 * t121 * r23 / (1.0 - r123) - t121;
  }
  for (int m = 1; m <= 2; ++m) {
    glm::dvec3 shift, xyz;
    for (int ch = 0; ch < 3; ++ch) {
      const double f0 = std::min(baseF0[ch], 0.9999), baseIor = (1.0 + std::sqrt(f0)) / (1.0 - std::sqrt(f0));
      shift[ch] = m * ((filmIor < 1.0 ? 0.0 : M_PI) + (baseIor < filmIor ? M_PI : 0.0));
      const double r23 = schlick(std::pow((baseIor - filmIor) / (baseIor + filmIor), 2.0), cos2);
      cm[ch] *= std::sqrt(std::clamp(r12 * r23, 1e-5, 0.9999));
    }
    const double phase = 2.0 * M_PI * m * opd * 1e-9;
    const double val[3] = {5.4856e-13, 4.4201e-13, 5.2481e-13}, pos[3] = {1.6810e+06, 1.7953e+06, 2.2084e+06},
                 var[3] = {4.3278e+09, 9.3046e+09, 6.6121e+09};
    for (int k = 0; k < 3; ++k)
      xyz[k] = val[k] * std::sqrt(2.0 * M_PI * var[k]) * std::cos(pos[k] * phase + shift[k]) * std::exp(-phase * phase * var[k]);
    xyz.x += 9.7470e-14 * std::sqrt(2.0 * M_PI * 4.5282e+09) * std::cos(2.2399e+06 * phase + shift.x) * std::exp(-4.5282e+09 * phase * phase);
    xyz /= 1.0685e-7;
    const glm::dvec3 rgb = WP_XYZ_TO_LINEAR_SRGB(glm::dvec3, xyz.x, xyz.y, xyz.z);
    intensity += cm * 2.0 * rgb;
  }
  return glm::max(intensity, glm::dvec3(0.0));
}

// The CPU reference's render, 128 x 128 with direct light only, of a unit
// sphere of `material` (named "m") under one sun of `irradiance` from
// toLight, seen from far away through a narrow field of view; `feature` must
// be compiled for it.
ImageStats sphere_under_sun(const char* material, glm::dvec3 toLight, double irradiance, uint32_t feature) {
  char light[256];
  std::snprintf(light, sizeof light, R"(, {"type": "directional_light", "direction": [%g, %g, %g], "irradiance": %g})", -toLight.x, -toLight.y,
                -toLight.z, irradiance);
  Scene scene = load_scene(write_scene("sun.json", std::string(R"({"camera": {"transform": {"from": [0, 0, 100], "at": [0, 0, 0],
      "up": [0, 1, 0]}, "vfov": 1.3, "resolution": [128, 128]}, "background": 0, "sampler": {"samples": 16},
      "integrator": {"type": "path tracer nee", "max bounces": 1}, "materials": [)") + material +
                                                       R"(], "surfaces": [{"type": "sphere", "radius": 1, "material": "m"})" + light + "]}"));
  RenderOptions o;
  const CompiledScene cs = compile_scene(scene, reference_options(o));
  EXPECT_TRUE(cs.params.kinds.w & KIND_BIT(feature));
  Progress quiet("", 0, false);
  return render_cpu(cs, 0, quiet);
}

// A sphere under a thin film (kIridescent, whose texture-free thickness is
// its maximum) lit by one sun, as SingleScatteringMatchesTheExtensionsFormulas
// renders it: metal-rough with both Fresnel terms mixed with the film's.
TEST(Layers, ThinFilmMatchesTheExtensionsFormula) {
  const glm::dvec3 toLight = glm::normalize(glm::dvec3(-0.3, 0.5, 0.8));
  const double irradiance = 3.0, factor = 0.9, filmIor = 1.45, thickness = 450.0, metallic = 0.4, roughness = 0.35;
  const glm::dvec3 base(0.3, 0.3, 0.35);
  const ImageStats img = sphere_under_sun(kIridescent, toLight, irradiance, FEATURE_IRIDESCENCE);
  const double tanHalf = std::tan(glm::radians(1.3 / 2.0));
  const glm::dvec3 eye(0, 0, 100);
  int checked = 0, plantedCaught = 0;
  double largestChannelSpread = 0.0;
  // Pixels half the size of the other test's: the film's colours change
  // faster across the sphere than the layers do.
  for (int y = 8; y < 128; y += 10) {
    for (int x = 8; x < 128; x += 10) {
      const glm::dvec3 d = glm::normalize(glm::dvec3((2.0 * (x + 0.5) / 128 - 1.0) * tanHalf, (1.0 - 2.0 * (y + 0.5) / 128) * tanHalf, -1.0));
      const double b = glm::dot(eye, d), c = glm::dot(eye, eye) - 1.0, disc = b * b - c;
      if (disc <= 0.0) continue;
      const glm::dvec3 p = eye + d * (-b - std::sqrt(disc)), n = glm::normalize(p), v = -d;
      const double nl = glm::dot(n, toLight);
      if (glm::dot(n, v) < 0.35 || nl < 0.2) continue;
      const glm::dvec3 h = glm::normalize(v + toLight);
      const double vh = glm::dot(v, h), w = std::pow(1.0 - vh, 5.0);
      const double spec = specular_brdf(n, v, toLight, roughness * roughness);
      auto radiance = [&](double film) {
        const glm::dvec3 fd = glm::mix(glm::dvec3(0.04 + 0.96 * w), film_reflectance(filmIor, film, glm::dvec3(0.04), vh), factor);
        const glm::dvec3 fm = glm::mix(base + (1.0 - base) * w, film_reflectance(filmIor, film, base, vh), factor);
        const double fdMax = std::max({fd.x, fd.y, fd.z});
        return ((1.0 - metallic) * ((1.0 - fdMax) * base / M_PI + fd * spec) + metallic * fm * spec) * nl * irradiance;
      };
      const glm::dvec3 expected = radiance(thickness), planted = radiance(0.9 * thickness);
      const glm::dvec3 got = img.mean(size_t(y) * 128 + size_t(x));
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(got[ch], expected[ch], 0.03 * expected[ch] + 1e-3) << "pixel " << x << ", " << y << ", channel " << ch;
        if (std::fabs(got[ch] - planted[ch]) > 0.03 * planted[ch] + 1e-3) ++plantedCaught;
      }
      largestChannelSpread = std::max(largestChannelSpread, std::max({expected.x, expected.y, expected.z}) - std::min({expected.x, expected.y, expected.z}));
      ++checked;
    }
  }
  EXPECT_GT(checked, 30);
  EXPECT_GT(largestChannelSpread, 0.02) << "the film colours nothing: the test would not see it";
  EXPECT_GT(plantedCaught, 10) << "a film 10 % thinner than the material's passes";
}

// A brushed sphere (kBrushed: anisotropy 0.8 at 0.5 rad from the tangent,
// which on a sphere runs along the parallels) under a sun, against
// anisotropic GGX written here (README.md:90-105 at acfcbe6; Heitz 2014's
// Lambda): alpha_t = mix(alpha, 1, strength^2) along the direction, alpha
// across it. The isotropic formula fails the same pixels.
TEST(Layers, AnisotropyMatchesTheExtensionsFormula) {
  const glm::dvec3 toLight = glm::normalize(glm::dvec3(0.4, 0.7, 0.6));
  const double irradiance = 3.0, metallic = 0.8, alpha = 0.3 * 0.3, at = alpha + (1.0 - alpha) * 0.64, rotation = 0.5;
  const glm::dvec3 base(0.9, 0.8, 0.6);
  const ImageStats img = sphere_under_sun(kBrushed, toLight, irradiance, FEATURE_ANISOTROPY);
  const double tanHalf = std::tan(glm::radians(1.3 / 2.0));
  const glm::dvec3 eye(0, 0, 100);
  int checked = 0, isotropicCaught = 0;
  // The pixel's mean over its area (the highlight is narrow enough that
  // its value at the centre is not the mean): 6 x 6 points in the pixel.
  auto pixel_mean = [&](int x, int y, double ax, double ay, bool& inside) {
    glm::dvec3 sum(0.0);
    inside = true;
    for (int j = 0; j < 6; ++j) {
      for (int i = 0; i < 6; ++i) {
        const glm::dvec3 d = glm::normalize(
            glm::dvec3((2.0 * (x + (i + 0.5) / 6.0) / 128 - 1.0) * tanHalf, (1.0 - 2.0 * (y + (j + 0.5) / 6.0) / 128) * tanHalf, -1.0));
        const double b = glm::dot(eye, d), c = glm::dot(eye, eye) - 1.0, disc = b * b - c;
        if (disc <= 0.0) {
          inside = false;
          return sum;
        }
        const glm::dvec3 p = eye + d * (-b - std::sqrt(disc)), n = glm::normalize(p), v = -d, l = toLight;
        const double nl = glm::dot(n, l), nv = glm::dot(n, v);
        if (nv < 0.35 || nl < 0.2) inside = false;  // away from the rim and the terminator
        // The sphere's tangent along its parallels, turned by the rotation.
        const glm::dvec3 t0 = glm::normalize(glm::dvec3(p.z, 0.0, -p.x)), b0 = glm::cross(n, t0);
        const glm::dvec3 t = std::cos(rotation) * t0 + std::sin(rotation) * b0, bt = glm::cross(n, t);
        auto local = [&](glm::dvec3 w) { return glm::dvec3(glm::dot(w, t), glm::dot(w, bt), glm::dot(w, n)); };
        auto lambda = [&](glm::dvec3 w) { return 0.5 * (std::sqrt(1.0 + (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / (w.z * w.z)) - 1.0); };
        const glm::dvec3 h = local(glm::normalize(v + l));
        const double q = (h.x / ax) * (h.x / ax) + (h.y / ay) * (h.y / ay) + h.z * h.z;
        const double spec = 1.0 / (M_PI * ax * ay * q * q) / (1.0 + lambda(local(v)) + lambda(local(l))) / (4.0 * nv * nl);
        const double w = std::pow(1.0 - glm::dot(v, glm::normalize(v + l)), 5.0);
        const double fd = 0.04 + 0.96 * w;
        const glm::dvec3 fm = base + (1.0 - base) * w;
        sum += ((1.0 - metallic) * ((1.0 - fd) * base / M_PI + fd * spec) + metallic * fm * spec) * nl * irradiance / 36.0;
      }
    }
    return sum;
  };
  for (int y = 8; y < 128; y += 10) {
    for (int x = 8; x < 128; x += 10) {
      bool inside;
      const glm::dvec3 expected = pixel_mean(x, y, at, alpha, inside), isotropic = pixel_mean(x, y, alpha, alpha, inside);
      if (!inside) continue;
      // Within 4 standard errors of the pixel's samples (the highlight
      // varies across a pixel) and 2 %.
      const size_t pixel = size_t(y) * 128 + size_t(x);
      const glm::dvec3 got = img.mean(pixel), se = glm::sqrt(img.variance(pixel) / std::max(img.count[pixel], 1.0));
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(got[ch], expected[ch], 4.0 * se[ch] + 0.02 * expected[ch] + 1e-3) << "pixel " << x << ", " << y << ", channel " << ch;
        if (std::fabs(got[ch] - isotropic[ch]) > 4.0 * se[ch] + 0.02 * isotropic[ch] + 1e-3) ++isotropicCaught;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 30);
  EXPECT_GT(isotropicCaught, 10) << "the isotropic lobe passes: the test would not see the anisotropy";
}

// A smooth glass sphere of KHR_materials_volume (ior 1.5, attenuation colour
// 0.5 after 1 unit) seen through its centre against a white background: at
// normal incidence the camera sees the front's reflection f0, the light
// that crosses (1 - f0)^2 a (a = e^(-2 sigma R), the two passes' Beer-Lambert
// factor of the diameter), and the internal reflections' geometric series:
// R = f0 + (1 - f0)^2 f0 a^2 / (1 - f0^2 a^2), T = (1 - f0)^2 a / (1 - f0^2 a^2).
TEST(Layers, VolumeAbsorbsAsBeerLambertSays) {
  for (double color : {0.5, 0.9}) {
    char material[300];
    std::snprintf(material, sizeof material,
                  R"({"type": "metal_rough", "name": "m", "base_color": 1, "metallic": 0, "roughness": 0, "transmission": 1,
                      "volume": {"attenuation_color": [%g, %g, %g], "attenuation_distance": 1}})",
                  color, color, color);
    const std::string scene = write_scene("glass.json", std::string(R"({"camera": {"transform": {"from": [0, 0, 100], "at": [0, 0, 0],
        "up": [0, 1, 0]}, "vfov": 0.02, "resolution": [2, 2]}, "background": 1, "sampler": {"samples": 4096},
        "integrator": {"type": "path tracer mis", "max bounces": 12}, "materials": [)") + material +
                                                                 R"(], "surfaces": [{"type": "sphere", "radius": 1, "material": "m"}]})");
    const ImageStats img = render_reference(scene, RenderOptions{});
    const double f0 = 0.04, a = std::exp(2.0 * std::log(color)), k = 1.0 / (1.0 - f0 * f0 * a * a);
    const double expected = f0 + (1 - f0) * (1 - f0) * f0 * a * a * k + (1 - f0) * (1 - f0) * a * k;
    auto [mean, se] = image_mean(img);
    EXPECT_NEAR(mean, expected, 4.0 * se + 0.005 * expected) << "attenuation colour " << color;
    // Planted: the same glass without its absorption is far off.
    const double clear = f0 + (1 - f0) * (1 - f0) * f0 * k + (1 - f0) * (1 - f0) * k;
    EXPECT_GT(std::fabs(mean - clear), 4.0 * se + 0.005 * expected);
  }
}

// Layers are read from darts files and refused where they would overflow
// the BSDF or nest too deep.
TEST(Layers, DartsFilesNameTheirProblems) {
  const std::string lambert = R"({"type": "lambertian", "albedo": 0.5})";
  auto scene = [&](const std::string& material) {
    return R"({"camera": {"resolution": [4, 4]}, "materials": [)" + material + R"(], "surfaces": [{"type": "sphere", "material": "m"}]})";
  };
  expect_error(scene(R"({"type": "sheen", "name": "m", "roughness": 2, "base": )" + lambert + "}"), {"/materials/0/roughness", "[0, 1]"});
  expect_error(scene(R"({"type": "clearcoat", "name": "m", "facter": 1, "base": )" + lambert + "}"), {"/materials/0", "facter", "factor"});
  expect_error(scene(R"({"type": "sheen", "name": "m", "base": {"type": "sheen", "base": )" + lambert + "}}"), {"at most one sheen"});
  expect_error(scene(R"({"type": "clearcoat", "name": "m", "base": {"type": "clearcoat", "base": {"type": "clearcoat", "base": )" + lambert + "}}}"),
               {"at most 2 deep"});
  expect_error(scene(R"({"type": "clearcoat", "name": "m", "base": {"type": "diffuse_light", "emit": 1}})"), {"diffuse_light"});
  expect_error(scene(R"({"type": "clearcoat", "name": "m", "base": {"type": "metal_rough", "emit": 1}})"), {"give \"emit\" to the layer"});
  expect_error(scene(R"({"type": "metal_rough", "name": "m", "specular": 1.5})"), {"/materials/0/specular", "[0, 1]"});
  // As glTF's attenuationColor: [0, 1], where 0 absorbs everything.
  expect_error(scene(R"({"type": "metal_rough", "name": "m", "volume": {"attenuation_color": [1.5, 1, 1]}})"),
               {"/materials/0/volume/attenuation_color", "[0, 1]"});
  expect_error(scene(R"({"type": "metal_rough", "name": "m", "volume": {"attenuation_distance": 0}})"), {"/materials/0/volume/attenuation_distance"});
  expect_error(scene(R"({"type": "metal_rough", "name": "m", "iridescence": {"ior": 0.5}})"), {"/materials/0/iridescence/ior", "[1, 10]"});
  expect_error(scene(R"({"type": "metal_rough", "name": "m", "anisotropy": {"strength": 2}})"), {"/materials/0/anisotropy/strength", "[0, 1]"});
  expect_error(scene(R"({"type": "metal_rough", "name": "m", "iridescence": {"thickness": 300}})"), {"/materials/0/iridescence", "thickness"});
  expect_error(scene(R"({"type": "metal_rough", "name": "m", "transmission": 1, "volume": {"dispersion": -1}})"),
               {"/materials/0/volume/dispersion", "[0, 1000]"});
}

// KHR_materials_dispersion's channel indices against the extension's own
// law (README.md:70): n(l) = n_d + (n_d - 1) / V_d (523655 / l^2 - 1.5168)
// with V_d = 20 / dispersion. Green is n_d (n at l_d), red and blue half
// the spread n(l_F) - n(l_C) below and above it, red no lower than the
// least index metal-rough refracts with.
TEST(Layers, DispersionIndicesFollowTheExtensionsCauchyLaw) {
  ShaderMath m;
  for (double ior : {1.33, 1.5, 1.7, 2.42})
    for (double d : {0.25, 1.0, 3.0}) {
      SCOPED_TRACE(testing::Message() << "ior " << ior << ", dispersion " << d);
      auto cauchy = [&](double lambda) { return ior + (ior - 1.0) * d / 20.0 * (523655.0 / (lambda * lambda) - 1.5168); };
      const double red = m.dispersed_ior(float(ior), float(d), 1u), green = m.dispersed_ior(float(ior), float(d), 2u),
                   blue = m.dispersed_ior(float(ior), float(d), 3u);
      EXPECT_NEAR(cauchy(587.56), ior, 1e-4);
      EXPECT_FLOAT_EQ(float(green), float(ior));
      EXPECT_NEAR(blue - red, cauchy(486.13) - cauchy(656.27), 3e-4 * (blue - red));
      EXPECT_NEAR(green - red, blue - green, 1e-6);
    }
  EXPECT_FLOAT_EQ(m.dispersed_ior(1.01f, 100.0f, 1u), METAL_ROUGH_MIN_IOR);
}

}  // namespace
}  // namespace wp::test
