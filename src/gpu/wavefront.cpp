// The wavefront loop: for each wave of paths, generate, then per bounce
// prepare, extend, (sort,) shade, prepare, connect, and accumulate; samples
// batched into submissions, their float sums folded into the image.
#include <algorithm>
#include <chrono>

#include "gpu/wavefront_impl.h"
#include "render/accumulate.h"
#include "util/error.h"

namespace wp {

void stage_barrier(vk::CommandBuffer cb) {
  vk::MemoryBarrier b(vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
                      vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite |
                          vk::AccessFlagBits::eIndirectCommandRead | vk::AccessFlagBits::eTransferRead |
                          vk::AccessFlagBits::eTransferWrite);
  cb.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer,
                     vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eDrawIndirect |
                         vk::PipelineStageFlagBits::eTransfer,
                     {}, b, {}, {});
}

void WavefrontRenderer::Impl::dispatch(vk::CommandBuffer cb, const vk::raii::Pipeline& p, const KernelPush& push, uint32_t groups, Stage stage) {
  cb.bindPipeline(vk::PipelineBindPoint::eCompute, *p);
  cb.pushConstants<KernelPush>(*pipelineLayout, vk::ShaderStageFlagBits::eCompute, 0, push);
  cb.dispatch(groups, 1, 1);
  stage_barrier(cb);
  stamp(cb, stage);
}

void WavefrontRenderer::Impl::dispatch_indirect(vk::CommandBuffer cb, const vk::raii::Pipeline& p, const KernelPush& push, uint32_t slot, Stage stage,
                       bool last) {
  cb.bindPipeline(vk::PipelineBindPoint::eCompute, *p);
  cb.pushConstants<KernelPush>(*pipelineLayout, vk::ShaderStageFlagBits::eCompute, 0, push);
  cb.dispatchIndirect(buffers[BINDING_INDIRECT]->handle(), slot * 3 * sizeof(uint32_t));
  if (!last) return;
  stage_barrier(cb);
  stamp(cb, stage);
}

uint32_t WavefrontRenderer::Impl::samples_per_wave(uint32_t pixels) const {
  if (settings.megakernel) return megakernel_samples();
  if (pixels >= capacity) return 1;
  return std::min(capacity / pixels, kMaxSamplesPerWave);
}

void WavefrontRenderer::Impl::record_wave(vk::CommandBuffer cb, uint32_t waveStart, uint32_t span, uint32_t sampleIndex, uint32_t samples,
                                          bool listed, uint32_t accumBase) {
  const uint32_t pathCount = span * samples;
  KernelPush push{};
  push.accumBase = accumBase;
  push.waveStart = waveStart;
  push.waveSpan = span;
  push.pathCount = pathCount;
  push.sampleIndex = sampleIndex;
  push.capacity = capacity;
  push.phase = listed ? GENERATE_FROM_LIST : GENERATE_CONSECUTIVE;
  // A regenerating megakernel (megakernel.comp) takes each pixel's samples in one invocation.
  if (settings.megakernel)
    return dispatch(cb, megakernel, push, interleaved_groups(megakernel_samples() > 1 ? span : pathCount), StageTimes::kMegakernel);
  dispatch(cb, generate, push, groups_for(pathCount), StageTimes::kGenerate);
  // Pass b extends the rays of paths with b scattering events (or passed
  // interfaces) behind them; path_shade ends every path at max bounces.
  const uint32_t passes = path_passes();
  for (uint32_t bounce = 0; bounce < passes; ++bounce) {
    push.queueIn = bounce & 1u;
    push.phase = PREPARE_EXTEND;
    dispatch(cb, prepare, push, 1, StageTimes::kPrepare);
    dispatch_indirect(cb, extend, push, INDIRECT_EXTEND, StageTimes::kExtend);
    if (sorting) {
      dispatch_indirect(cb, sort, push, INDIRECT_SHADE, StageTimes::kSort);
      push.phase = PREPARE_SORT;
      dispatch(cb, prepare, push, 1, StageTimes::kPrepare);
      // Each key's kernel over its queue; the queues are disjoint and the
      // appends atomic, so the dispatches need no barrier between them.
      for (size_t k = 0; k < shadeByKey.size(); ++k)
        dispatch_indirect(cb, shadeByKey[k], push, INDIRECT_SHADE_KEY0 + shadeKeys[k], StageTimes::kShade, k + 1 == shadeByKey.size());
    } else {
      dispatch_indirect(cb, shade, push, INDIRECT_SHADE, StageTimes::kShade);
    }
    push.phase = PREPARE_CONNECT;
    dispatch(cb, prepare, push, 1, StageTimes::kPrepare);
    dispatch_indirect(cb, connect, push, INDIRECT_CONNECT, StageTimes::kConnect);
  }
  dispatch(cb, accumulate, push, groups_for(span), StageTimes::kAccumulate);
}

