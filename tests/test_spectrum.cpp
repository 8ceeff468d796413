// The spectral mode's wavelengths (shaders/shared/spectrum.glsl): the
// visible-wavelength sampler against its density (chi-square, and a planted
// density 4 % narrower caught), the density's normalization, and the colour
// matching functions' fit against the CIE 1931 observer's integrals and
// chromaticities; D65's table; the RGB uplift's round trip.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "render/rgb_to_spectrum.h"
#include "render/spectra.h"
#include "stats/compare.h"
#include "test_support.h"

namespace wp::test {
namespace {

using namespace shader;

// The integral of f over [360, 830] nm by the midpoint rule.
template <class F>
double integral(F f, int steps = 47000) {
  const double a = SPECTRUM_MIN_NM, b = SPECTRUM_MAX_NM, h = (b - a) / steps;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) sum += f(a + (i + 0.5) * h);
  return sum * h;
}

// Chi-square of n wavelengths drawn by sample_visible_wavelength against
// `pdf`, in 94 bins of 5 nm.
Chi2Result wavelength_chi2(double (*pdf)(double), int n, uint32_t seed) {
  ShaderMath m;
  uint32_t state = m.rng_seed(seed, 1u, 2u);
  const int bins = 94;
  const double width = (SPECTRUM_MAX_NM - SPECTRUM_MIN_NM) / bins;
  std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
  for (int i = 0; i < n; ++i) {
    const float lambda = m.sample_visible_wavelength(m.rng_next(state));
    EXPECT_TRUE(lambda >= SPECTRUM_MIN_NM && lambda <= SPECTRUM_MAX_NM) << lambda;
    observed[std::min(bins - 1, std::max(0, int((lambda - SPECTRUM_MIN_NM) / width)))] += 1.0;
  }
  for (int b = 0; b < bins; ++b) {
    const double lo = SPECTRUM_MIN_NM + b * width;
    double p = 0.0;
    for (int k = 0; k < 50; ++k) p += pdf(lo + (k + 0.5) * width / 50) * width / 50;
    expected[b] = p * n;
  }
  return chi2_test(observed, expected, n);
}

double shared_pdf(double lambda) { return ShaderMath().visible_wavelength_pdf(float(lambda)); }
double narrower_pdf(double lambda) {  // the shape 4 % narrower, normalized again
  static const double norm = integral([](double l) { return 1.0 / std::pow(std::cosh(0.0072 * 1.04 * (l - 538.0)), 2.0); });
  return 1.0 / std::pow(std::cosh(0.0072 * 1.04 * (lambda - 538.0)), 2.0) / norm;
}

TEST(Spectrum, VisibleWavelengthsSampleTheirDensity) {
  EXPECT_NEAR(integral(shared_pdf), 1.0, 1e-4) << "the density integrates to 1 over the visible range";
  EXPECT_EQ(ShaderMath().visible_wavelength_pdf(359.0f), 0.0f);
  EXPECT_EQ(ShaderMath().visible_wavelength_pdf(831.0f), 0.0f);
  const Chi2Result fit = wavelength_chi2(shared_pdf, 1000000, 3);
  EXPECT_TRUE(fit.problem.empty()) << fit.problem;
  EXPECT_GT(fit.pValue, 0.01) << "chi2 = " << fit.statistic << " with " << fit.dof << " dof";
  const Chi2Result planted = wavelength_chi2(narrower_pdf, 1000000, 4);
  EXPECT_LT(planted.pValue, 0.01) << "a density 4 % narrower passes";
}

// The fit of the colour matching functions: y bar's integral is the CIE's
// 106.857 nm (to 1 %), the equal-energy spectrum's chromaticity is (1/3,
// 1/3) (to 0.01), and the matrix takes D65's XYZ to sRGB's white. A
// sampled estimate of y bar's integral, by the wavelength sampler's
// density, converges to the same number.
TEST(Spectrum, ColourMatchingFunctionsMatchTheCieObserver) {
  ShaderMath m;
  const double x = integral([&](double l) { return double(m.cie_xyz_bar(float(l)).x); });
  const double y = integral([&](double l) { return double(m.cie_xyz_bar(float(l)).y); });
  const double z = integral([&](double l) { return double(m.cie_xyz_bar(float(l)).z); });
  EXPECT_NEAR(y / CIE_Y_INTEGRAL, 1.0, 0.01);
  EXPECT_NEAR(x / (x + y + z), 1.0 / 3.0, 0.01);
  EXPECT_NEAR(y / (x + y + z), 1.0 / 3.0, 0.01);
  EXPECT_NEAR(m.cie_xyz_bar(555.0f).y, 1.0f, 0.01f) << "y bar peaks at 1 near 555 nm";
  const glm::vec3 white = m.xyz_to_linear_srgb(glm::vec3(0.95047f, 1.0f, 1.08883f));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(white[c], 1.0f, 1e-3f) << "channel " << c;
  uint32_t state = m.rng_seed(9u, 1u, 2u);
  const int n = 400000;
  double sum = 0.0, sumSq = 0.0;
  for (int i = 0; i < n; ++i) {
    const float lambda = m.sample_visible_wavelength(m.rng_next(state));
    const double v = m.cie_xyz_bar(lambda).y / m.visible_wavelength_pdf(lambda);
    sum += v;
    sumSq += v * v;
  }
  const double mean = sum / n, se = std::sqrt((sumSq / n - mean * mean) / n);
  EXPECT_NEAR(mean, y, 4.0 * se) << "importance-sampled y bar";
}

// D65's table: 100 at 560 nm, and its white point: the chromaticity of the
// CIE's tables (0.3127, 0.3290) within what the matching functions' fit
// allows (its equal-energy point lies 0.002 off 1/3, above).
TEST(Spectrum, D65IsTheCiesDaylight) {
  ShaderMath m;
  EXPECT_FLOAT_EQ(m.cie_d65(560.0f), 100.0f);
  EXPECT_FLOAT_EQ(m.cie_d65(362.5f), 0.5f * (46.6383f + 49.3637f));
  EXPECT_EQ(m.cie_d65(355.0f), 0.0f);
  glm::dvec3 xyz(0.0);
  for (int i = 0; i < 4700; ++i) {
    const float lambda = SPECTRUM_MIN_NM + 0.1f * (float(i) + 0.5f);
    xyz += double(m.cie_d65(lambda)) * glm::dvec3(m.cie_xyz_bar(lambda));
  }
  const double sum = xyz.x + xyz.y + xyz.z;
  EXPECT_NEAR(xyz.x / sum, 0.3127, 0.003);
  EXPECT_NEAR(xyz.y / sum, 0.3290, 0.003);
}

// The uplift's round trip: a reflectance's spectrum, integrated under D65
// by the film's matching functions, gives the reflectance back. Over random
// colours (a third with one channel 0, the gamut's edge), the error relative
// to the largest component (or to 0.05 for darker colours): median 3e-4,
// 99 % of colours within 0.31 %, the worst 11 % (a dark, saturated green,
// 0.006 absolute; the sigmoid's quadratic is bounded). Greys are exact (a
// constant spectrum); every spectrum lies within [0, 1]. A table whose
// coefficients are those of the next brighter grid colour is caught.
std::vector<double> uplift_errors(const glm::vec4* spectra, bool checkRange) {
  SceneView v;
  v.spectrumTexels = spectra;
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<double> errors;
  for (int trial = 0; trial < 3000; ++trial) {
    glm::vec3 rgb(u(rng), u(rng), u(rng));
    if (trial % 3 == 0) rgb[trial % 4 == 0 ? 0 : 2] = 0.0f;
    const glm::vec3 c = v.rgb_to_spectrum_coefficients(rgb);
    const double largest = std::max({rgb.x, rgb.y, rgb.z});
    errors.push_back(glm::length(spectrum_to_rgb(c) - glm::dvec3(rgb)) / std::max(largest, 0.05));
    for (float lambda = SPECTRUM_MIN_NM; checkRange && lambda <= SPECTRUM_MAX_NM; lambda += 10.0f) {
      const float s = v.sigmoid_polynomial(c, lambda);
      EXPECT_TRUE(s >= 0.0f && s <= 1.0f) << s;
    }
  }
  std::sort(errors.begin(), errors.end());
  return errors;
}

// The table the build linked in, looked up as the kernels look it up.
TEST(Spectrum, UpliftedReflectancesKeepTheirColour) {
  const SpectraTexels spectra = spectra_texels();
  const std::vector<double> errors = uplift_errors(spectra.texels, true);
  EXPECT_LT(errors[errors.size() / 2], 1e-3);
  EXPECT_LT(errors[errors.size() * 99 / 100], 5e-3);
  EXPECT_LT(errors.back(), 0.15);
  SceneView v;
  v.spectrumTexels = spectra.texels;
  for (float g : {0.0f, 0.18f, 0.5f, 1.0f}) {
    const glm::dvec3 back = spectrum_to_rgb(v.rgb_to_spectrum_coefficients(glm::vec3(g)));
    EXPECT_NEAR(back.x, g, 1e-5);
    EXPECT_NEAR(back.y, g, 1e-5);
    EXPECT_NEAR(back.z, g, 1e-5);
  }
  std::vector<glm::vec4> shifted(spectra.texels, spectra.texels + spectra.count);
  const int res = RGB_TO_SPECTRUM_RES;
  const size_t slice = size_t(res) * size_t(res);
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k + 1 < res; ++k)
      std::copy_n(&spectra.texels[SPECTRA_RGB_COEFFICIENTS + size_t(l * res + k + 1) * slice], slice,
                  &shifted[SPECTRA_RGB_COEFFICIENTS + size_t(l * res + k) * slice]);
  EXPECT_GT(uplift_errors(shifted.data(), false)[errors.size() * 99 / 100], 5e-3) << "a planted shift of the table";
}

