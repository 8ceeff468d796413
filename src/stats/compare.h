// compare.h — do two renders estimate the same image? Per pixel and channel a
// Welch z-test with a variance floor, Sidak-corrected over all pixel-channels,
// passing when at least 99.75 % of them pass (Mitsuba's rule); plus a test of
// the whole-image mean of each channel (Sidak over the three), which has far
// more power against a small global bias. The channels are tested apart
// because one path sample carries all three: they are correlated, and adding
// their variances as if independent understates the error by up to sqrt(3).
#pragma once

#include <string>

#include "image/image.h"

namespace wp {

struct CompareSettings {
  double alpha = 0.01;                // family-wise significance of each test
  double minPixelPassFraction = 0.9975;
  double relativeFloor = 1e-4;        // differences below this fraction of the mean are never significant
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
  bool passed() const { return pixelTestPassed && meanTestPassed; }
  std::string summary() const;
};

// Throws InputError if the images differ in size.
CompareResult compare_images(const ImageStats& a, const ImageStats& b, const CompareSettings& settings = {});

}  // namespace wp
