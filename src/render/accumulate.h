// accumulate.h — pixel sums into an image: the host's half of the one
// accumulation (sample_moments and aov_sample in integrator.glsl define what
// a sample adds).
#pragma once

#include <cstddef>

#include "image/image.h"
#include "shader/types.h"

namespace wp {

// Adds sums `a` (one sample's moments, or a GPU batch's sums of them) to the
// colour of pixel `pixel` of `image`, in double precision.
inline void add_to_pixel(ImageStats& image, size_t pixel, const shader::PixelAccum& a) {
  double* sum = &image.sum[pixel * image.stride];
  double* sumSq = &image.sumSq[pixel * image.stride];
  for (int c = 0; c < 3; ++c) {
    sum[c] += a.sum[c];
    sumSq[c] += a.sumSq[c];
  }
  // The illuminance is linear in the colour: its sum is the colour sum's.
  sum[ImageStats::kY] += 0.2126 * double(a.sum.x) + 0.7152 * double(a.sum.y) + 0.0722 * double(a.sum.z);
  sumSq[ImageStats::kY] += a.sumSq.w;
  image.count[pixel] += a.sum.w;
}

// Where each of an image's AOV layers takes its channels from in an
// AovSample (aov_sample_channel), resolved once per image.
struct AovLayout {
  struct Span {
    size_t first;   // in the image's channels
    size_t from;    // in AovSample's channels
    size_t count;
  };
  std::vector<Span> spans;
  explicit AovLayout(const ImageStats& image) {
    for (size_t i = 1; i < image.layers.size(); ++i)
      spans.push_back({image.layers[i].first, aov_sample_channel(image.layers[i].name), image.layers[i].channels.size()});
  }
  bool empty() const { return spans.empty(); }
};

// Adds AOV sums (one sample's AovSample and its squares, or a GPU batch's
// AovAccum) to the AOV layers of pixel `pixel`.
inline void add_aovs_to_pixel(ImageStats& image, const AovLayout& layout, size_t pixel, const shader::AovAccum& a) {
  const float sums[AOV_CHANNELS] = {a.sumA.x, a.sumA.y, a.sumA.z, a.sumA.w, a.sumB.x, a.sumB.y, a.sumB.z, a.sumB.w};
  const float squares[AOV_CHANNELS] = {a.sumSqA.x, a.sumSqA.y, a.sumSqA.z, a.sumSqA.w,
                                       a.sumSqB.x, a.sumSqB.y, a.sumSqB.z, a.sumSqB.w};
  for (const AovLayout::Span& s : layout.spans) {
    for (size_t c = 0; c < s.count; ++c) {
      image.sum[pixel * image.stride + s.first + c] += sums[s.from + c];
      image.sumSq[pixel * image.stride + s.first + c] += squares[s.from + c];
    }
  }
}

}  // namespace wp