uint32_t WavefrontRenderer::Impl::render(ImageStats& image, SampleRange range, Progress& progress, const PassHook& afterPass) {
  uint64_t truncated = 0;
  times = StageTimes{};
  times.photonPassSeconds = photonPassSeconds;
  times.photonRecords = photonMapSize;
  uint32_t reached = range.begin;
  if (!scene.adaptive.enabled()) {
    reached = render_samples(image, truncated, progress, range.begin, range.end, nullptr, afterPass);
  } else {
    // Batches of the whole render's grid (multiples of the batch size from
    // sample 0), so that a range resumed at a batch's start continues it.
    std::vector<uint32_t> active = unconverged_pixels(image, range.begin, scene.adaptive);
    const uint32_t batch = uint32_t(scene.adaptive.batch);
    while (reached < range.end && !active.empty()) {
      uint32_t next = std::min((reached / batch + 1) * batch, range.end);
      try {
        render_samples(image, truncated, progress, reached, next, &active, {});
      } catch (DeviceLost& lost) {
        // A batch part done leaves its pixels with samples the others lack.
        lost.intact = lost.reached == reached;
        lost.reached = reached;
        throw;
      }
      reached = next;
      std::vector<uint32_t> still;
      for (uint32_t p : active) {
        if (!pixel_converged(image.count[p], image.illuminance_sum(p), image.illuminance_sum_sq(p), scene.adaptive.tolerance))
          still.push_back(p);
      }
      active.swap(still);
      if (afterPass && !afterPass(image, reached)) break;
    }
    if (active.empty()) reached = range.end;  // every pixel converged: the range is done
  }
  progress.finish();
  if (truncated > 0) {
    throw RenderError(std::to_string(truncated) + " rays needed more than " + std::to_string(traversal_step_cap()) +
                      " BVH traversal steps; the image would be wrong, so none was written" +
                      (settings.megakernel ? " (the megakernel shares lavapipe's loop budget among a path's rays: "
                                             "use the wavefront kernels)"
                                           : ""));
  }
  return reached;
}

std::vector<WavefrontRenderer::Impl::Tile> WavefrontRenderer::Impl::tiles_of(uint32_t count, const std::vector<uint32_t>* list) const {
  std::vector<Tile> tiles;
  const uint32_t pixels = uint32_t(scene.width) * uint32_t(scene.height);
  if (!list) {
    for (uint32_t base = 0; base < count; base += tilePixels) {
      const uint32_t span = std::min(tilePixels, count - base);
      tiles.push_back({base, span, base, span});
    }
    return tiles;
  }
  for (uint32_t first = 0; first < list->size();) {
    Tile t;
    t.base = (*list)[first];
    t.span = std::min(tilePixels, pixels - t.base);
    t.first = first;
    while (first < list->size() && (*list)[first] < t.base + t.span) ++first;
    t.count = first - t.first;
    tiles.push_back(t);
  }
  return tiles;
}