// ---- The spectral mode (spectral.glsl) ----------------------------------------

// A SceneView that reads the tables the build linked in, outside any scene.
SceneView spectral_view() {
  SceneView v;
  v.spectrumTexels = spectra_texels().texels;
  v.scene.kinds.w = KIND_BIT(FEATURE_SPECTRAL) | KIND_BIT(FEATURE_SPECTRAL_TABLE) | KIND_BIT(FEATURE_SPECTRAL_UNBOUNDED_TABLE);
  v.scene.counts.w = SCENE_FLAG_SPECTRAL;
  v.spectrumChannels = 4u;
  return v;
}

// The film's sRGB of light `spectrum` (a function of the path's wavelengths),
// averaged over n stratified wavelength samples: what a pixel converges to.
template <class F>
glm::dvec3 film_rgb(SceneView& v, F spectrum, int n = 20000) {
  glm::dvec3 sum(0.0);
  for (int i = 0; i < n; ++i) {
    const float u = (float(i) + 0.5f) / float(n);
    sum += glm::dvec3(v.spectral_sample_rgb(spectrum(v.path_wavelengths(u)), u));
  }
  return sum / double(n);
}

// White light renders white, and a reflectance under it its own colour,
// within the uplift's round trip (99 % of colours within 0.31 %): the film's
// matching functions, white balance and D65 against the table's fit. Light
// of equal energy at every wavelength instead of D65 (a planted error) is
// caught: it renders 9 % bluer than white.
TEST(Spectral, TheFilmRendersWhiteLightWhiteAndColoursAsTheyAre) {
  SceneView v = spectral_view();
  auto d65 = [&](glm::vec4 l) { return glm::vec4(v.illuminant_d65(l.x), v.illuminant_d65(l.y), v.illuminant_d65(l.z), v.illuminant_d65(l.w)); };
  const glm::dvec3 white = film_rgb(v, [&](glm::vec4 l) { return v.light_spectrum(glm::vec3(1.0f), l); });
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(white[c], 1.0, 2e-3) << "channel " << c;
  const glm::dvec3 flat = film_rgb(v, [&](glm::vec4 l) { return glm::vec4(1.0f) / d65(l); });
  EXPECT_GT(glm::length(flat / flat.y - glm::dvec3(1.0)), 0.05) << "a planted equal-energy white";
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int trial = 0; trial < 24; ++trial) {
    const glm::vec3 rgb(u(rng), u(rng), u(rng));
    const glm::dvec3 got = film_rgb(v, [&](glm::vec4 l) { return v.reflectance_spectrum(rgb, l) * v.light_spectrum(glm::vec3(1.0f), l); });
    const double largest = std::max({rgb.x, rgb.y, rgb.z});
    EXPECT_LT(glm::length(got - glm::dvec3(rgb)), 0.01 * largest + 2e-3) << rgb.x << " " << rgb.y << " " << rgb.z;
    // Emitted colours (unbounded) too, at any brightness.
    const glm::dvec3 lit = film_rgb(v, [&](glm::vec4 l) { return v.light_spectrum(rgb * 7.0f, l); });
    EXPECT_LT(glm::length(lit / 7.0 - glm::dvec3(rgb)), 0.01 * largest + 2e-3) << rgb.x << " " << rgb.y << " " << rgb.z;
  }
}

