// The photon mapper's first pass on the GPU (INTEGRATOR_PHOTONS): the
// photons kernel (photons.comp) traces batches of photons, a bounce per
// dispatch, and its records are put in the order the host's trace gives
// them (photon_pass.h), then balanced into the map the kernels gather from.
#include <algorithm>
#include <chrono>
#include <cstring>

#include "gpu/wavefront_impl.h"
#include "render/photon_pass.h"
#include "util/error.h"

// SPIR-V compiled from shaders/photons.comp at build time (see CMakeLists.txt).
#include "photons.spv.h"
#include "photons_spectral.spv.h"

namespace wp {

std::vector<shader::Photon> WavefrontRenderer::Impl::trace_photons(uint32_t count, uint32_t seed) {
  if (!*photons) photons = make_pipeline(kernel(WP_KERNEL(photons)));
  // Photons trace one ray an invocation: the scene's whole step cap, whatever
  // a megakernel's rays would share.
  shader::SceneParams params = device_params(true);
  ctx.upload(*buffers[BINDING_SCENE], &params, sizeof(shader::SceneParams));
  // A batch is the path slots; each photon leaves at most one record a
  // bounce, two texels in the shadow-ray buffer (three a shadow ray).
  static_assert(sizeof(shader::Photon) <= sizeof(shader::ShadowRay));
  const uint64_t recordBytes = uint64_t(capacity) * sizeof(shader::Photon);
  if (!readRecords) readRecords = std::make_unique<Buffer>(ctx, recordBytes, vk::BufferUsageFlagBits::eTransferDst, true);
  const bool timed = timestamps;
  timestamps = false;  // no stage of a render's
  std::vector<shader::Photon> out, batch;
  uint64_t truncated = 0;
  for (uint32_t first = 0; first < count; first += capacity) {
    const uint32_t n = std::min(capacity, count - first);
    // Photons first .. first + n of count, in path slots 0 .. n.
    KernelPush push{};
    push.waveStart = first;
    push.pathCount = n;
    push.sampleIndex = count;
    push.capacity = capacity;
    push.phase = PHOTONS_EMIT;
    push.photonSeed = seed;
    ctx.run_now([&](vk::CommandBuffer cb) {
      cb.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipelineLayout, 0, *set, {});
      dispatch(cb, photons, push, groups_for(n), StageTimes::kGenerate);
    });
    batch.clear();
    push.phase = PHOTONS_BOUNCE;
    // Every photon ends within max bounces + 1 traces (photon_bounce).
    for (uint32_t bounce = 0; bounce <= scene.params.image.z; ++bounce) {
      ctx.run_now([&](vk::CommandBuffer cb) {
        cb.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipelineLayout, 0, *set, {});
        cb.fillBuffer(buffers[BINDING_COUNTERS]->handle(), 0, VK_WHOLE_SIZE, 0);
        stage_barrier(cb);
        dispatch(cb, photons, push, groups_for(n), StageTimes::kExtend);
        cb.copyBuffer(buffers[BINDING_COUNTERS]->handle(), readCounters->handle(), vk::BufferCopy(0, 0, readCounters->size()));
        cb.copyBuffer(buffers[BINDING_SHADOW_RAYS]->handle(), readRecords->handle(), vk::BufferCopy(0, 0, uint64_t(n) * sizeof(shader::Photon)));
        vk::MemoryBarrier toHost(vk::AccessFlagBits::eTransferWrite, vk::AccessFlagBits::eHostRead);
        cb.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eHost, {}, toHost, {}, {});
      });
      const auto* counters = static_cast<const uint32_t*>(readCounters->mapped());
      truncated += counters[COUNTER_TRUNCATED];
      const uint32_t records = std::min(counters[COUNTER_PHOTON_RECORDS], n);
      const auto* from = static_cast<const shader::Photon*>(readRecords->mapped());
      batch.insert(batch.end(), from, from + records);
      if (counters[COUNTER_PHOTONS_ALIVE] == 0) break;
    }
    // Photon by photon (a record's axis holds its photon's slot), each
    // one's records bounce by bounce: the batch holds them bounce by bounce.
    std::stable_sort(batch.begin(), batch.end(), [](const shader::Photon& a, const shader::Photon& b) { return a.axis < b.axis; });
    for (shader::Photon& ph : batch) ph.axis += first;
    out.insert(out.end(), batch.begin(), batch.end());
  }
  timestamps = timed;
  params = device_params();
  ctx.upload(*buffers[BINDING_SCENE], &params, sizeof(shader::SceneParams));
  if (truncated > 0)
    throw RenderError(std::to_string(truncated) + " photon(s) outran the traversal step cap of " + std::to_string(scene.params.counts.z) +
                      " on " + ctx.info().name + "; the photon map would be wrong");
  return out;
}

void WavefrontRenderer::Impl::build_photon_map() {
  const auto start = std::chrono::steady_clock::now();
  const bool kernels = settings.photonPass == PhotonPass::Kernels || (settings.photonPass == PhotonPass::Auto && !cpu_device());
  std::vector<shader::Photon> map = balance_photons(kernels ? trace_photons(scene.photonCount, scene.photonSeed) : wp::trace_photons(scene));
  photonMapSize = uint32_t(map.size());
  add_texels(BINDING_PHOTONS, map, "photon map");
  vk::BufferView view = *views[BINDING_PHOTONS];
  ctx.device().updateDescriptorSets(
      vk::WriteDescriptorSet(*set, BINDING_PHOTONS, 0, 1, vk::DescriptorType::eUniformTexelBuffer, nullptr, nullptr, &view), {});
  shader::SceneParams params = device_params();
  ctx.upload(*buffers[BINDING_SCENE], &params, sizeof(shader::SceneParams));
  photonPassSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<shader::Photon> WavefrontRenderer::trace_photons(uint32_t count, uint32_t seed) {
  return impl_->trace_photons(count, seed);
}

}  // namespace wp
