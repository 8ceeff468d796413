// Work that only the benchmarks, the tests and `wavepath test` ask of the GPU
// renderer: closest and any hits of given rays (the ray caster, raycast.comp)
// and the probes of probes.glsl (probe.comp).
#include <algorithm>
#include <cstring>

#include "gpu/wavefront_impl.h"
#include "render/shader_cpp.h"

// SPIR-V compiled from shaders/*.comp at build time (see CMakeLists.txt).
#include "raycast.spv.h"
#include "raycast_spectral.spv.h"
#include "probe.spv.h"
#include "probe_spectral.spv.h"

namespace wp {

const vk::raii::Pipeline& WavefrontRenderer::Impl::ray_caster(bool single, bool anyHit) {
  vk::raii::Pipeline& p = anyHit ? (single ? occludeSingle : occlude) : (single ? raycastSingle : raycast);
  if (!*p) p = make_pipeline(kernel(WP_KERNEL(raycast), Folding::Branches), {single, true, anyHit});
  return p;
}

std::vector<shader::Hit> WavefrontRenderer::Impl::cast_rays(const std::vector<shader::ShadowRay>& rays, uint64_t* truncated, double* kernelSeconds,
                                   bool coherent, bool anyHit) {
  if (coherent) return run_on_rays(ray_caster(true, anyHit), nullptr, rays, truncated, kernelSeconds);
  return run_on_rays(ray_caster(false, anyHit), &ray_caster(true, anyHit), rays, truncated, kernelSeconds);
}

// Rays as the kernels read them (kernel.glsl's read_shadow_ray), field by
// field, into mapped memory.
void WavefrontRenderer::Impl::write_shadow_rays(void* mapped, const shader::ShadowRay* rays, uint32_t n) const {
  const uint64_t texels = shadow_ray_bytes(compiledParams) / 16u;
  auto* out = static_cast<glm::uvec4*>(mapped);
  for (uint32_t i = 0; i < n; ++i) {
    const shader::ShadowRay& r = rays[i];
    glm::uvec4* t = out + i * texels;
    t[0] = glm::uvec4(glm::floatBitsToUint(r.origin), glm::floatBitsToUint(r.tmax));
    t[1] = glm::uvec4(glm::floatBitsToUint(r.dir), r.path);
    t[2] = glm::uvec4(glm::floatBitsToUint(glm::vec3(r.contribution)), r.media);
    if (texels > 3) t[3] = glm::uvec4(glm::floatBitsToUint(r.contribution.w), 0u, 0u, 0u);
  }
}

std::vector<shader::Hit> WavefrontRenderer::Impl::run_on_rays(const vk::raii::Pipeline& kernel, const vk::raii::Pipeline* single,
                                     const std::vector<shader::ShadowRay>& rays, uint64_t* truncated, double* kernelSeconds) {
  std::vector<shader::Hit> hits(rays.size());
  const bool timed = timestamps;
  reserve_queries(2);
  timestamps = false;  // no per-stage bookkeeping: only the kernel's dispatch is timed
  double kernelTime = 0.0;
  const Buffer& rayBuffer = *buffers[BINDING_SHADOW_RAYS];
  const uint64_t hitBytes = hit_record_bytes(scene);
  if (!readHits) readHits = std::make_unique<Buffer>(ctx, uint64_t(capacity) * hitBytes, vk::BufferUsageFlagBits::eTransferDst, true);
  if (!rayBuffer.mapped() && !rayStaging)
    rayStaging = std::make_unique<Buffer>(ctx, uint64_t(capacity) * shadow_ray_bytes(compiledParams), vk::BufferUsageFlagBits::eTransferSrc, true);
  // One chunk through `p`: the rays truncated, and the kernel's GPU time added to kernelTime.
  auto run_chunk = [&](const vk::raii::Pipeline& p, uint32_t n, uint32_t perInvocation) {
    // The rays' upload is submitted and waited for on its own: a timestamp
    // at the compute stage need not wait for a copy recorded before it, and
    // on a discrete GPU the copy crosses PCIe (32 bytes a ray), which can
    // take longer than the walks of camera rays.
    ctx.run_now([&](vk::CommandBuffer cb) {
      if (!rayBuffer.mapped()) cb.copyBuffer(rayStaging->handle(), rayBuffer.handle(), vk::BufferCopy(0, 0, n * shadow_ray_bytes(compiledParams)));
      cb.fillBuffer(buffers[BINDING_COUNTERS]->handle(), 0, VK_WHOLE_SIZE, 0);
    });
    ctx.run_now([&](vk::CommandBuffer cb) {
      stage_barrier(cb);  // the upload's writes, visible to the kernel
      cb.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipelineLayout, 0, *set, {});
      KernelPush push{};
      push.pathCount = n;
      push.capacity = capacity;
      if (timed) {
        cb.resetQueryPool(*queries, 0, 2);
        cb.writeTimestamp(vk::PipelineStageFlagBits::eComputeShader, *queries, 0);
      }
      dispatch(cb, p, push, tracing_groups(n, perInvocation), StageTimes::kExtend);
      if (timed) cb.writeTimestamp(vk::PipelineStageFlagBits::eComputeShader, *queries, 1);
      // The chunk's hits, and (instanced scenes) their instances after the capacity's hits (kernel.glsl's write_hit).
      std::vector<vk::BufferCopy> parts{vk::BufferCopy(0, 0, uint64_t(n) * 16u)};
      if (hitBytes > 16u) parts.emplace_back(uint64_t(capacity) * 16u, uint64_t(capacity) * 16u, uint64_t(n) * 16u);
      cb.copyBuffer(buffers[BINDING_HITS]->handle(), readHits->handle(), parts);
      cb.copyBuffer(buffers[BINDING_COUNTERS]->handle(), readCounters->handle(), vk::BufferCopy(0, 0, readCounters->size()));
      vk::MemoryBarrier toHost(vk::AccessFlagBits::eTransferWrite, vk::AccessFlagBits::eHostRead);
      cb.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eHost, {}, toHost, {}, {});
    });
    if (timed) {
      uint64_t ticks[2] = {0, 0};
      if (ctx.device().getDispatcher()->vkGetQueryPoolResults(*ctx.device(), *queries, 0, 2, sizeof(ticks), ticks, sizeof(uint64_t),
                                                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS)
        kernelTime += double(ticks[1] - ticks[0]) * timestampPeriodNs * 1e-9;
    }
    return static_cast<const uint32_t*>(readCounters->mapped())[COUNTER_TRUNCATED];
  };
  const uint32_t perInvocation = single ? tracingRays : 1u;
  uint64_t lost = 0;
  for (size_t start = 0; start < rays.size(); start += capacity) {
    uint32_t n = uint32_t(std::min<size_t>(capacity, rays.size() - start));
    write_shadow_rays(rayBuffer.mapped() ? rayBuffer.mapped() : rayStaging->mapped(), rays.data() + start, n);
    uint32_t chunkLost = run_chunk(kernel, n, perInvocation);
    // A ray past its share of the loop budget: the chunk again, one ray per invocation.
    if (chunkLost > 0 && perInvocation > 1) {
      ++oneRayReruns;
      chunkLost = run_chunk(*single, n, 1);
    }
    const auto* words = static_cast<const uint32_t*>(readHits->mapped());
    for (uint32_t i = 0; i < n; ++i) {
      shader::Hit& h = hits[start + i];
      std::memcpy(&h, words + 4 * i, 16);
      h.instance = hitBytes > 16 ? words[4 * (capacity + i)] : WP_INVALID;
    }
    lost += chunkLost;
  }
  if (truncated) *truncated = lost;
  if (kernelSeconds) *kernelSeconds = kernelTime;
  timestamps = timed;
  return hits;
}

