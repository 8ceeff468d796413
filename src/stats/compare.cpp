#include "stats/compare.h"

#include <cmath>
#include <cstdio>

#include "util/error.h"

namespace wp {

namespace {

double two_sided_p(double z) {
  return std::erfc(std::fabs(z) / std::sqrt(2.0));
}

}  // namespace

CompareResult compare_images(const ImageStats& a, const ImageStats& b, const CompareSettings& s) {
  if (a.width != b.width || a.height != b.height) {
    throw InputError("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " vs " +
                     std::to_string(b.width) + "x" + std::to_string(b.height));
  }
  CompareResult r;
  size_t n = a.pixels() * 3;
  r.pixelChannels = n;
  // Sidak: the per-test level that keeps the family-wise error at alpha.
  double alphaPixel = 1.0 - std::pow(1.0 - s.alpha, 1.0 / double(n));
  // Per channel: sum of pixel means and sum of their variances. Pixels are
  // independent, but the channels of one path sample are not (one path carries
  // all three), so the image-mean test is done per channel.
  double sumA[3] = {}, sumB[3] = {}, varA[3] = {}, varB[3] = {};
  for (size_t p = 0; p < a.pixels(); ++p) {
    glm::dvec3 ma = a.mean(p), mb = b.mean(p);
    glm::dvec3 va = a.variance(p), vb = b.variance(p);
    double na = std::max(a.count[p], 1.0), nb = std::max(b.count[p], 1.0);
    for (int c = 0; c < 3; ++c) {
      double seA = va[c] / na, seB = vb[c] / nb;
      double floor = s.relativeFloor * 0.5 * (std::fabs(ma[c]) + std::fabs(mb[c]));
      double se2 = std::max(seA + seB, floor * floor) + 1e-300;
      double z = (ma[c] - mb[c]) / std::sqrt(se2);
      if (two_sided_p(z) < alphaPixel) ++r.failingPixelChannels;
      sumA[c] += ma[c];
      sumB[c] += mb[c];
      varA[c] += seA;
      varB[c] += seB;
    }
  }
  r.pixelPassFraction = 1.0 - double(r.failingPixelChannels) / double(n);
  r.pixelTestPassed = r.pixelPassFraction >= s.minPixelPassFraction;

  const double pixels = double(a.pixels());
  const double alphaChannel = 1.0 - std::pow(1.0 - s.alpha, 1.0 / 3.0);
  r.meanTestPassed = true;
  double seTotal = 0.0;
  for (int c = 0; c < 3; ++c) {
    double meanA = sumA[c] / pixels, meanB = sumB[c] / pixels;
    double se = std::sqrt(varA[c] + varB[c]) / pixels;
    double floor = s.relativeFloor * 0.5 * (std::fabs(meanA) + std::fabs(meanB));
    double z = (meanA - meanB) / std::max(se, floor + 1e-300);
    double p = two_sided_p(z);
    if (p < alphaChannel) r.meanTestPassed = false;
    if (c == 0 || p < r.meanP) {
      r.meanZ = z;
      r.meanP = p;
    }
    r.meanA += meanA / 3.0;
    r.meanB += meanB / 3.0;
    seTotal += se / 3.0;  // sd(X + Y) <= sd(X) + sd(Y) whatever the correlation
  }
  if (r.meanB != 0.0) {
    r.relativeBias = r.meanA / r.meanB - 1.0;
    r.relativeBiasCi95 = 1.96 * seTotal / std::fabs(r.meanB);
  }
  return r;
}

std::string CompareResult::summary() const {
  char buf[512];
  std::snprintf(buf, sizeof(buf),
                "%s: %zu of %zu pixel-channels differ significantly (%.3f%% pass, need 99.75%%); image mean %.6g vs "
                "%.6g, worst channel z = %.2f, p = %.3g; relative bias %+.3f%% +- %.3f%% (95%%)",
                passed() ? "AGREE" : "DIFFER", failingPixelChannels, pixelChannels, 100.0 * pixelPassFraction, meanA,
                meanB, meanZ, meanP, 100.0 * relativeBias, 100.0 * relativeBiasCi95);
  return buf;
}

}  // namespace wp
