#include "stats/chi2.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace wp {

// Series for x < a + 1, Lentz's continued fraction otherwise.
double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  double lg = std::lgamma(a);
  if (x < a + 1.0) {
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
    }
    return 1.0 - sum * std::exp(-x + a * std::log(x) - lg);
  }
  double b = x + 1.0 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::fabs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    double del = d * c;
    h *= del;
    if (std::fabs(del - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - lg) * h;
}


Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected, double sampleCount) {
  Chi2Result r;
  double expTotal = std::accumulate(expected.begin(), expected.end(), 0.0);
  if (expTotal > 1.1 * sampleCount) r.problem = "the pdf integrates to more than 1.1";
  std::vector<size_t> order(observed.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  double poolObs = 0.0, poolExp = 0.0;
  int cells = 0;
  for (size_t i : order) {
    if (expected[i] == 0.0) {
      if (observed[i] > sampleCount * 1e-5) r.problem = "samples fell into a cell where the pdf is zero";
      continue;
    }
    if (expected[i] < 5.0) {
      poolObs += observed[i];
      poolExp += expected[i];
      continue;
    }
    double d = observed[i] - expected[i];
    r.statistic += d * d / expected[i];
    ++cells;
  }
  if (poolExp > 0.0) {
    double d = poolObs - poolExp;
    r.statistic += d * d / poolExp;
    ++cells;
  }
  r.dof = cells - 1;
  r.pValue = r.dof > 0 ? gamma_q(0.5 * r.dof, 0.5 * r.statistic) : 1.0;
  return r;
}

double sidak(double alpha, int tests) {
  return 1.0 - std::pow(1.0 - alpha, 1.0 / tests);
}

}  // namespace wp
