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
  double sumA = 0.0, sumB = 0.0, varSumA = 0.0, varSumB = 0.0;
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
      sumA += ma[c];
      sumB += mb[c];
      varSumA += seA;
      varSumB += seB;
    }
  }
  r.pixelPassFraction = 1.0 - double(r.failingPixelChannels) / double(n);
  r.pixelTestPassed = r.pixelPassFraction >= s.minPixelPassFraction;
  r.meanA = sumA / double(n);
  r.meanB = sumB / double(n);
  double seMean = std::sqrt(varSumA + varSumB) / double(n);
  double floor = s.relativeFloor * 0.5 * (std::fabs(r.meanA) + std::fabs(r.meanB));
  r.meanZ = (r.meanA - r.meanB) / std::max(seMean, floor + 1e-300);
  r.meanP = two_sided_p(r.meanZ);
  r.meanTestPassed = r.meanP >= s.alpha;
  if (r.meanB != 0.0) {
    r.relativeBias = r.meanA / r.meanB - 1.0;
    r.relativeBiasCi95 = 1.96 * seMean / std::fabs(r.meanB);
  }
  return r;
}

std::string CompareResult::summary() const {
  char buf[512];
  std::snprintf(buf, sizeof(buf),
                "%s: %zu of %zu pixel-channels differ significantly (%.3f%% pass, need 99.75%%); image mean %.6g vs "
                "%.6g, z = %.2f, p = %.3g; relative bias %+.3f%% +- %.3f%% (95%%)",
                passed() ? "AGREE" : "DIFFER", failingPixelChannels, pixelChannels, 100.0 * pixelPassFraction, meanA,
                meanB, meanZ, meanP, 100.0 * relativeBias, 100.0 * relativeBiasCi95);
  return buf;
}

}  // namespace wp