// The memo of a scene's constant colours (compile_spectral_colours): the
// Cornell box computes no colour, so its kernels have no table, and every
// constant colour of it (its walls' reflectances, its light's radiance) is
// in the memo, each kind, with the coefficients the table gives it; a
// colour it does not hold fails the CPU reference's render. A scene that
// blends colours keeps the table for reflectances, one with a point light
// for radiances. A memo fitted without regard to the kind (a planted
// error) is caught.
TEST(Spectral, ConstantColoursAreMemoisedWithTheTablesCoefficients) {
  RenderOptions o;
  o.spectral = true;
  CompiledScene cs = compile_scene(load_scene(source_path("scenes/cornell-box.json")), o);
  ASSERT_GT(cs.params.media.y, 0u);
  ASSERT_EQ(cs.params.kinds.w & KIND_BIT(FEATURE_SPECTRAL_TABLE), 0u);
  SceneView v = cs.view();
  SceneView table = cs.view();
  table.scene.kinds.w |= KIND_BIT(FEATURE_SPECTRAL_TABLE);
  int found = 0;
  for (const Texture& t : cs.textures) {
    if ((t.info.x & TEX_TYPE_MASK) != TEX_CONSTANT) continue;
    const glm::vec3 rgb(t.color0);
    if (rgb.x == rgb.y && rgb.y == rgb.z) continue;
    for (uint32_t kind : {SPECTRAL_COLOUR_REFLECTANCE, SPECTRAL_COLOUR_UNBOUNDED}) {
      glm::vec3 c(0.0f);
      ASSERT_TRUE(v.spectral_colour_memo(rgb, kind, c)) << rgb.x << " " << rgb.y << " " << rgb.z << " kind " << kind;
      float scale = 0.0f;
      EXPECT_EQ(c, table.colour_coefficients(rgb, kind, scale));
      ++found;
    }
  }
  EXPECT_GE(found, 8) << "the walls' three colours and the light's, each kind";
  const glm::vec4 lambdas(450.0f, 550.0f, 650.0f, 500.0f);
  EXPECT_THROW(v.reflectance_spectrum(glm::vec3(0.3f, 0.2f, 0.1f), lambdas), RenderError);
  EXPECT_EQ(v.reflectance_spectrum(glm::vec3(0.4f), lambdas), glm::vec4(0.4f)) << "a grey needs no coefficients";

  const std::string blended = write_scene("spectral-blend.json", R"({
    "camera": { "transform": { "from": [0, 0, 4], "at": [0, 0, 0], "up": [0, 1, 0] }, "vfov": 40, "resolution": [8, 8] },
    "materials": [
      { "type": "blend", "name": "mix", "amount": 0.3, "a": { "type": "lambertian", "albedo": [0.8, 0.1, 0.1] },
        "b": { "type": "lambertian", "albedo": [0.1, 0.1, 0.8] } }
    ],
    "surfaces": [ { "type": "sphere", "radius": 1, "material": "mix" } ]
  })");
  const CompiledScene withTable = compile_scene(load_scene(blended), o);
  EXPECT_NE(withTable.params.kinds.w & KIND_BIT(FEATURE_SPECTRAL_TABLE), 0u);
  EXPECT_EQ(withTable.params.kinds.w & KIND_BIT(FEATURE_SPECTRAL_UNBOUNDED_TABLE), 0u) << "its light is constant";
  EXPECT_EQ(withTable.spectra.count, size_t(SPECTRA_TEXELS));
  const std::string pointLit = write_scene("spectral-point.json", R"({
    "camera": { "transform": { "from": [0, 0, 4], "at": [0, 0, 0], "up": [0, 1, 0] }, "vfov": 40, "resolution": [8, 8] },
    "materials": [ { "type": "lambertian", "name": "red", "albedo": [0.8, 0.1, 0.1] } ],
    "surfaces": [ { "type": "sphere", "radius": 1, "material": "red" },
                  { "type": "point_light", "position": [0, 3, 3], "intensity": [4, 3, 2] } ]
  })");
  const CompiledScene lightTable = compile_scene(load_scene(pointLit), o);
  EXPECT_EQ(lightTable.params.kinds.w & KIND_BIT(FEATURE_SPECTRAL_TABLE), 0u) << "its reflectance is constant";
  EXPECT_NE(lightTable.params.kinds.w & KIND_BIT(FEATURE_SPECTRAL_UNBOUNDED_TABLE), 0u) << "a point light falls off";

  // Every entry fitted as a reflectance, whatever its kind: the light's
  // radiance would be uplifted as the reflectance of its colour.
  std::vector<glm::vec4> planted = cs.spectralColours;
  for (size_t i = 0; i < planted.size(); i += 2) {
    if (planted[i].w < 0.0f) continue;
    float scale = 0.0f;
    planted[i + 1] = glm::vec4(table.colour_coefficients(glm::vec3(planted[i]), SPECTRAL_COLOUR_REFLECTANCE, scale), 0.0f);
  }
  v.spectralColourTexels = planted.data();
  const glm::vec3 light(17.0f, 12.0f, 4.0f);
  EXPECT_GT(glm::length(v.unbounded_spectrum(light, lambdas) - table.unbounded_spectrum(light, lambdas)), 0.1f)
      << "a memo that confuses the kinds";
}