double WavefrontRenderer::Impl::submit_tile(vk::CommandBuffer cb, const vk::raii::Fence& fence, const Tile& tile, uint32_t sample, uint32_t n,
                                            bool listed) {
  const uint32_t wavesPerSample = (tile.count + capacity - 1) / capacity;
  const uint32_t perWave = samples_per_wave(tile.count);
  const uint32_t dispatchesPerBounce = sorting ? 7 : 5;
  const uint32_t dispatchesPerWave = settings.megakernel ? 1 : 2 + dispatchesPerBounce * path_passes();
  const bool aovs = !scene.aovs.empty();
  cb.reset();
  cb.begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
  reserve_queries(n * wavesPerSample * dispatchesPerWave + 1);
  stageOf.clear();
  if (timestamps) cb.resetQueryPool(*queries, 0, queryCapacity);
  cb.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipelineLayout, 0, *set, {});
  cb.fillBuffer(buffers[BINDING_ACCUM]->handle(), 0, VK_WHOLE_SIZE, 0);
  if (aovs) cb.fillBuffer(buffers[BINDING_AOV_ACCUM]->handle(), 0, VK_WHOLE_SIZE, 0);
  cb.fillBuffer(buffers[BINDING_COUNTERS]->handle(), 0, VK_WHOLE_SIZE, 0);
  stage_barrier(cb);
  if (timestamps) cb.writeTimestamp(vk::PipelineStageFlagBits::eComputeShader, *queries, 0);
  // Waves start at pixel tile.first, or (listed) at entry 0 of the tile's part of the list.
  const uint32_t start0 = listed ? 0 : tile.first;
  for (uint32_t s = sample; s < sample + n; s += perWave) {
    const uint32_t samples = std::min(perWave, sample + n - s);
    for (uint32_t at = 0; at < tile.count; at += capacity)
      record_wave(cb, start0 + at, std::min(capacity, tile.count - at), s, samples, listed, tile.base);
  }
  const uint64_t accumBytes = uint64_t(tile.span) * sizeof(shader::PixelAccum);
  cb.copyBuffer(buffers[BINDING_ACCUM]->handle(), readAccum->handle(), vk::BufferCopy(0, 0, accumBytes));
  if (aovs) {
    cb.copyBuffer(buffers[BINDING_AOV_ACCUM]->handle(), readAovAccum->handle(),
                  vk::BufferCopy(0, 0, uint64_t(tile.span) * sizeof(shader::AovAccum)));
  }
  cb.copyBuffer(buffers[BINDING_COUNTERS]->handle(), readCounters->handle(), vk::BufferCopy(0, 0, readCounters->size()));
  vk::MemoryBarrier toHost(vk::AccessFlagBits::eTransferWrite, vk::AccessFlagBits::eHostRead);
  cb.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eHost, {}, toHost, {}, {});
  cb.end();
  auto t0 = std::chrono::steady_clock::now();
  ctx.submit_and_wait(cb, fence, true);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

uint32_t WavefrontRenderer::Impl::render_samples(ImageStats& image, uint64_t& truncated, Progress& progress, uint32_t first,
                                                 uint32_t end, const std::vector<uint32_t>* list, const PassHook& afterPass) {
  vk::raii::CommandBuffers cbs(ctx.device(), vk::CommandBufferAllocateInfo(*commandPool, vk::CommandBufferLevel::ePrimary, 1));
  vk::CommandBuffer cb = *cbs[0];
  vk::raii::Fence fence(ctx.device(), vk::FenceCreateInfo());
  const std::vector<Tile> tiles = tiles_of(uint32_t(image.pixels()), list);
  // The listed pixels of the only tile go up once; of several, each tile's before its submission.
  if (list && tiles.size() == 1) ctx.upload(*buffers[BINDING_PIXEL_LIST], list->data(), list->size() * sizeof(uint32_t));
  // With several tiles, a round's float sums wait here, tile by tile, until
  // the last tile has taken the round's samples too, and only then go into
  // the image: a device lost in the middle of a round leaves the image
  // holding the samples every pixel has (32 bytes a pixel, and 64 more with
  // AOV layers, on the host; one tile renders straight into the image).
  const bool held = tiles.size() > 1;
  const bool aovs = !scene.aovs.empty();
  std::vector<shader::PixelAccum> heldAccum(held ? image.pixels() : 0);
  std::vector<shader::AovAccum> heldAov(held && aovs ? image.pixels() : 0);
  uint32_t perSubmit = 1;
  uint32_t sample = first;
  try {
    while (sample < end) {
      const uint32_t n = std::min(perSubmit, end - sample);
      double longest = 0.0;
      uint64_t nonFinite = 0;
      for (const Tile& tile : tiles) {
        if (list && tiles.size() > 1)
          ctx.upload(*buffers[BINDING_PIXEL_LIST], list->data() + tile.first, tile.count * sizeof(uint32_t));
        double seconds = submit_tile(cb, fence, tile, sample, n, list != nullptr);
        // A ray past its share of the loop budget (trace_items.glsl): the same
        // samples again, one ray per invocation from now on.
        if (static_cast<const uint32_t*>(readCounters->mapped())[COUNTER_TRUNCATED] > 0 && tracingRays > 1) {
          ++oneRayReruns;
          tracingRays = 1;
          create_tracing_pipelines();
          seconds = submit_tile(cb, fence, tile, sample, n, list != nullptr);
        }
        const auto t0 = std::chrono::steady_clock::now();
        const auto* acc = static_cast<const shader::PixelAccum*>(readAccum->mapped());
        const auto* aov = static_cast<const shader::AovAccum*>(readAovAccum->mapped());
        if (held && &tile != &tiles.back()) {
          std::copy(acc, acc + tile.span, heldAccum.begin() + tile.base);
          if (aovs) std::copy(aov, aov + tile.span, heldAov.begin() + tile.base);
        }
        times.foldSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        ++times.submissions;
        nonFinite += fold_counters(truncated);
        collect_times();
        progress.add(uint64_t(n) * tile.count);
        longest = std::max(longest, seconds);
      }
      const auto t0 = std::chrono::steady_clock::now();
      for (const Tile& tile : tiles) {
        const bool last = &tile == &tiles.back();
        fold(image, tile, last ? static_cast<const shader::PixelAccum*>(readAccum->mapped()) : heldAccum.data() + tile.base,
             !aovs ? nullptr : last ? static_cast<const shader::AovAccum*>(readAovAccum->mapped()) : heldAov.data() + tile.base);
      }
      times.foldSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      image.nonFinite += nonFinite;
      sample += n;
      if (afterPass && sample < end && !afterPass(image, sample)) return sample;
      // Aim for submissions of about targetSubmitSeconds: long enough to keep
      // the device busy, short enough for a live progress line. Float sums in
      // the accumulators stay exact enough for a few hundred samples.
      if (longest < settings.targetSubmitSeconds * 0.5) perSubmit = std::min(perSubmit * 2, 256u);
    }
  } catch (DeviceLost& lost) {
    lost.reached = sample;  // every round before it was added whole
    lost.intact = true;
    throw;
  }
  return end;
}

