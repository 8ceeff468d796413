// The GPU renderer's resources and pipelines: buffers and their texel views,
// the descriptor set, each kernel's pipeline specialized to the scene and the
// device, timestamps, and the driver's statistics of each kernel.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gpu/specialize.h"
#include "gpu/wavefront_impl.h"
#include "render/shader_cpp.h"
#include "util/error.h"
#include "util/fault.h"

// SPIR-V compiled from shaders/*.comp at build time (see CMakeLists.txt).
#include "accumulate.spv.h"
#include "accumulate_spectral.spv.h"
#include "connect.spv.h"
#include "connect_spectral.spv.h"
#include "connect_multi.spv.h"
#include "connect_multi_spectral.spv.h"
#include "extend.spv.h"
#include "extend_spectral.spv.h"
#include "generate.spv.h"
#include "generate_spectral.spv.h"
#include "megakernel.spv.h"
#include "megakernel_spectral.spv.h"
#include "prepare.spv.h"
#include "prepare_spectral.spv.h"
#include "shade.spv.h"
#include "shade_spectral.spv.h"
#include "sort.spv.h"
#include "sort_spectral.spv.h"

namespace wp {

namespace {

std::string memory_text(uint64_t bytes) {
  char text[32];
  if (bytes < (1u << 20)) std::snprintf(text, sizeof text, "%.0f KiB", std::ceil(double(bytes) / 1024.0));
  else std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / double(1 << 20));
  return text;
}

// The device, and the memory it has, for messages.
std::string device_memory(const VulkanContext& ctx) {
  if (fault::device_memory_limit() > 0) return ctx.info().name + " (WAVEPATH_FAULT gives it " + memory_text(fault::device_memory_limit()) + ")";
  return ctx.info().name + " (" + memory_text(ctx.info().deviceLocalMemory) + " of device-local memory)";
}

}  // namespace

WavefrontRenderer::Impl::Impl(const VulkanContext& c, const CompiledScene& s, const WavefrontSettings& st) : ctx(c), scene(s), settings(st) {
  const uint64_t maxRange = ctx.info().maxStorageBufferRange;
  const uint32_t pixels = uint32_t(scene.width) * uint32_t(scene.height);
  if (pixels == 0) throw RenderError("the image has no pixels");  // path slots (and ray batches) come from pixels
  if (settings.workgroupSize == 0 || settings.workgroupSize > ctx.info().maxComputeWorkGroupInvocations) {
    throw RenderError("workgroup size " + std::to_string(settings.workgroupSize) + " is not supported by " + ctx.info().name);
  }
  // Each path may cast one shadow ray per light sample: their buffer and
  // their dispatch bound the paths per wave too.
  lightSamples = std::max(1u, scene.params.mode.w);
  // Paths and shadow rays are also read through texel views (bindings.glsl).
  const uint64_t maxViewBytes = uint64_t(ctx.info().maxTexelBufferElements) * 16u;
  sorting = sort_by_material();
  // A photon map traced here takes batches of path slots: more than a small
  // image's pixels (the batches' dispatches, not their photons, cost on CPU devices).
  // A small image's waves hold several samples (samples_per_wave).
  const uint64_t samplesPerWave = std::min<uint64_t>(std::max(scene.spp, 1), kMaxSamplesPerWave);
  const uint64_t slots = std::max<uint64_t>({pixels, scene.photonMapLeftToDevice ? kPhotonBatch : 0,
                                             std::min<uint64_t>(kSmallImageWavePaths, uint64_t(pixels) * samplesPerWave)});
  capacity = std::min<uint64_t>({slots, settings.maxPathsPerWave, std::min(maxRange, maxViewBytes) / path_state_bytes(compiledParams),
                                 std::min(maxRange, maxViewBytes) / (shadow_ray_bytes(compiledParams) * lightSamples),
                                 uint64_t(ctx.info().maxComputeWorkGroupCount) * settings.workgroupSize / lightSamples,
                                 std::min<uint64_t>(ctx.info().maxTexelBufferElements, maxRange / sizeof(uint32_t)) / queue_count()});
  try {
    create_scene_buffers();
  } catch (const DeviceOutOfMemory&) {
    throw RenderError("out of device memory: the scene's arrays (BVH, primitives, materials, textures) need " +
                      memory_text(measure(&Impl::create_scene_buffers)) + ", more than " + device_memory(ctx) + " holds");
  }
  fit_tile_buffers(maxRange);
  create_pipelines();
  commandPool = vk::raii::CommandPool(ctx.device(), vk::CommandPoolCreateInfo(
                                                        vk::CommandPoolCreateFlagBits::eResetCommandBuffer, ctx.queue_family()));
  auto props = ctx.physical().getProperties();
  auto families = ctx.physical().getQueueFamilyProperties();
  timestamps = props.limits.timestampComputeAndGraphics && families[ctx.queue_family()].timestampValidBits > 0;
  timestampPeriodNs = props.limits.timestampPeriod;
  if (scene.photonMapLeftToDevice) build_photon_map();
}