// A path carries four wavelengths: the hero and the sample rotated by a
// quarter, a half and three quarters, each through the density's inverse
// CDF. Each is a channel of the path's colours, and the film counts all four
// (light in one channel alone reaches the pixel, and the four channels' images
// add up to the whole's); a dispersive boundary keeps the hero alone at four
// times its weight, where RGB keeps one of three channels at three times.
// A film that left out the fourth channel (a planted error) is caught.
TEST(Spectral, APathCarriesFourWavelengthsAndTheFilmCountsEach) {
  SceneView v = spectral_view();
  ASSERT_EQ(v.spectrumChannels, 4u);
  for (float u : {0.0f, 0.1f, 0.37f, 0.5f, 0.8f, 0.99f}) {
    const glm::vec4 l = v.path_wavelengths(u);
    for (int k = 0; k < 4; ++k) {
      float rotated = u + 0.25f * float(k);
      rotated -= std::floor(rotated);
      EXPECT_EQ(l[k], v.sample_visible_wavelength(rotated)) << "u " << u << ", wavelength " << k;
    }
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < k; ++j) EXPECT_NE(l[k], l[j]);
  }
  // (Samples whose four wavelengths all lie where the eye sees them.)
  for (float u : {0.11f, 0.13f, 0.15f, 0.17f}) {
    const glm::vec4 radiance(0.3f, 0.5f, 0.7f, 0.9f);
    glm::vec3 parts(0.0f);
    for (int k = 0; k < 4; ++k) {
      glm::vec4 one(0.0f);
      one[k] = radiance[k];
      const glm::vec3 rgb = v.spectral_sample_rgb(one, u);
      EXPECT_GT(glm::length(rgb), 1e-3f) << "channel " << k << " at u " << u;
      parts += rgb;
    }
    const glm::vec3 whole = v.spectral_sample_rgb(radiance, u);
    EXPECT_LT(glm::length(parts - whole), 1e-5f * glm::length(whole));
    glm::vec4 planted = radiance;
    planted.w = 0.0f;
    EXPECT_GT(glm::length(v.spectral_sample_rgb(planted, u) - whole), 1e-3f) << "a film without the fourth wavelength";
  }
  EXPECT_EQ(v.spectrum_keep_channel(glm::vec4(0.5f), 1u), glm::vec4(2.0f, 0.0f, 0.0f, 0.0f));
  ShaderMath rgb;
  ASSERT_EQ(rgb.spectrumChannels, 3u);
  EXPECT_EQ(glm::vec3(rgb.spectrum_keep_channel(glm::vec4(0.5f), 2u)), glm::vec3(0.0f, 1.5f, 0.0f));
  EXPECT_EQ(rgb.spectrum_max(glm::vec4(0.1f, 0.2f, 0.3f, 9.0f)), 0.3f) << "RGB has no fourth channel";
  EXPECT_EQ(v.spectrum_max(glm::vec4(0.1f, 0.2f, 0.3f, 9.0f)), 9.0f);
}

