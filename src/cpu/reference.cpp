#include "cpu/reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>

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
  const uint32_t maxBounces = cs.params.image.z;
  const AdaptiveSampling adaptive = cs.adaptive;
  const uint32_t lightSamples = std::max(1u, cs.params.mode.w);

  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, image.pixels(), 64), [&](const tbb::blocked_range<size_t>& r) {
      uint64_t localTruncated = 0;
      uint64_t localNonFinite = 0;
      for (size_t pixel = r.begin(); pixel != r.end(); ++pixel) {
        for (uint32_t s = 0; s < spp; ++s) {
          PathState p;
          view.path_begin(p, uint32_t(pixel), s);
          // Each iteration is one bounce: extend, shade, connect. path_shade ends
          // the path after maxBounces scattering events, so this loop is bounded.
          for (uint32_t bounce = 0; bounce <= maxBounces; ++bounce) {
            Hit h;
            if (view.trace_ray(p.origin, p.dir, WP_INF, false, h) != TRACE_OK) {
              ++localTruncated;
              h.prim = WP_INVALID;
            }
            SceneView::ShadowRays srs;
            bool alive = view.path_shade(p, h, srs);
            for (uint32_t j = 0; j < lightSamples; ++j) {
              const ShadowRay& sr = srs.ray[j];
              if (sr.tmax <= 0.0f) continue;
              Hit sh;
              if (view.trace_ray(sr.origin, sr.dir, sr.tmax, true, sh) != TRACE_OK) ++localTruncated;
              else if (sh.prim == WP_INVALID) p.radiance += sr.contribution;
            }
            if (!alive) break;
          }
          if (view.radiance_is_finite(p.radiance)) {
            for (int c = 0; c < 3; ++c) {
              image.sum[3 * pixel + size_t(c)] += p.radiance[c];
              image.sumSq[3 * pixel + size_t(c)] += double(p.radiance[c]) * double(p.radiance[c]);
            }
            double y = view.illuminance(p.radiance);
            image.illuminanceSumSq[pixel] += y * y;
            image.count[pixel] += 1.0;
          } else {
            ++localNonFinite;
          }
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
