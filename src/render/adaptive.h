// adaptive.h — CS184's adaptive sampling, shared by the GPU and CPU renderers:
// pixels are sampled in batches, and after each batch a pixel stops once the
// 95% confidence interval of its mean illuminance is within `tolerance` of the
// mean: 1.96 * sigma / sqrt(n) <= tolerance * mu.
#pragma once

#include <cmath>

namespace wp {

struct AdaptiveSampling {
  int batch = 0;            // samples between convergence checks; 0: off
  float tolerance = 0.05f;  // relative half-width of the 95% interval
  bool enabled() const { return batch > 0; }
};

// n samples of illuminance with sum s1 and sum of squares s2.
inline bool pixel_converged(double n, double s1, double s2, float tolerance) {
  if (n < 2.0) return false;
  double mu = s1 / n;
  double var = std::max(0.0, (s2 - s1 * s1 / n) / (n - 1.0));
  return 1.96 * std::sqrt(var / n) <= double(tolerance) * mu;
}

}  // namespace wp