// The film's table of weights (film_weight) against the exact weight it is
// made of, the matching functions times D65 over the density at the
// sample's wavelength: within 0.2 % of the largest weight everywhere between
// its samples (D65's table bends at its 5 nm samples: 0.1 % there), the
// mean within 1e-6; a table read one sample off (a planted error) is caught.
TEST(Spectral, TheFilmsTableOfWeightsFollowsTheExactWeights) {
  SceneView v = spectral_view();
  float largest = 0.0f, worst = 0.0f, plantedWorst = 0.0f;
  double meanTable = 0.0, meanExact = 0.0;
  std::vector<glm::vec4> planted(spectra_texels().texels, spectra_texels().texels + spectra_texels().count);
  for (int k = FILM_WEIGHT_SEGMENTS; k > 0; --k) planted[size_t(SPECTRA_FILM_WEIGHTS + k)] = planted[size_t(SPECTRA_FILM_WEIGHTS + k - 1)];
  SceneView shifted = v;
  shifted.spectrumTexels = planted.data();
  for (int i = 0; i <= 100000; ++i) {
    const float u = float(i) / 100000.0f;
    const glm::vec3 exact = v.film_weight_exact(u);
    ASSERT_TRUE(std::isfinite(exact.x) && std::isfinite(exact.y) && std::isfinite(exact.z)) << u;
    largest = std::max({largest, exact.x, exact.y, exact.z});
    worst = std::max(worst, glm::length(v.film_weight(u) - exact));
    meanTable += double(v.film_weight(u).y);
    meanExact += double(exact.y);
    plantedWorst = std::max(plantedWorst, glm::length(shifted.film_weight(u) - exact));
  }
  EXPECT_LT(worst, 2e-3f * largest);
  EXPECT_NEAR(meanTable / meanExact, 1.0, 1e-6);
  EXPECT_GT(plantedWorst, 5e-3f * largest) << "a table one sample off";
}

