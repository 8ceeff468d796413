// compare.h — do two renders estimate the same image? Per pixel and channel a
// Welch z-test with a variance floor, Sidak-corrected over all pixel-channels,
// passing when at least 99.75 % of them pass (Mitsuba's rule); plus a test of
// the whole-image mean of each channel (Sidak over the three), which has far
// more power against a small global bias; plus mean tests per tile (16x16 by
// default, Sidak over tiles and channels), which have the power against a
// bias confined to a region. The channels are tested apart
// because one path sample carries all three: they are correlated, and adding
// their variances as if independent understates the error by up to sqrt(3).
#pragma once

#include <string>
#include <vector>

#include "image/image.h"

namespace wp {

struct CompareSettings {
  double alpha = 0.01;                // family-wise significance of each test
  double minPixelPassFraction = 0.9975;
  double relativeFloor = 1e-4;        // differences below this fraction of the mean (a pixel's: of the pixel,
                                      // or of the image where that is more) are never significant
  int tileSize = 16;
};

struct TileResult {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixel bounds [x0, x1) x [y0, y1)
  double z = 0.0;                      // of the channel with the largest |z|
  double p = 1.0;
  double relativeBias = 0.0;           // tile mean of A / tile mean of B - 1, over channels
  bool failed = false;
};

struct CompareResult {
  size_t pixelChannels = 0;
  size_t failingPixelChannels = 0;
  double pixelPassFraction = 0.0;
  bool pixelTestPassed = false;
  double meanA = 0.0;  // image mean over pixels and channels
  double meanB = 0.0;
  double meanZ = 0.0;  // of the channel with the smallest p
  double meanP = 1.0;
  bool meanTestPassed = false;
  double relativeBias = 0.0;      // meanA / meanB - 1
  double relativeBiasCi95 = 0.0;  // half-width of its 95 % interval
  std::vector<TileResult> tiles;  // row by row
  size_t failingTiles = 0;
  bool tileTestPassed = false;
  std::vector<float> zMap;        // per pixel: z of the channel with the largest |z|
  bool passed() const { return pixelTestPassed && meanTestPassed && tileTestPassed; }
  // The tiles with the largest |z|, most significant first.
  std::vector<TileResult> worst_tiles(size_t count) const;
  std::string summary() const;
};

// Plants a bias in a render: every sample of the pixels [x0, x1) x [y0, y1)
// of `region` (all pixels by default) scaled by `factor`, as if the renderer
// had scaled them (the sums by factor, the sums of squares by its square).
// For showing what the comparison detects (`wavepath compare --plant-bias`,
// the tests); renderers carry no such hook.
void plant_bias(ImageStats& image, double factor, glm::uvec4 region = glm::uvec4(0u, 0u, ~0u, ~0u));

// Throws InputError if the images differ in size.
CompareResult compare_images(const ImageStats& a, const ImageStats& b, const CompareSettings& settings = {});

}  // namespace wp
