// accumulate.h — pixel sums into an image: the host's half of the one
// accumulation (sample_moments in integrator.glsl defines what a sample adds).
#pragma once

#include <cstddef>

#include "image/image.h"
#include "render/shader_cpp.h"

namespace wp {

// Adds sums `a` (one sample's moments, or a GPU batch's sums of them) to
// pixel `pixel` of `image`, in double precision.
inline void add_to_pixel(ImageStats& image, size_t pixel, const shader::PixelAccum& a) {
  for (size_t c = 0; c < 3; ++c) {
    image.sum[3 * pixel + c] += a.sum[int(c)];
    image.sumSq[3 * pixel + c] += a.sumSq[int(c)];
  }
  image.count[pixel] += a.sum.w;
  image.illuminanceSumSq[pixel] += a.sumSq.w;
}

}  // namespace wp