// Gold at normal incidence, through the kernels' conductor code at four
// wavelengths, against R = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2) computed in
// double precision from Johnson and Christy's points (metal_spectra.glsl's
// source; the generator's raw data, interpolated linearly). The fourth
// channel, at the first's wavelength, reflects as the first.
TEST(Spectral, GoldAtNormalIncidenceReflectsAsMeasured) {
  SceneView v = spectral_view();
  const glm::vec4 lambdas(450.0f, 550.0f, 650.0f, 450.0f);
  auto reflectance = [&](uint32_t metal) {
    glm::vec4 eta, kappa;
    v.conductor_at_wavelengths(glm::vec3(0.0f), glm::vec4(0.0f, 0.0f, 0.0f, CONDUCTOR_NAMED * float(metal + 1u)), lambdas, eta, kappa);
    return v.fresnel_conductor(1.0f, eta, kappa);
  };
  const glm::vec4 r = reflectance(METAL_AU);
  EXPECT_NEAR(r.x, 0.40819371891910416, 1e-4);
  EXPECT_NEAR(r.y, 0.79155328372198153, 1e-4);
  EXPECT_NEAR(r.z, 0.95652226640788107, 1e-4);
  EXPECT_EQ(r.w, r.x);
  // Silver reflects more than gold in the blue, copper less than gold in the green.
  EXPECT_GT(reflectance(METAL_AG).x, 0.9f);
  EXPECT_LT(reflectance(METAL_CU).y, r.y);
}

// The furnace box (grey walls of albedo 1/2 that emit white 1/2), rendered
// spectrally with the wavelengths confined to each tenth of the sampler's
// range in turn: at every wavelength a path carries, its radiance (over D65,
// which the film applies: light_spectrum)
// has the RGB render's mean, 1 - 1/2^3 at two bounces. `plant` scales the
// radiance (a planted bias); returns the largest |z| over the bands.
double furnace_band_z(double plant) {
  Scene scene = load_scene(source_path("tests/data/furnace.json"));
  RenderOptions o;
  o.maxBounces = 2;
  o.spectral = true;
  const CompiledScene cs = compile_scene(scene, o);
  SceneView v = cs.view();
  const double expected = 0.875;
  double worst = 0.0;
  for (int band = 0; band < 10; ++band) {
    v.wavelengthBand = glm::vec2(float(band) / 10.0f, float(band + 1) / 10.0f);
    double sum = 0.0, sumSq = 0.0;
    int n = 0;
    for (uint32_t pixel = 0; pixel < uint32_t(cs.width * cs.height); pixel += 7) {
      for (uint32_t s = 0; s < 16; ++s) {
        SceneView::SampleRays rays;
        AovSample aov;
        const PathState p = v.trace_sample(pixel, s, rays, aov);
        EXPECT_TRUE(p.wavelengths >= v.wavelengthBand.x && p.wavelengths <= v.wavelengthBand.y) << p.wavelengths;
        for (int c = 0; c < PATH_WAVELENGTHS; ++c) {
          const double x = plant * double(p.radiance[c]);  // (over D65: light_spectrum)
          sum += x;
          sumSq += x * x;
          ++n;
        }
      }
    }
    const double mean = sum / n, var = std::max(sumSq / n - mean * mean, 1e-12);
    worst = std::max(worst, std::fabs(mean - expected) / std::sqrt(var / n));
  }
  return worst;
}

