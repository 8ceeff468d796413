// The spectral mode's wavelengths (shaders/shared/spectrum.glsl): the
// visible-wavelength sampler against its density (chi-square, and a planted
// density 4 % narrower caught), the density's normalization, and the colour
// matching functions' fit against the CIE 1931 observer's integrals and
// chromaticities.
#include <cmath>
#include <vector>

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

}  // namespace
}  // namespace wp::test