void WavefrontRenderer::Impl::fold(ImageStats& image, const Tile& tile, const shader::PixelAccum* acc, const shader::AovAccum* aov) {
  for (size_t p = 0; p < tile.span; ++p) add_to_pixel(image, tile.base + p, acc[p]);
  AovLayout layout(image);
  if (!layout.empty())
    for (size_t p = 0; p < tile.span; ++p) add_aovs_to_pixel(image, layout, tile.base + p, aov[p]);
}

uint64_t WavefrontRenderer::Impl::fold_counters(uint64_t& truncated) {
  const auto* counters = static_cast<const uint32_t*>(readCounters->mapped());
  truncated += counters[COUNTER_TRUNCATED];
  auto count64 = [counters](uint32_t slot) { return uint64_t(counters[slot]) | uint64_t(counters[slot + 1]) << 32; };
  times.closestHitRays += count64(COUNTER_CLOSEST_RAYS);
  times.shadowRays += count64(COUNTER_SHADOW_RAYS);
  return counters[COUNTER_NONFINITE];
}

WavefrontRenderer::WavefrontRenderer(const VulkanContext& ctx, const CompiledScene& scene, const WavefrontSettings& settings)
    : impl_(std::make_unique<Impl>(ctx, scene, settings)) {}

WavefrontRenderer::~WavefrontRenderer() = default;

uint32_t WavefrontRenderer::render(ImageStats& image, SampleRange range, Progress& progress, const PassHook& afterPass) {
  if (image.width != impl_->scene.width || image.height != impl_->scene.height || image.aov_names() != impl_->scene.aovs)
    throw RenderError("internal error: the image to render into does not match the scene's size or layers");
  return impl_->render(image, range, progress, afterPass);
}

void WavefrontRenderer::update_params() {
  if (kernel_defining_params(impl_->scene.params) != kernel_defining_params(impl_->compiledParams))
    throw RenderError("internal error: the scene's parameters changed in a way its kernels were not made for");
  shader::SceneParams params = impl_->device_params();
  impl_->ctx.upload(*impl_->buffers[BINDING_SCENE], &params, sizeof(shader::SceneParams));
}

ImageStats WavefrontRenderer::render(Progress& progress) {
  ImageStats image(impl_->scene.width, impl_->scene.height, image_layers(impl_->scene.aovs));
  render(image, SampleRange{0, uint32_t(impl_->scene.spp)}, progress);
  return image;
}

const StageTimes& WavefrontRenderer::stage_times() const {
  return impl_->times;
}

uint64_t WavefrontRenderer::one_ray_reruns() const {
  return impl_->oneRayReruns;
}

}  // namespace wp
