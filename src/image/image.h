// image.h — a rendered image as statistics: per pixel and channel the sum and
// sum of squares of the samples, and per pixel the sample count, in double
// precision. The PNG shows the mean; the EXR keeps mean, variance and count so
// that `wavepath compare` and the tests can judge images later.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace wp {

struct ImageStats {
  int width = 0;
  int height = 0;
  std::vector<double> sum;    // 3 per pixel
  std::vector<double> sumSq;  // 3 per pixel
  std::vector<double> count;  // 1 per pixel
  std::vector<double> illuminanceSumSq;  // 1 per pixel: for adaptive sampling (illuminance sums follow from `sum`)
  uint64_t nonFinite = 0;     // samples dropped because they were NaN or infinite

  ImageStats() = default;
  ImageStats(int w, int h)
      : width(w), height(h), sum(size_t(w) * h * 3), sumSq(size_t(w) * h * 3), count(size_t(w) * h), illuminanceSumSq(size_t(w) * h) {}
  size_t pixels() const { return size_t(width) * size_t(height); }
  glm::dvec3 mean(size_t pixel) const;
  // Unbiased sample variance of one sample (not of the mean); 0 below 2 samples.
  glm::dvec3 variance(size_t pixel) const;
  double mean_luminance() const;
  // Sum of the illuminance (luminance) of the samples of a pixel.
  double illuminance_sum(size_t pixel) const;
};

// The mean as 8-bit sRGB, clamped: three bytes per pixel, row by row.
std::vector<uint8_t> to_srgb8(const ImageStats& image);
// PNG file contents for 8-bit RGB pixels.
std::vector<uint8_t> encode_png(int width, int height, const std::vector<uint8_t>& rgb);

// 8-bit sRGB PNG of the mean, clamped. Written to a temporary file and renamed,
// so a failed or interrupted write never leaves a complete-looking image.
void write_png(const std::string& path, const ImageStats& image);

// Samples per pixel as colour, CS184's sample-rate image: blue (few) through
// green to red (maxSamples).
void write_sample_rate_png(const std::string& path, const ImageStats& image, int maxSamples);

// OpenEXR, 32-bit float channels R, G, B (mean), var.R, var.G, var.B (sample
// variance) and n (sample count). Written atomically like the PNG.
void write_exr(const std::string& path, const ImageStats& image);
ImageStats read_exr(const std::string& path);

}  // namespace wp
