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

void WavefrontRenderer::Impl::record_wave(vk::CommandBuffer cb, uint32_t waveStart, uint32_t pathCount, uint32_t sampleIndex, bool listed) {
  KernelPush push{};
  push.waveStart = waveStart;
  push.pathCount = pathCount;
  push.sampleIndex = sampleIndex;
  push.capacity = capacity;
  push.phase = listed ? GENERATE_FROM_LIST : GENERATE_CONSECUTIVE;
  if (settings.megakernel) return dispatch(cb, megakernel, push, interleaved_groups(pathCount), StageTimes::kMegakernel);
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
  dispatch(cb, accumulate, push, groups_for(pathCount), StageTimes::kAccumulate);
}

uint32_t WavefrontRenderer::Impl::render(ImageStats& image, SampleRange range, Progress& progress, const PassHook& afterPass) {
  const uint32_t pixels = uint32_t(scene.width) * uint32_t(scene.height);
  uint64_t truncated = 0;
  times = StageTimes{};
  uint32_t reached = range.begin;
  if (!scene.adaptive.enabled()) {
    reached = render_samples(image, truncated, progress, range.begin, range.end, pixels, false, afterPass);
  } else {
    // Batches of the whole render's grid (multiples of the batch size from
    // sample 0), so that a range resumed at a batch's start continues it.
    std::vector<uint32_t> active = unconverged_pixels(image, range.begin, scene.adaptive);
    const uint32_t batch = uint32_t(scene.adaptive.batch);
    while (reached < range.end && !active.empty()) {
      uint32_t next = std::min((reached / batch + 1) * batch, range.end);
      ctx.upload(*buffers[BINDING_PIXEL_LIST], active.data(), active.size() * sizeof(uint32_t));
      render_samples(image, truncated, progress, reached, next, uint32_t(active.size()), true, {});
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

uint32_t WavefrontRenderer::Impl::render_samples(ImageStats& image, uint64_t& truncated, Progress& progress, uint32_t first,
                                                 uint32_t end, uint32_t count, bool listed, const PassHook& afterPass) {
  vk::raii::CommandBuffers cbs(ctx.device(), vk::CommandBufferAllocateInfo(*commandPool, vk::CommandBufferLevel::ePrimary, 1));
  vk::CommandBuffer cb = *cbs[0];
  vk::raii::Fence fence(ctx.device(), vk::FenceCreateInfo());
  uint32_t perSubmit = 1;
  const uint32_t wavesPerSample = (count + capacity - 1) / capacity;
  const uint32_t dispatchesPerBounce = sorting ? 7 : 5;
  const uint32_t dispatchesPerWave = settings.megakernel ? 1 : 2 + dispatchesPerBounce * path_passes();
  const bool aovs = !scene.aovs.empty();
  for (uint32_t sample = first; sample < end;) {
    uint32_t n = std::min(perSubmit, end - sample);
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
    for (uint32_t s = sample; s < sample + n; ++s)
      for (uint32_t start = 0; start < count; start += capacity) record_wave(cb, start, std::min(capacity, count - start), s, listed);
    cb.copyBuffer(buffers[BINDING_ACCUM]->handle(), readAccum->handle(), vk::BufferCopy(0, 0, readAccum->size()));
    if (aovs) cb.copyBuffer(buffers[BINDING_AOV_ACCUM]->handle(), readAovAccum->handle(), vk::BufferCopy(0, 0, readAovAccum->size()));
    cb.copyBuffer(buffers[BINDING_COUNTERS]->handle(), readCounters->handle(), vk::BufferCopy(0, 0, readCounters->size()));
    vk::MemoryBarrier toHost(vk::AccessFlagBits::eTransferWrite, vk::AccessFlagBits::eHostRead);
    cb.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eHost, {}, toHost, {}, {});
    cb.end();
    auto t0 = std::chrono::steady_clock::now();
    ctx.device().resetFences(*fence);
    ctx.queue().submit(vk::SubmitInfo({}, {}, cb), *fence);
    while (ctx.device().waitForFences(*fence, VK_TRUE, 1000000000ull) == vk::Result::eTimeout) {
    }
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // A ray past its share of the loop budget (trace_items.glsl): the same
    // samples again, one ray per invocation from now on.
    if (static_cast<const uint32_t*>(readCounters->mapped())[COUNTER_TRUNCATED] > 0 && tracingRays > 1) {
      ++oneRayReruns;
      tracingRays = 1;
      create_tracing_pipelines();
      continue;
    }
    fold(image, truncated);
    collect_times();
    sample += n;
    progress.add(uint64_t(n) * count);
    if (afterPass && sample < end && !afterPass(image, sample)) return sample;
    // Aim for submissions of about targetSubmitSeconds: long enough to keep
    // the device busy, short enough for a live progress line. Float sums in
    // the accumulators stay exact enough for a few hundred samples.
    if (seconds < settings.targetSubmitSeconds * 0.5) perSubmit = std::min(perSubmit * 2, 256u);
  }
  return end;
}

void WavefrontRenderer::Impl::fold(ImageStats& image, uint64_t& truncated) {
  const auto* acc = static_cast<const shader::PixelAccum*>(readAccum->mapped());
  for (size_t p = 0; p < image.pixels(); ++p) add_to_pixel(image, p, acc[p]);
  AovLayout layout(image);
  if (!layout.empty()) {
    const auto* aov = static_cast<const shader::AovAccum*>(readAovAccum->mapped());
    for (size_t p = 0; p < image.pixels(); ++p) add_aovs_to_pixel(image, layout, p, aov[p]);
  }
  const auto* counters = static_cast<const uint32_t*>(readCounters->mapped());
  truncated += counters[COUNTER_TRUNCATED];
  image.nonFinite += counters[COUNTER_NONFINITE];
  auto count64 = [counters](uint32_t slot) { return uint64_t(counters[slot]) | uint64_t(counters[slot + 1]) << 32; };
  times.closestHitRays += count64(COUNTER_CLOSEST_RAYS);
  times.shadowRays += count64(COUNTER_SHADOW_RAYS);
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
  shader::SceneParams params = impl_->scene.params;
  params.counts.z = impl_->traversal_step_cap();
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
