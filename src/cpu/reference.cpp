#include "cpu/reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>

#include "render/accumulate.h"
#include "util/error.h"

namespace wp {

RenderOptions reference_options(RenderOptions options) {
  options.bvhLayout = BvhLayout::Binary;
  return options;
}

ImageStats render_cpu(const CompiledScene& cs, int threads, Progress& progress) {
  using namespace shader;
  SceneView view = cs.view();  // read-only; shared by all threads
  ImageStats image(cs.width, cs.height);
  std::atomic<uint64_t> truncated{0};
  std::atomic<uint64_t> nonFinite{0};
  const uint32_t spp = uint32_t(cs.spp);
  const AdaptiveSampling adaptive = cs.adaptive;

  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, image.pixels(), 64), [&](const tbb::blocked_range<size_t>& r) {
      uint64_t localTruncated = 0;
      uint64_t localNonFinite = 0;
      for (size_t pixel = r.begin(); pixel != r.end(); ++pixel) {
        for (uint32_t s = 0; s < spp; ++s) {
          SceneView::SampleRays rays;
          PathState p = view.trace_sample(uint32_t(pixel), s, rays);
          localTruncated += rays.truncated;
          if (view.radiance_is_finite(p.radiance)) add_to_pixel(image, pixel, view.sample_moments(p.radiance));
          else ++localNonFinite;
          // Adaptive sampling: after each batch, stop once the pixel has converged.
          if (adaptive.enabled() && (s + 1) % uint32_t(adaptive.batch) == 0 &&
              pixel_converged(image.count[pixel], image.illuminance_sum(pixel), image.illuminanceSumSq[pixel], adaptive.tolerance)) {
            break;
          }
        }
      }
      truncated += localTruncated;
      nonFinite += localNonFinite;
      progress.add(uint64_t(r.size()) * spp);
    });
  });
  progress.finish();
  image.nonFinite = nonFinite.load();
  if (truncated.load() > 0) {
    throw RenderError(std::to_string(truncated.load()) + " rays needed more than " + std::to_string(cs.params.counts.z) +
                      " BVH traversal steps; the image would be wrong, so none was written");
  }
  return image;
}

}  // namespace wp