std::vector<shader::Hit> WavefrontRenderer::cast_shadow_rays(const std::vector<shader::ShadowRay>& rays, uint64_t* truncated,
                                                             double* kernelSeconds, bool coherent) {
  return impl_->cast_rays(rays, truncated, kernelSeconds, coherent, true);
}

std::vector<shader::Hit> WavefrontRenderer::cast_rays(const std::vector<shader::ShadowRay>& rays, uint64_t* truncated,
                                                      double* kernelSeconds, bool coherent) {
  return impl_->cast_rays(rays, truncated, kernelSeconds, coherent, false);
}

std::vector<shader::Hit> WavefrontRenderer::run_probes(const std::vector<shader::ShadowRay>& queries) {
  if (!*impl_->probe) impl_->probe = impl_->make_pipeline(impl_->kernel(WP_KERNEL(probe)));
  return impl_->run_on_rays(impl_->probe, nullptr, queries, nullptr, nullptr);
}

std::vector<glm::vec3> WavefrontRenderer::eval_textures(const std::vector<TextureQuery>& queries) {
  std::vector<shader::ShadowRay> rays(queries.size());
  for (size_t i = 0; i < queries.size(); ++i) {
    rays[i].origin = queries[i].p;
    rays[i].dir = glm::vec3(queries[i].uv, 0.0f);
    rays[i].path = (PROBE_TEXTURE << PROBE_KIND_SHIFT) | queries[i].texture;
  }
  std::vector<shader::Hit> out = run_probes(rays);
  std::vector<glm::vec3> colors(out.size());
  for (size_t i = 0; i < out.size(); ++i) colors[i] = glm::vec3(out[i].t, out[i].u, out[i].v);
  return colors;
}

}  // namespace wp