TEST(Spectral, FurnaceBoxIsAnalyticInEveryWavelengthBand) {
  EXPECT_LT(furnace_band_z(1.0), 4.0);
  EXPECT_GT(furnace_band_z(1.02), 4.0) << "a planted bias of 2 %";
  // And the film: the whole render white and analytic.
  Scene scene = load_scene(source_path("tests/data/furnace.json"));
  RenderOptions o;
  o.maxBounces = 2;
  o.spp = 32;
  o.spectral = true;
  Progress quiet("", 0, false);
  expect_mean(render_cpu(compile_scene(scene, o), 0, quiet), 0.875, "spectral furnace");
}

// Without dispersion, measured spectra or interreflection between colours
// (one bounce of white light), the spectral and RGB renders estimate the same
// image: they differ by the uplift's round trip (99 % of colours within
// 0.31 %), below what 512 samples resolve. The comparison the project trusts
// decides, and catches a planted bias of 2 %.
TEST(Spectral, DirectLightAgreesWithRgbWithinTheRoundTrip) {
  const std::string path = write_scene("spectral-direct.json", R"({
    "camera": { "transform": { "from": [0, 1.6, 5], "at": [0, 0.6, 0], "up": [0, 1, 0] }, "vfov": 40, "resolution": [32, 24] },
    "integrator": { "type": "path tracer mis", "max bounces": 1 },
    "materials": [
      { "type": "lambertian", "name": "floor", "albedo": { "type": "checker", "scale": 0.0796, "even": [0.8, 0.75, 0.1], "odd": [0.1, 0.3, 0.7], "mapping": { "type": "uv" } } },
      { "type": "lambertian", "name": "red", "albedo": [0.8, 0.05, 0.05] },
      { "type": "metal", "name": "gold", "albedo": [0.9, 0.6, 0.2], "roughness": 0.2 },
      { "type": "phong", "name": "cyan", "albedo": [0.1, 0.6, 0.7], "exponent": 20 }
    ],
    "surfaces": [
      { "type": "quad", "size": 8, "material": "floor", "transform": { "rotate": [-90, 1, 0, 0] } },
      { "type": "sphere", "radius": 0.45, "material": "red", "transform": { "translate": [-1.2, 0.45, 0] } },
      { "type": "sphere", "radius": 0.45, "material": "gold", "transform": { "translate": [0.1, 0.45, 0.3] } },
      { "type": "sphere", "radius": 0.45, "material": "cyan", "transform": { "translate": [1.3, 0.45, 0.2] } },
      { "type": "quad", "size": 1.2, "material": { "type": "diffuse_light", "emit": 6 }, "transform": [ { "rotate": [90, 1, 0, 0] }, { "translate": [0.5, 3, 1] } ] }
    ]
  })");
  RenderOptions o;
  o.seed = 1;
  const ImageStats rgb = render_reference(path, o, 512);
  o.seed = 2;
  o.spectral = true;
  ImageStats spectral = render_reference(path, o, 512);
  const CompareResult same = compare_images(spectral, rgb);
  EXPECT_TRUE(same.passed()) << same.summary();
  plant_bias(spectral, 1.02);
  EXPECT_FALSE(compare_images(spectral, rgb).passed()) << "a planted bias of 2 %";
}

// A glass's index by Sellmeier's equation in double precision, from the
// coefficients glasses.glsl takes from its sources.
double sellmeier(uint32_t glass, double lambdaNm) {
  const double l2 = lambdaNm * lambdaNm * 1e-6;
  double n2 = 1.0;
#define WP_GLASS_TERMS(id, name, b1, b2, b3, b4, c1, c2, c3, c4)                                                            \
  if (glass == id)                                                                                                         \
    n2 += double(b1) * l2 / (l2 - double(c1)) + double(b2) * l2 / (l2 - double(c2)) + double(b3) * l2 / (l2 - double(c3)) + \
          double(b4) * l2 / (l2 - double(c4));
  WP_GLASSES(WP_GLASS_TERMS)
#undef WP_GLASS_TERMS
  return std::sqrt(n2);
}

