// chi2.h — Pearson's chi-square goodness-of-fit test as pbrt, Mitsuba and Nori
// use it to check a sampler against its pdf: cells with an expected count
// under 5 pooled into one, the level Sidak-corrected over the tests run.
// The tests and `wavepath test` (darts' test scenes) share it.
#pragma once

#include <string>
#include <vector>

namespace wp {

// Regularised upper incomplete gamma Q(a, x): the chi-square survival
// function is Q(k/2, x/2).
double gamma_q(double a, double x);

struct Chi2Result {
  double statistic = 0.0;
  int dof = 0;
  double pValue = 1.0;
  std::string problem;  // samples in zero-expectation cells, a pdf integrating past 1.1...
};

// Observed and expected counts per cell (expected already scaled to the sample count).
Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected, double sampleCount);

// Sidak-corrected per-test level for `tests` tests at family-wise level alpha.
double sidak(double alpha, int tests);

}  // namespace wp
