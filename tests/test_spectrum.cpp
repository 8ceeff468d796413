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
std::vector<double> uplift_errors(const RgbToSpectrumTable& table, bool checkRange) {
  ShaderMath m;
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<double> errors;
  for (int trial = 0; trial < 3000; ++trial) {
    glm::vec3 rgb(u(rng), u(rng), u(rng));
    if (trial % 3 == 0) rgb[trial % 4 == 0 ? 0 : 2] = 0.0f;
    const glm::vec3 c = rgb_to_spectrum(table, rgb);
    const double largest = std::max({rgb.x, rgb.y, rgb.z});
    errors.push_back(glm::length(spectrum_to_rgb(c) - glm::dvec3(rgb)) / std::max(largest, 0.05));
    for (float lambda = SPECTRUM_MIN_NM; checkRange && lambda <= SPECTRUM_MAX_NM; lambda += 10.0f) {
      const float s = m.sigmoid_polynomial(c, lambda);
      EXPECT_TRUE(s >= 0.0f && s <= 1.0f) << s;
    }
  }
  std::sort(errors.begin(), errors.end());
  return errors;
}

TEST(Spectrum, UpliftedReflectancesKeepTheirColour) {
  const RgbToSpectrumTable& table = rgb_to_spectrum_table();
  const std::vector<double> errors = uplift_errors(table, true);
  EXPECT_LT(errors[errors.size() / 2], 1e-3);
  EXPECT_LT(errors[errors.size() * 99 / 100], 5e-3);
  EXPECT_LT(errors.back(), 0.15);
  for (float v : {0.0f, 0.18f, 0.5f, 1.0f}) {
    const glm::dvec3 back = spectrum_to_rgb(rgb_to_spectrum(table, glm::vec3(v)));
    EXPECT_NEAR(back.x, v, 1e-5);
    EXPECT_NEAR(back.y, v, 1e-5);
    EXPECT_NEAR(back.z, v, 1e-5);
  }
  RgbToSpectrumTable shifted = table;
  const size_t slice = size_t(table.res) * size_t(table.res) * 3;
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k + 1 < table.res; ++k)
      std::copy_n(&table.coefficients[(size_t(l * table.res + k + 1)) * slice], slice, &shifted.coefficients[size_t(l * table.res + k) * slice]);
  EXPECT_GT(uplift_errors(shifted, false)[errors.size() * 99 / 100], 5e-3) << "a planted shift of the table";
}

}  // namespace
}  // namespace wp::test