// A 45-degree prism of each named glass (24 degrees of diamond: steeper
// prisms reflect the violet totally), in the spectral mode: a ray
// enters one face at half the apex angle and leaves by the other, refracted both times by
// the kernels' dielectric lobe at the index disperse gives the wavelength
// the path keeps. Band by band over the wavelengths, its deviation is what
// Snell's law gives with the glass's Sellmeier index, D = t1 + asin(n sin(A
// - asin(sin t1 / n))) - A (the indices at the d line: BK7 1.5168, fused
// silica 1.4585, water 1.3333, diamond 2.4173); blue bends more than red.
// Taking another glass's index (a planted error) misses by degrees.
TEST(Spectral, PrismDeviationFollowsEachGlassSellmeierIndex) {
  SceneView v = spectral_view();
  EXPECT_NEAR(sellmeier(GLASS_BK7, 587.56), 1.5168, 1e-4);
  EXPECT_NEAR(sellmeier(GLASS_FUSED_SILICA, 587.56), 1.4585, 1e-4);
  EXPECT_NEAR(sellmeier(GLASS_WATER, 587.56), 1.3333, 2e-4);
  EXPECT_NEAR(sellmeier(GLASS_DIAMOND, 587.56), 2.4173, 1e-3);
  const glm::vec3 d(1.0f, 0.0f, 0.0f);
  for (uint32_t glass = 0; glass < GLASS_COUNT; ++glass) {
    const double apex = (glass == GLASS_DIAMOND ? 24.0 : 45.0) * WP_PI / 180.0, t1 = apex / 2.0;
    const glm::vec3 n1(-std::cos(float(t1)), std::sin(float(t1)), 0.0f), n2(std::cos(float(t1)), std::sin(float(t1)), 0.0f);
    auto analytic = [&](double n) { return t1 + std::asin(n * std::sin(apex - std::asin(std::sin(t1) / n))) - apex; };
    double lastLambda = 0.0, lastDeviation = 0.0;
    for (int band = 0; band < 10; ++band) {
      PathState p{};
      p.rng = 7u + uint32_t(band);
      p.wavelengths = (float(band) + 0.5f) / 10.0f;
      ShaderMath::Bsdf b{};
      b.lobeCount = 1u;
      b.lobeType[0] = MAT_DIELECTRIC;
      b.lobeParam[0] = float(sellmeier(glass, 587.56));
      b.lobeDispersion[0] = -float(glass + 1u);
      const glm::vec4 lambdas = v.path_wavelengths(p.wavelengths);
      v.disperse(p, b, lambdas);
      const uint32_t channel = (p.flags & PATH_CHANNEL_MASK) >> PATH_CHANNEL_SHIFT;
      ASSERT_GE(channel, 1u);
      const double lambda = lambdas[int(channel) - 1];
      ShaderMath::Lobe in = v.lobe_with_params(glm::vec4(b.lobeParam[0], 0.0f, 0.0f, 0.0f), glm::vec4(0.0f));
      in.color = glm::vec4(1.0f);
      in.front = true;
      glm::vec3 inside, out;
      ASSERT_GT(v.dielectric_sample_delta(in, n1, n1, -d, 0.99999f, inside).x, 0.0f);
      ShaderMath::Lobe leave = in;
      leave.front = false;
      ASSERT_GT(v.dielectric_sample_delta(leave, -n2, -n2, -inside, 0.99999f, out).x, 0.0f);
      const double deviation = std::acos(std::clamp(double(glm::dot(d, out)), -1.0, 1.0));
      const double n = sellmeier(glass, lambda);
      EXPECT_NEAR(deviation, analytic(n), 2e-4) << "glass " << glass << " at " << lambda << " nm";
      const double other = sellmeier(glass == GLASS_BK7 ? GLASS_FUSED_SILICA : GLASS_BK7, lambda);
      EXPECT_GT(std::fabs(deviation - analytic(other)), 0.02) << "a planted wrong glass";
      if (lastLambda > 0.0 && std::fabs(lambda - lastLambda) > 5.0) {
        EXPECT_EQ(lambda < lastLambda, deviation > lastDeviation) << "shorter waves bend more";
      }
      lastLambda = lambda;
      lastDeviation = deviation;
    }
  }
}

}  // namespace
}  // namespace wp::test
