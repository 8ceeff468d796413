// render_control.h — which samples a render takes, and how it may stop
// early: what the GPU and CPU renderers share so that a render can be split
// into sample ranges, budgeted, interrupted and resumed (docs/partial-renders.md).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "image/image.h"
#include "render/adaptive.h"

namespace wp {

// Samples [begin, end) of every pixel. The random numbers of a sample depend
// only on the seed, the pixel and the sample's index (rng.glsl), so ranges
// rendered apart add up to the range they cover.
struct SampleRange {
  uint32_t begin = 0;
  uint32_t end = 0;
  uint32_t size() const { return end > begin ? end - begin : 0; }
};

// Called by a renderer between passes (after whole samples of every pixel it
// samples; under adaptive sampling, after whole batches) with the image so
// far and the sample every pixel has reached. Returning false stops the
// render there. Renderers call it about twice a second at most, and at least
// every few seconds where a pass is that short.
using PassHook = std::function<bool(const ImageStats& image, uint32_t reached)>;

// The pixels adaptive sampling still samples from sample `begin` on, in an
// image holding samples [0, begin) (begin a multiple of the batch): every
// pixel at 0, else those not converged.
inline std::vector<uint32_t> unconverged_pixels(const ImageStats& image, uint32_t begin, const AdaptiveSampling& adaptive) {
  std::vector<uint32_t> active;
  for (uint32_t p = 0; p < uint32_t(image.pixels()); ++p) {
    if (begin == 0 || !pixel_converged(image.count[p], image.illuminance_sum(p), image.illuminance_sum_sq(p), adaptive.tolerance))
      active.push_back(p);
  }
  return active;
}

}  // namespace wp
