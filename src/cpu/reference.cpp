#include "cpu/reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>

#include "render/accumulate.h"
#include "render/shader_cpp.h"
#include "util/error.h"

namespace wp {

RenderOptions reference_options(RenderOptions options) {
  options.bvhLayout = BvhLayout::Binary;
  options.binaryFused = true;
  options.photonsOnHost = true;
  return options;
}

uint32_t render_cpu(const CompiledScene& cs, int threads, ImageStats& image, SampleRange range, Progress& progress,
                    const PassHook& afterPass) {
  using namespace shader;
  if (image.width != cs.width || image.height != cs.height || image.aov_names() != cs.aovs)
    throw RenderError("internal error: the image to render into does not match the scene's size or layers");
  if (cs.photonMapLeftToDevice) throw RenderError("internal error: the CPU reference was given a scene whose photon map was left to a GPU");
  SceneView view = cs.view();  // read-only; shared by all threads
  view.aovs = !cs.aovs.empty();
  const AovLayout aovLayout(image);
  std::atomic<uint64_t> truncated{0};
  std::atomic<uint64_t> nonFinite{0};
  const AdaptiveSampling adaptive = cs.adaptive;
  std::vector<uint32_t> active;
  if (adaptive.enabled()) active = unconverged_pixels(image, range.begin, adaptive);
  else for (uint32_t p = 0; p < uint32_t(image.pixels()); ++p) active.push_back(p);

  // Passes of whole samples, growing while they take under a quarter of a
  // second (the pass hook's cadence); under adaptive sampling, one batch
  // each, after which converged pixels stop.
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  uint32_t reached = range.begin;
  uint32_t perPass = 1;
  while (reached < range.end && !active.empty()) {
    uint32_t next = adaptive.enabled() ? std::min((reached / uint32_t(adaptive.batch) + 1) * uint32_t(adaptive.batch), range.end)
                                       : std::min(reached + perPass, range.end);
    auto t0 = std::chrono::steady_clock::now();
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, active.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
        uint64_t localTruncated = 0;
        uint64_t localNonFinite = 0;
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const uint32_t pixel = active[i];
          for (uint32_t s = reached; s < next; ++s) {
            SceneView::SampleRays rays;
            AovSample aov;
            PathState p = view.trace_sample(pixel, s, rays, aov);
            localTruncated += rays.truncated;
            const glm::vec3 l = view.sample_rgb(p);
            if (!view.radiance_is_finite(l)) {
              ++localNonFinite;
              continue;
            }
            add_to_pixel(image, pixel, view.sample_moments(l));
            if (!aovLayout.empty()) add_aovs_to_pixel(image, aovLayout, pixel, view.aov_moments(aov));
          }
        }
        truncated += localTruncated;
        nonFinite += localNonFinite;
        progress.add(uint64_t(r.size()) * (next - reached));
      });
    });
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    reached = next;
    if (adaptive.enabled()) {
      std::vector<uint32_t> still;
      for (uint32_t p : active)
        if (!pixel_converged(image.count[p], image.illuminance_sum(p), image.illuminance_sum_sq(p), adaptive.tolerance)) still.push_back(p);
      active.swap(still);
    } else if (seconds < 0.25) {
      perPass = std::min(perPass * 2, 256u);
    }
    if (reached < range.end && !active.empty() && afterPass && !afterPass(image, reached)) break;
  }
  if (active.empty()) reached = range.end;  // every pixel converged: the range is done
  progress.finish();
  image.nonFinite += nonFinite.load();
  if (truncated.load() > 0) {
    throw RenderError(std::to_string(truncated.load()) + " rays needed more than " + std::to_string(cs.params.counts.z) +
                      " BVH traversal steps; the image would be wrong, so none was written");
  }
  return reached;
}

ImageStats render_cpu(const CompiledScene& cs, int threads, Progress& progress) {
  ImageStats image(cs.width, cs.height, image_layers(cs.aovs));
  render_cpu(cs, threads, image, SampleRange{0, uint32_t(cs.spp)}, progress);
  return image;
}

}  // namespace wp
