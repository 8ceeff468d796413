#include "stats/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "util/error.h"

namespace wp {

namespace {

double two_sided_p(double z) {
  return std::erfc(std::fabs(z) / std::sqrt(2.0));
}

// Mean of each channel over each tile, A against B, Sidak over all tests.
void tile_tests(const ImageStats& a, const ImageStats& b, const CompareSettings& s, CompareResult& r) {
  int t = std::max(1, s.tileSize);
  int tilesX = (a.width + t - 1) / t, tilesY = (a.height + t - 1) / t;
  double alphaTile = 1.0 - std::pow(1.0 - s.alpha, 1.0 / double(tilesX * tilesY * 3));
  for (int ty = 0; ty < tilesY; ++ty) {
    for (int tx = 0; tx < tilesX; ++tx) {
      TileResult tile;
      tile.x0 = tx * t;
      tile.y0 = ty * t;
      tile.x1 = std::min(a.width, tile.x0 + t);
      tile.y1 = std::min(a.height, tile.y0 + t);
      glm::dvec3 sA(0.0), sB(0.0), vA(0.0), vB(0.0);
      for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
          size_t p = size_t(y) * size_t(a.width) + size_t(x);
          sA += a.mean(p);
          sB += b.mean(p);
          vA += a.variance(p) / std::max(a.count[p], 1.0);
          vB += b.variance(p) / std::max(b.count[p], 1.0);
        }
      }
      for (int c = 0; c < 3; ++c) {
        double floor = s.relativeFloor * 0.5 * (std::fabs(sA[c]) + std::fabs(sB[c]));
        double z = (sA[c] - sB[c]) / std::max(std::sqrt(vA[c] + vB[c]), floor + 1e-300);
        if (std::fabs(z) >= std::fabs(tile.z)) {
          tile.z = z;
          tile.p = two_sided_p(z);
        }
      }
      double totalB = sB.x + sB.y + sB.z;
      tile.relativeBias = totalB != 0.0 ? (sA.x + sA.y + sA.z) / totalB - 1.0 : 0.0;
      tile.failed = tile.p < alphaTile;
      r.failingTiles += tile.failed;
      r.tiles.push_back(tile);
    }
  }
  r.tileTestPassed = r.failingTiles == 0;
}

}  // namespace

std::vector<TileResult> CompareResult::worst_tiles(size_t count) const {
  std::vector<TileResult> sorted = tiles;
  std::sort(sorted.begin(), sorted.end(), [](const TileResult& x, const TileResult& y) { return std::fabs(x.z) > std::fabs(y.z); });
  if (sorted.size() > count) sorted.resize(count);
  return sorted;
}

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
  // The floor of a pixel's difference is relative to the pixel, and never
  // below the same fraction of the image's mean: a pixel a million times
  // darker than the image (a glossy lobe's far tail, 1e-24) keeps too few
  // bits of variance in floats to be tested, and no bias there can matter.
  glm::dvec3 imageLevel(0.0);
  for (size_t p = 0; p < a.pixels(); ++p) imageLevel += 0.5 * (glm::abs(a.mean(p)) + glm::abs(b.mean(p)));
  imageLevel /= double(std::max<size_t>(a.pixels(), 1));
  r.zMap.assign(a.pixels(), 0.0f);
  for (size_t p = 0; p < a.pixels(); ++p) {
    glm::dvec3 ma = a.mean(p), mb = b.mean(p);
    glm::dvec3 va = a.variance(p), vb = b.variance(p);
    double na = std::max(a.count[p], 1.0), nb = std::max(b.count[p], 1.0);
    for (int c = 0; c < 3; ++c) {
      double seA = va[c] / na, seB = vb[c] / nb;
      double floor = s.relativeFloor * std::max(0.5 * (std::fabs(ma[c]) + std::fabs(mb[c])), imageLevel[c]);
      double se2 = std::max(seA + seB, floor * floor) + 1e-300;
      double z = (ma[c] - mb[c]) / std::sqrt(se2);
      if (two_sided_p(z) < alphaPixel) ++r.failingPixelChannels;
      if (std::fabs(z) > std::fabs(r.zMap[p])) r.zMap[p] = float(z);
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
  tile_tests(a, b, s, r);
  return r;
}

std::string CompareResult::summary() const {
  char buf[1024];
  std::snprintf(buf, sizeof(buf),
                "%s: %zu of %zu pixel-channels differ significantly (%.3f%% pass, need 99.75%%); %zu of %zu tiles differ; "
                "image mean %.6g vs %.6g, worst channel z = %.2f, p = %.3g; relative bias %+.3f%% +- %.3f%% (95%%)",
                passed() ? "AGREE" : "DIFFER", failingPixelChannels, pixelChannels, 100.0 * pixelPassFraction, failingTiles,
                tiles.size(), meanA, meanB, meanZ, meanP, 100.0 * relativeBias, 100.0 * relativeBiasCi95);
  std::string out = buf;
  for (const TileResult& t : worst_tiles(3)) {
    if (!t.failed) break;
    std::snprintf(buf, sizeof(buf), "\n  tile x %d-%d, y %d-%d: relative bias %+.2f%%, z = %.2f", t.x0, t.x1 - 1, t.y0, t.y1 - 1,
                  100.0 * t.relativeBias, t.z);
    out += buf;
  }
  return out;
}

void plant_bias(ImageStats& image, double factor, glm::uvec4 region) {
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (uint32_t(x) < region.x || uint32_t(x) >= region.z || uint32_t(y) < region.y || uint32_t(y) >= region.w) continue;
      const size_t p = size_t(y) * size_t(image.width) + size_t(x);
      for (size_t c = 0; c <= ImageStats::kY; ++c) {  // the colour, its illuminance included
        image.sum[p * image.stride + c] *= factor;
        image.sumSq[p * image.stride + c] *= factor * factor;
      }
    }
  }
}

}  // namespace wp