void WavefrontRenderer::Impl::reserve_queries(uint32_t count) {
  if (!timestamps || count <= queryCapacity) return;
  queryCapacity = std::max(count, queryCapacity * 2);
  queries = vk::raii::QueryPool(ctx.device(), vk::QueryPoolCreateInfo({}, vk::QueryType::eTimestamp, queryCapacity));
}

void WavefrontRenderer::Impl::stamp(vk::CommandBuffer cb, Stage stage) {
  if (!timestamps) return;
  stageOf.push_back(stage);
  cb.writeTimestamp(vk::PipelineStageFlagBits::eComputeShader, *queries, uint32_t(stageOf.size()));
}

void WavefrontRenderer::Impl::collect_times() {
  if (!timestamps || stageOf.empty()) return;
  std::vector<uint64_t> ticks(stageOf.size() + 1);
  auto result = ctx.device().getDispatcher()->vkGetQueryPoolResults(
      *ctx.device(), *queries, 0, uint32_t(ticks.size()), ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
      VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
  if (result != VK_SUCCESS) return;
  for (size_t i = 0; i < stageOf.size(); ++i) {
    times.seconds[stageOf[i]] += double(ticks[i + 1] - ticks[i]) * timestampPeriodNs * 1e-9;
    times.dispatches[stageOf[i]] += 1;
  }
}

bool WavefrontRenderer::Impl::is_texel_binding(uint32_t binding) {
  switch (binding) {
    case BINDING_NODES:
    case BINDING_WIDE_NODES:
    case BINDING_TRIANGLES:
    case BINDING_TRIANGLE_SHADING:
    case BINDING_VERTEX_DATA:
    case BINDING_SPHERES:
    case BINDING_INSTANCES:
    case BINDING_MATERIALS:
    case BINDING_EMITTERS:
    case BINDING_TEXTURES:
    case BINDING_POINT_LIGHTS:
    case BINDING_MEDIA:
    case BINDING_VOLUMES:
    case BINDING_PHOTONS:
    case BINDING_TEXELS:
    case BINDING_FLOAT_TABLES:
    case BINDING_SPECTRA:
    case BINDING_SPECTRAL_COLOURS:
    case BINDING_PATH_TEXELS:
    case BINDING_HIT_TEXELS:
    case BINDING_SHADOW_RAY_TEXELS:
    case BINDING_QUEUE_TEXELS:
      return true;
    default:
      return false;
  }
}

uint32_t WavefrontRenderer::Impl::walk_records_of(uint32_t binding) {
  switch (binding) {
    case BINDING_NODE_WORDS:
      return BINDING_NODES;
    case BINDING_WIDE_NODE_WORDS:
      return BINDING_WIDE_NODES;
    case BINDING_TRIANGLE_WORDS:
      return BINDING_TRIANGLES;
    default:
      return binding;
  }
}

vk::DescriptorType WavefrontRenderer::Impl::descriptor_type(uint32_t binding) {
  if (binding == BINDING_SCENE) return vk::DescriptorType::eUniformBuffer;
  return is_texel_binding(binding) ? vk::DescriptorType::eUniformTexelBuffer : vk::DescriptorType::eStorageBuffer;
}

void WavefrontRenderer::Impl::make_buffer(std::unique_ptr<Buffer>& slot, uint64_t bytes, vk::BufferUsageFlags usage, bool hostVisible) {
  if (measured) {
    *measured += std::max<uint64_t>(bytes, 16);
    return;
  }
  slot = std::make_unique<Buffer>(ctx, bytes, usage, hostVisible);
}

void WavefrontRenderer::Impl::add_work(uint32_t binding, uint64_t bytes, vk::BufferUsageFlags extra) {
  using U = vk::BufferUsageFlagBits;
  make_buffer(buffers[binding], bytes, U::eStorageBuffer | U::eTransferDst | U::eTransferSrc | extra, false);
}

void WavefrontRenderer::Impl::add_readable_work(uint32_t binding, uint32_t view, uint64_t bytes, vk::Format format) {
  add_work(binding, bytes, vk::BufferUsageFlagBits::eUniformTexelBuffer);
  if (measured) return;
  views[view] = vk::raii::BufferView(ctx.device(), vk::BufferViewCreateInfo({}, buffers[binding]->handle(), format, 0, VK_WHOLE_SIZE));
}

uint64_t WavefrontRenderer::Impl::measure(void (Impl::*create)()) {
  uint64_t bytes = 0;
  measured = &bytes;
  (this->*create)();
  measured = nullptr;
  return bytes;
}

void WavefrontRenderer::Impl::create_scene_buffers() {
  if (!measured) {
    buffers.resize(BINDING_COUNT);
    for (uint32_t b = 0; b < BINDING_COUNT; ++b) views.emplace_back(nullptr);
  }
  make_buffer(buffers[BINDING_SCENE], sizeof(shader::SceneParams), vk::BufferUsageFlagBits::eUniformBuffer | vk::BufferUsageFlagBits::eTransferDst,
              false);
  if (!measured) {
    shader::SceneParams params = device_params();
    ctx.upload(*buffers[BINDING_SCENE], &params, sizeof(shader::SceneParams));
  }
  add_texels(BINDING_NODES, scene.nodes, "BVH nodes");
  add_texels(BINDING_WIDE_NODES, scene.wideNodes, "wide BVH nodes");
  add_texels(BINDING_TRIANGLES, scene.triangles, "primitives");
  add_texels(BINDING_TRIANGLE_SHADING, scene.triangleShading, "vertex normals and UVs");
  add_texels(BINDING_VERTEX_DATA, scene.triangleVertexData, "tangents, vertex colours and second UVs");
  add_texels(BINDING_SPHERES, scene.spheres, "spheres");
  add_texels(BINDING_INSTANCES, scene.instances, "instances");
  add_texels(BINDING_MATERIALS, scene.materials, "materials");
  add_texels(BINDING_EMITTERS, scene.emitters, "emitters");
  add_texels(BINDING_TEXTURES, scene.textures, "textures");
  add_texels(BINDING_POINT_LIGHTS, scene.pointLights, "point lights");
  add_texels(BINDING_MEDIA, scene.media, "media");
  add_texels(BINDING_VOLUMES, scene.volumeWords, "media's density grids", vk::Format::eR32Uint);
  add_texels(BINDING_PHOTONS, scene.photons, "photon map");
  add_texels(BINDING_TEXELS, scene.texels, "image texels", vk::Format::eR32G32Uint);
  add_texels(BINDING_FLOAT_TABLES, scene.floatTables, "float tables", vk::Format::eR32Sfloat);
  add_texels(BINDING_SPECTRA, scene.spectra.texels, scene.spectra.count, "spectral tables", vk::Format::eR32G32B32A32Sfloat);
  add_texels(BINDING_SPECTRAL_COLOURS, scene.spectralColours, "spectral colour memo", vk::Format::eR32G32B32A32Sfloat);
}

void WavefrontRenderer::Impl::create_tile_buffers() {
  const bool aovs = !scene.aovs.empty();
  add_work(BINDING_PIXEL_LIST, uint64_t(tilePixels) * sizeof(uint32_t));
  add_readable_work(BINDING_PATHS, BINDING_PATH_TEXELS, uint64_t(capacity) * path_state_bytes(compiledParams));
  add_readable_work(BINDING_HITS, BINDING_HIT_TEXELS, uint64_t(capacity) * hit_record_bytes(scene));
  // Queues 0 and 1, and with sorting by material class each sort key's.
  add_readable_work(BINDING_QUEUES, BINDING_QUEUE_TEXELS, uint64_t(capacity) * queue_count() * sizeof(uint32_t), vk::Format::eR32Uint);
  add_work(BINDING_SORT, SORT_KEYS * sizeof(uint32_t));
  add_readable_work(BINDING_SHADOW_RAYS, BINDING_SHADOW_RAY_TEXELS, uint64_t(capacity) * lightSamples * shadow_ray_bytes(compiledParams));
  add_work(BINDING_COUNTERS, COUNTER_COUNT * sizeof(uint32_t));
  add_work(BINDING_INDIRECT, INDIRECT_SLOTS * 3 * sizeof(uint32_t), vk::BufferUsageFlagBits::eIndirectBuffer);
  const uint64_t accumBytes = uint64_t(tilePixels) * sizeof(shader::PixelAccum);
  add_work(BINDING_ACCUM, accumBytes);
  make_buffer(readAccum, accumBytes, vk::BufferUsageFlagBits::eTransferDst, true);
  // AOV layers: a first-hit record per path slot and sums per pixel of the
  // tile; a placeholder each where the render records none.
  const uint64_t aovAccumBytes = aovs ? uint64_t(tilePixels) * sizeof(shader::AovAccum) : sizeof(shader::AovAccum);
  add_work(BINDING_AOV_SAMPLES, (aovs ? uint64_t(capacity) : 1u) * sizeof(shader::AovSample));
  add_work(BINDING_AOV_ACCUM, aovAccumBytes);
  make_buffer(readAovAccum, aovAccumBytes, vk::BufferUsageFlagBits::eTransferDst, true);
  make_buffer(readCounters, COUNTER_COUNT * sizeof(uint32_t), vk::BufferUsageFlagBits::eTransferDst, true);
}

void WavefrontRenderer::Impl::release_tile_buffers() {
  for (uint32_t b : {BINDING_PATH_TEXELS, BINDING_HIT_TEXELS, BINDING_QUEUE_TEXELS, BINDING_SHADOW_RAY_TEXELS}) views[b] = nullptr;
  for (uint32_t b : {BINDING_PIXEL_LIST, BINDING_PATHS, BINDING_HITS, BINDING_QUEUES, BINDING_SORT, BINDING_SHADOW_RAYS, BINDING_COUNTERS,
                     BINDING_INDIRECT, BINDING_ACCUM, BINDING_AOV_SAMPLES, BINDING_AOV_ACCUM})
    buffers[b].reset();
  readAccum.reset();
  readAovAccum.reset();
  readCounters.reset();
}

void WavefrontRenderer::Impl::fit_tile_buffers(uint64_t maxRange) {
  // The image in tiles of consecutive pixels, as many as the accumulators
  // (and the AOVs') may hold in one storage buffer: an image too large for
  // one is rendered tile after tile each round of samples (render_samples).
  const uint32_t pixels = uint32_t(scene.width) * uint32_t(scene.height);
  const bool aovs = !scene.aovs.empty();
  uint64_t tileLimit = maxRange / (aovs ? std::max(sizeof(shader::PixelAccum), sizeof(shader::AovAccum)) : sizeof(shader::PixelAccum));
  if (settings.maxTilePixels > 0) tileLimit = std::min<uint64_t>(tileLimit, settings.maxTilePixels);
  tilePixels = uint32_t(std::min<uint64_t>(pixels, tileLimit));
  // Where the device has no room for them, tiles of half as many pixels
  // (and no more path slots than a tile's pixels), down to one row: tiles
  // render the same image as one.
  const uint32_t row = uint32_t(scene.width);
  const uint32_t asked = tilePixels;
  uint64_t askedBytes = 0;
  for (;;) {
    try {
      create_tile_buffers();
      break;
    } catch (const DeviceOutOfMemory&) {
      release_tile_buffers();
      const uint64_t need = measure(&Impl::create_tile_buffers);
      if (askedBytes == 0) askedBytes = need;
      if (tilePixels <= row) {
        throw RenderError("out of device memory: even tiles of one row (" + std::to_string(tilePixels) + " pixels) need " + memory_text(need) +
                          " of buffers beside the scene's " + memory_text(measure(&Impl::create_scene_buffers)) + ", more than " +
                          device_memory(ctx) + " holds");
      }
      tilePixels = std::max(row, tilePixels / 2);
      capacity = std::min(capacity, tilePixels);
    }
  }
  if (tilePixels < asked) {
    std::fprintf(stderr, "wavepath: %s: out of device memory for tiles of %u pixels (%s of buffers); rendering in tiles of %u pixels\n",
                 ctx.info().name.c_str(), asked, memory_text(askedBytes).c_str(), tilePixels);
  }
}

shader::SceneParams WavefrontRenderer::Impl::device_params(bool wholeCap) const {
  shader::SceneParams params = scene.params;
  if (!wholeCap) params.counts.z = traversal_step_cap();
  if (scene.photonMapLeftToDevice) params.photons.x = photonMapSize;
  return params;
}

uint32_t WavefrontRenderer::Impl::traversal_step_cap() const {
  const uint32_t cap = scene.params.counts.z;
  // Only lavapipe has a loop budget for the megakernel's rays to share.
  if (!settings.megakernel || !cpu_device()) return cap;
  if (scene.params.kinds.w & KIND_BIT(FEATURE_MEDIA))
    throw RenderError("the megakernel cannot fit participating media's tracking into lavapipe's loop budget; use the wavefront kernels");
  const uint64_t bounces = scene.params.image.z;
  const uint64_t perRay = megakernel_steps_per_ray(megakernel_samples());
  if (perRay < kMegakernelMinimumCap) {
    throw RenderError("the megakernel variant fits " + std::to_string(bounces) + " bounces into lavapipe's loop budget only with " +
                      std::to_string(perRay) + " traversal steps per ray (at least " + std::to_string(kMegakernelMinimumCap) +
                      " needed); use fewer bounces or the wavefront kernels");
  }
  return uint32_t(std::min<uint64_t>(cap, perRay));
}

uint64_t WavefrontRenderer::Impl::megakernel_steps_per_ray(uint64_t paths) const {
  const uint64_t bounces = scene.params.image.z, lightSamples = std::max(1u, scene.params.mode.w);
  // The photon mapper's one gather per path takes its search's share first.
  const uint64_t gather = scene.params.mode.x == INTEGRATOR_PHOTONS ? paths * PHOTON_SEARCH_STEPS_MAX : 0u;
  const uint64_t budget = TRAVERSAL_STEP_BUDGET - std::min<uint64_t>(TRAVERSAL_STEP_BUDGET, gather);
  const uint64_t traversals = paths * (bounces + 1 + bounces * lightSamples);
  return (budget - std::min(budget, paths * (bounces + 1))) / traversals;
}

uint32_t WavefrontRenderer::Impl::megakernel_samples() const {
  if (!settings.megakernel) return 1u;
  uint32_t k = std::max(1u, settings.megakernelSamples);
  // On lavapipe an invocation's paths share its loop budget: fewer of them
  // where the settings' would leave each ray too few steps (deep bounces,
  // the photon mapper's gathers).
  if (cpu_device())
    while (k > 1u && megakernel_steps_per_ray(k) < kMegakernelMinimumCap) --k;
  return k;
}

uint32_t WavefrontRenderer::Impl::rays_per_invocation() const {
  if (settings.raysPerInvocation != 0) return settings.raysPerInvocation;
  bool several = cpu_device() && scene.params.accel.x == BVH_LAYOUT_WIDE && settings.compaction &&
                 scene.bvhDepth >= kMultiRayMinDepth;
  return several ? kRaysPerInvocationOnCpus : 1u;
}

uint32_t WavefrontRenderer::Impl::groups_for(uint32_t n) const {
  return (n + settings.workgroupSize - 1) / settings.workgroupSize;
}

uint32_t WavefrontRenderer::Impl::interleaved_groups(uint32_t n) const {
  const uint32_t t = workgroup_interleave();
  return (groups_for(n) + t - 1) / t * t;
}

uint32_t WavefrontRenderer::Impl::tracing_fill() const { return cpu_device() ? 0u : TRACING_INVOCATIONS_ON_GPUS; }

uint32_t WavefrontRenderer::Impl::tracing_groups(uint32_t n, uint32_t perInvocation) const {
  return perInvocation > 1 ? groups_for(TRACING_INVOCATIONS(n, perInvocation, tracing_fill())) : interleaved_groups(n);
}

std::vector<std::pair<std::string, const vk::raii::Pipeline*>> WavefrontRenderer::Impl::kernels() const {
  std::vector<std::pair<std::string, const vk::raii::Pipeline*>> k{
      {"generate", &generate}, {"prepare", &prepare},       {"extend", &extend},
      {"sort", &sort},         {"shade", &shade},           {"connect", &connect},
      {"accumulate", &accumulate}, {"megakernel", &megakernel}, {"raycast", &raycast},
      {"raycast-single", &raycastSingle}, {"occlude", &occlude}, {"occlude-single", &occludeSingle},
      {"probe", &probe}, {"photons", &photons}};
  for (size_t i = 0; i < shadeByKey.size(); ++i)
    k.emplace_back(shadeKeys[i] == SORT_KEY_MISS ? "shade-misses" : "shade-class-" + std::to_string(shadeKeys[i] - 1), &shadeByKey[i]);
  return k;
}

vk::raii::Pipeline WavefrontRenderer::Impl::make_pipeline(Kernel k, PipelineOptions o) {
  // The specialization constants of the kernels, by their ids (bindings.glsl).
  const shader::uvec4& accel = scene.params.accel;
  // More slots than the register stack holds select the indexed stack.
  bool indexed = settings.stack == TraversalStack::Indexed || (settings.stack == TraversalStack::Auto && !cpu_device());
  uint32_t stackSlots = indexed ? std::max(accel.z, WIDE_REGISTER_STACK + 1u) : accel.z;
  // A sorted shade kernel holds its class's kinds only.
  const glm::uvec4 kinds = o.shadeKey == SORT_KEYS ? scene.params.kinds : scene.shade_key_kinds(o.shadeKey);
  constexpr uint32_t kConstants = SPEC_COUNT;
  uint32_t values[kConstants] = {};
  values[SPEC_WORKGROUP_SIZE] = settings.workgroupSize;
  values[SPEC_INTEGRATOR] = scene.params.mode.x;
  values[SPEC_LIGHT_SAMPLES] = scene.params.mode.w;
  values[SPEC_BVH_LAYOUT] = accel.x;
  values[SPEC_WIDE_CHILD_ORDER] = accel.y;
  values[SPEC_ROOT_AT_ENTRY] = (accel.w & WALK_ROOT_AT_ENTRY) != 0u ? 1u : 0u;
  values[SPEC_BINARY_FUSED] = (accel.w & WALK_BINARY_FUSED) != 0u ? 1u : 0u;
  values[SPEC_MATERIAL_KINDS] = kinds.x;
  values[SPEC_TEXTURE_KINDS] = kinds.y;
  values[SPEC_LIGHT_KINDS] = kinds.z;
  values[SPEC_FEATURES] = kinds.w;
  values[SPEC_STACK_SIZE] = stackSlots;
  values[SPEC_COMPACTION] = settings.compaction ? 1u : 0u;  // bools are 32-bit 0 or 1
  values[SPEC_SORT_BY_MATERIAL] = sorting ? 1u : 0u;
  values[SPEC_RAYS_PER_INVOCATION] = o.single ? 1u : tracingRays;
  values[SPEC_TRACING_FILL] = tracing_fill();
  values[SPEC_WALK_LOADS] = settings.walkLoads ? 1u : 0u;
  values[SPEC_DYNAMIC_FETCH] = settings.dynamicFetch ? 1u : 0u;
  values[SPEC_WORKGROUP_INTERLEAVE] = o.interleaved ? workgroup_interleave() : 1u;
  values[SPEC_ANY_HIT] = o.anyHit ? 1u : 0u;  // raycast.comp
  values[SPEC_SHADE_KEY] = o.shadeKey;        // shade.comp
  values[SPEC_MEGAKERNEL_SAMPLES] = megakernel_samples();  // megakernel.comp
  values[SPEC_AOVS] = scene.aovs.empty() ? 0u : 1u;
  vk::SpecializationMapEntry entries[kConstants];
  for (uint32_t i = 0; i < kConstants; ++i) entries[i] = vk::SpecializationMapEntry(i, i * sizeof(uint32_t), sizeof(uint32_t));
  vk::SpecializationInfo spec(kConstants, entries, sizeof(values), values);
  // The constants applied to the SPIR-V here (gpu/specialize.h); where the
  // optimizer fails, the driver applies them.
  std::vector<uint32_t> specialized;
  if (settings.specializeSpirv) {
    std::string error;
    specialized = specialize_kernel(k.code, k.bytes / sizeof(uint32_t), std::vector<uint32_t>(values, values + kConstants), error,
                                    k.folding);
    if (specialized.empty()) std::fprintf(stderr, "wavepath: the kernel's SPIR-V could not be specialized (%s); the driver specializes it\n", error.c_str());
  }
  vk::ShaderModuleCreateInfo moduleInfo = specialized.empty()
      ? vk::ShaderModuleCreateInfo({}, k.bytes, k.code)
      : vk::ShaderModuleCreateInfo({}, specialized.size() * sizeof(uint32_t), specialized.data());
  vk::raii::ShaderModule module(ctx.device(), moduleInfo);
  vk::PipelineShaderStageCreateInfo stage({}, vk::ShaderStageFlagBits::eCompute, *module, "main", specialized.empty() ? &spec : nullptr);
  vk::PipelineCreateFlags flags;
  if (settings.captureStatistics && ctx.info().pipelineStatistics) flags |= vk::PipelineCreateFlagBits::eCaptureStatisticsKHR;
  return vk::raii::Pipeline(ctx.device(), nullptr, vk::ComputePipelineCreateInfo(flags, stage, *pipelineLayout));
}

void WavefrontRenderer::Impl::create_tracing_pipelines() {
  prepare = make_pipeline(kernel(WP_KERNEL(prepare)));
  extend = make_pipeline(kernel(WP_KERNEL(extend), Folding::Branches));
  if (scene.params.mode.w > 1u) {
    if (!ctx.info().floatAtomicAdd) {
      throw RenderError(ctx.info().name + " lacks float atomics (VK_EXT_shader_atomic_float), which " +
                        std::to_string(scene.params.mode.w) + " light samples per vertex need; use one (-l 1)");
    }
    connect = make_pipeline(kernel(WP_KERNEL(connect_multi), Folding::Branches));
  } else {
    connect = make_pipeline(kernel(WP_KERNEL(connect), Folding::Branches));
  }
  raycast = vk::raii::Pipeline(nullptr);  // the ray caster's multi-ray pipelines are remade on use (ray_caster)
  occlude = vk::raii::Pipeline(nullptr);
}

void WavefrontRenderer::Impl::create_pipelines() {
  if (settings.walkLoads) {
    for (uint32_t b : {BINDING_NODES, BINDING_WIDE_NODES, BINDING_TRIANGLES}) {
      if (buffers[b]->size() > ctx.info().maxStorageBufferRange)
        throw RenderError("the *-loads variants read the scene's BVH and primitives as storage buffers, and " + ctx.info().name + " allows " +
                          std::to_string(ctx.info().maxStorageBufferRange >> 20) + " MiB in one; this scene needs " +
                          std::to_string(buffers[b]->size() >> 20) + " MiB: use a variant without -loads");
    }
  }
  std::vector<vk::DescriptorSetLayoutBinding> bindings;
  uint32_t texelBindings = 0;
  for (uint32_t b = 0; b < BINDING_COUNT; ++b) {
    bindings.emplace_back(b, descriptor_type(b), 1, vk::ShaderStageFlagBits::eCompute);
    texelBindings += is_texel_binding(b);
  }
  setLayout = vk::raii::DescriptorSetLayout(ctx.device(), vk::DescriptorSetLayoutCreateInfo({}, bindings));
  vk::PushConstantRange push(vk::ShaderStageFlagBits::eCompute, 0, sizeof(KernelPush));
  vk::DescriptorSetLayout layouts[] = {*setLayout};
  pipelineLayout = vk::raii::PipelineLayout(ctx.device(), vk::PipelineLayoutCreateInfo({}, layouts, push));
  vk::DescriptorPoolSize sizes[] = {{vk::DescriptorType::eUniformBuffer, 1},
                                    {vk::DescriptorType::eUniformTexelBuffer, texelBindings},
                                    {vk::DescriptorType::eStorageBuffer, BINDING_COUNT - 1 - texelBindings}};
  pool = vk::raii::DescriptorPool(ctx.device(), vk::DescriptorPoolCreateInfo(vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet, 1, sizes));
  set = std::move(vk::raii::DescriptorSets(ctx.device(), vk::DescriptorSetAllocateInfo(*pool, layouts))[0]);
  std::vector<vk::DescriptorBufferInfo> infos(BINDING_COUNT);
  std::vector<vk::BufferView> texelViews(BINDING_COUNT);
  std::vector<vk::WriteDescriptorSet> writes;
  for (uint32_t b = 0; b < BINDING_COUNT; ++b) {
    if (is_texel_binding(b)) {
      texelViews[b] = *views[b];
      writes.emplace_back(*set, b, 0, 1, bindings[b].descriptorType, nullptr, nullptr, &texelViews[b]);
      continue;
    }
    const uint32_t records = walk_records_of(b);
    if (records != b) {
      // The walks' records as a storage buffer: within the device's range
      // (the kernels read it only in the *-loads variants, which check that
      // the records fit, above).
      const Buffer& texels = *buffers[records];
      const uint64_t maxRange = ctx.info().maxStorageBufferRange;
      infos[b] = vk::DescriptorBufferInfo(texels.handle(), 0, texels.size() > maxRange ? maxRange : VK_WHOLE_SIZE);
    } else {
      infos[b] = vk::DescriptorBufferInfo(buffers[b]->handle(), 0, VK_WHOLE_SIZE);
    }
    writes.emplace_back(*set, b, 0, 1, bindings[b].descriptorType, nullptr, &infos[b]);
  }
  ctx.device().updateDescriptorSets(writes, {});
  tracingRays = rays_per_invocation();
  create_tracing_pipelines();
  generate = make_pipeline(kernel(WP_KERNEL(generate)));
  if (sorting) {
    sort = make_pipeline(kernel(WP_KERNEL(sort)));
    shadeKeys.push_back(SORT_KEY_MISS);
    for (uint32_t c = 0; c < scene.shadeClasses.size(); ++c) shadeKeys.push_back(c + 1);
    for (uint32_t key : shadeKeys) {
      PipelineOptions o;
      o.shadeKey = key;
      shadeByKey.push_back(make_pipeline(kernel(WP_KERNEL(shade)), o));
    }
  } else {
    shade = make_pipeline(kernel(WP_KERNEL(shade)));
  }
  accumulate = make_pipeline(kernel(WP_KERNEL(accumulate)));
  if (settings.megakernel) megakernel = make_pipeline(kernel(WP_KERNEL(megakernel)), {false, true, false});
  // probe (eval_textures and run_probes) is made on first use.
}

std::vector<KernelStatistics> WavefrontRenderer::kernel_statistics() const {
  const VulkanContext& ctx = impl_->ctx;
  if (!impl_->settings.captureStatistics) throw RenderError("kernel statistics were not captured (WavefrontSettings::captureStatistics)");
  if (!ctx.info().pipelineStatistics)
    throw RenderError(ctx.info().name + " reports no kernel statistics (its driver lacks VK_KHR_pipeline_executable_properties)");
  std::vector<KernelStatistics> out;
  for (const auto& [name, made] : impl_->kernels()) {
    if (!**made) continue;  // a kernel this renderer does not use
    const vk::Pipeline pipeline = **made;
    std::vector<vk::PipelineExecutablePropertiesKHR> executables = ctx.device().getPipelineExecutablePropertiesKHR(vk::PipelineInfoKHR(pipeline));
    for (uint32_t i = 0; i < executables.size(); ++i) {
      KernelStatistics k{name, executables[i].name.data(), {}};
      for (const vk::PipelineExecutableStatisticKHR& st : ctx.device().getPipelineExecutableStatisticsKHR(vk::PipelineExecutableInfoKHR(pipeline, i))) {
        std::string value;
        switch (st.format) {
          case vk::PipelineExecutableStatisticFormatKHR::eBool32: value = st.value.b32 ? "yes" : "no"; break;
          case vk::PipelineExecutableStatisticFormatKHR::eInt64: value = std::to_string(st.value.i64); break;
          case vk::PipelineExecutableStatisticFormatKHR::eUint64: value = std::to_string(st.value.u64); break;
          case vk::PipelineExecutableStatisticFormatKHR::eFloat64: value = std::to_string(st.value.f64); break;
        }
        k.values.emplace_back(st.name.data(), value);
      }
      out.push_back(std::move(k));
    }
  }
  return out;
}

}  // namespace wp
