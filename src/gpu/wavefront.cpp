#include "gpu/wavefront.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "cpu/reference.h"
#include "render/accumulate.h"
#include "util/error.h"

// SPIR-V compiled from shaders/*.comp at build time (see CMakeLists.txt).
#include "accumulate.spv.h"
#include "connect.spv.h"
#include "connect_multi.spv.h"
#include "extend.spv.h"
#include "generate.spv.h"
#include "megakernel.spv.h"
#include "prepare.spv.h"
#include "raycast.spv.h"
#include "texprobe.spv.h"
#include "shade.spv.h"
#include "sort.spv.h"

namespace wp {

namespace {

using shader::KernelPush;

struct Kernel {
  const uint32_t* code;
  size_t bytes;
};

template <size_t N>
Kernel kernel(const uint32_t (&code)[N]) {
  return Kernel{code, N * sizeof(uint32_t)};
}


// Every stage reads what the previous one wrote, indirect arguments included.
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

}  // namespace

const std::vector<KernelVariant>& kernel_variants() {
  static const std::vector<KernelVariant> variants = [] {
    WavefrontSettings noCompaction;
    noCompaction.compaction = false;
    WavefrontSettings megakernel;
    megakernel.megakernel = true;
    WavefrontSettings sorted;
    sorted.sortByMaterial = true;
    WavefrontSettings registerStack;
    registerStack.stack = TraversalStack::Registers;
    WavefrontSettings indexedStack;
    indexedStack.stack = TraversalStack::Indexed;
    WavefrontSettings oneRay;
    oneRay.raysPerInvocation = 1;
    WavefrontSettings multiRay;
    multiRay.raysPerInvocation = 16;
    std::vector<KernelVariant> v{
        {"gpu", "wavefront kernels, 8-wide compressed BVH, workgroups of 64", WavefrontSettings{}, BvhLayout::Wide},
        {"gpu-greedy", "wavefront kernels, wide BVH collapsed greedily (largest child opened first) instead of by SAH",
         WavefrontSettings{}, BvhLayout::Wide, false, false, WideCollapse::Greedy},
        {"gpu-bvh2", "wavefront kernels, binary BVH, workgroups of 64", WavefrontSettings{}, BvhLayout::Binary},
        {"gpu-nocompact", "wavefront kernels without path compaction: every bounce runs over every path", noCompaction,
         BvhLayout::Wide},
        {"gpu-mega", "one kernel per path (camera ray to pixel), its rays sharing lavapipe's loop budget", megakernel,
         BvhLayout::Wide},
        {"gpu-rotate", "wavefront kernels, wide BVH from the SAH tree improved by tree rotations", WavefrontSettings{},
         BvhLayout::Wide, true},
        {"gpu-clustered", "wavefront kernels, wide BVH from the clustered SAH build (Morton clusters at the top, exact sweep at the bottom)",
         WavefrontSettings{}, BvhLayout::Wide, false, true},
        {"gpu-sort", "wavefront kernels, paths sorted by the class of material their ray hit, each class shaded by a kernel holding only its kinds", sorted,
         BvhLayout::Wide},
        {"gpu-regstack", "wavefront kernels, the wide walk's stack in registers on every device (gpu: on CPU devices)",
         registerStack, BvhLayout::Wide},
        {"gpu-memstack", "wavefront kernels, the wide walk's stack in an indexed array on every device (gpu: on GPUs)",
         indexedStack, BvhLayout::Wide},
        {"gpu-oneray", "wavefront kernels, one ray per invocation of the tracing kernels (gpu: 16 on CPU devices, for trees of depth 4 or more)",
         oneRay, BvhLayout::Wide},
        {"gpu-multiray", "wavefront kernels, 16 rays per invocation of the tracing kernels (shared within subgroups) on every device and tree", multiRay,
         BvhLayout::Wide}};
    for (uint32_t size : {32u, 128u, 256u}) {
      WavefrontSettings s;
      s.workgroupSize = size;
      v.push_back({"gpu-wg" + std::to_string(size), "wavefront kernels, 8-wide compressed BVH, workgroups of " + std::to_string(size),
                   s, BvhLayout::Wide});
    }
    return v;
  }();
  return variants;
}

RenderOptions variant_options(RenderOptions options, const std::string& renderer) {
  if (renderer == "cpu") return reference_options(options);
  const KernelVariant& v = kernel_variant(renderer);
  options.bvhLayout = v.bvhLayout;
  options.bvhRotations = v.bvhRotations;
  options.clusteredBuild = v.clusteredBuild;
  options.wideCollapse = v.wideCollapse;
  return options;
}

const KernelVariant& kernel_variant(const std::string& name) {
  std::string known;
  for (const KernelVariant& v : kernel_variants()) {
    if (name == v.name) return v;
    known += std::string(known.empty() ? "" : ", ") + v.name;
  }
  throw InputError("unknown kernel variant \"" + name + "\" (known: " + known + ")");
}

struct WavefrontRenderer::Impl {
  const VulkanContext& ctx;
  const CompiledScene& scene;
  WavefrontSettings settings;
  uint32_t capacity = 0;  // path slots per wave
  uint32_t lightSamples = 1;  // shadow rays per path and bounce, at most
  std::vector<std::unique_ptr<Buffer>> buffers;  // indexed by BINDING_*
  std::vector<vk::raii::BufferView> views;        // the texel buffers' views, indexed by BINDING_*
  std::unique_ptr<Buffer> readAccum;
  std::unique_ptr<Buffer> readCounters;
  // run_on_rays' transfer buffers, made on first use and kept: a fresh pinned
  // buffer per call made an H100's ray casts 4 to 5 times slower after a few
  // dozen calls. The staging buffer only where the rays' buffer is not mapped.
  std::unique_ptr<Buffer> rayStaging, readHits;
  vk::raii::DescriptorSetLayout setLayout{nullptr};
  vk::raii::PipelineLayout pipelineLayout{nullptr};
  vk::raii::DescriptorPool pool{nullptr};
  vk::raii::DescriptorSet set{nullptr};
  vk::raii::Pipeline generate{nullptr}, prepare{nullptr}, extend{nullptr}, sort{nullptr}, shade{nullptr}, connect{nullptr},
      accumulate{nullptr}, megakernel{nullptr}, raycast{nullptr}, raycastSingle{nullptr}, occlude{nullptr},
      occludeSingle{nullptr}, texprobe{nullptr};
  // Sorting by material class: one shade kernel per sort key that can occur,
  // specialized to its class (shadeKeys[i] is shadeByKey[i]'s key), the
  // misses' first.
  std::vector<vk::raii::Pipeline> shadeByKey;
  std::vector<uint32_t> shadeKeys;
  bool sorting = false;  // by material class (settings.sortByMaterial, not for the megakernel)
  uint32_t tracingRays = 1;  // rays per invocation of prepare's sizing, extend, connect and raycast (rays_per_invocation)
  vk::raii::CommandPool commandPool{nullptr};
  // Timestamps: one after every dispatch of a submission; stageOf[i] names the
  // stage whose dispatch ended at timestamp i + 1.
  vk::raii::QueryPool queries{nullptr};
  uint32_t queryCapacity = 0;
  std::vector<int> stageOf;
  bool timestamps = false;
  double timestampPeriodNs = 1.0;
  StageTimes times;
  uint64_t oneRayReruns = 0;  // one_ray_reruns()

  using Stage = StageTimes::Stage;

  Impl(const VulkanContext& c, const CompiledScene& s, const WavefrontSettings& st) : ctx(c), scene(s), settings(st) {
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
    capacity = std::min<uint64_t>({pixels, settings.maxPathsPerWave, std::min(maxRange, maxViewBytes) / sizeof(shader::PathState),
                                   std::min(maxRange, maxViewBytes) / (sizeof(shader::ShadowRay) * lightSamples),
                                   uint64_t(ctx.info().maxComputeWorkGroupCount) * settings.workgroupSize / lightSamples,
                                   std::min<uint64_t>(ctx.info().maxTexelBufferElements, maxRange / sizeof(uint32_t)) / queue_count()});
    create_buffers(pixels, maxRange);
    create_pipelines();
    commandPool = vk::raii::CommandPool(ctx.device(), vk::CommandPoolCreateInfo(
                                                          vk::CommandPoolCreateFlagBits::eResetCommandBuffer, ctx.queue_family()));
    auto props = ctx.physical().getProperties();
    auto families = ctx.physical().getQueueFamilyProperties();
    timestamps = props.limits.timestampComputeAndGraphics && families[ctx.queue_family()].timestampValidBits > 0;
    timestampPeriodNs = props.limits.timestampPeriod;
  }

  // Makes room for `count` timestamps in the query pool.
  void reserve_queries(uint32_t count) {
    if (!timestamps || count <= queryCapacity) return;
    queryCapacity = std::max(count, queryCapacity * 2);
    queries = vk::raii::QueryPool(ctx.device(), vk::QueryPoolCreateInfo({}, vk::QueryType::eTimestamp, queryCapacity));
  }

  void stamp(vk::CommandBuffer cb, Stage stage) {
    if (!timestamps) return;
    stageOf.push_back(stage);
    cb.writeTimestamp(vk::PipelineStageFlagBits::eComputeShader, *queries, uint32_t(stageOf.size()));
  }

  // Attributes the intervals between a submission's timestamps to stages.
  void collect_times() {
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

  // The scene's arrays, which the kernels read as texel buffers (bindings.glsl):
  // records as RGBA32UI, image texels as RG32UI, the environment CDF as R32F.
  static bool is_texel_binding(uint32_t binding) {
    switch (binding) {
      case BINDING_NODES:
      case BINDING_WIDE_NODES:
      case BINDING_TRIANGLES:
      case BINDING_TRIANGLE_SHADING:
      case BINDING_SPHERES:
      case BINDING_MATERIALS:
      case BINDING_EMITTERS:
      case BINDING_TEXTURES:
      case BINDING_POINT_LIGHTS:
      case BINDING_TEXELS:
      case BINDING_ENVIRONMENT_CDF:
      case BINDING_PATH_TEXELS:
      case BINDING_HIT_TEXELS:
      case BINDING_SHADOW_RAY_TEXELS:
      case BINDING_QUEUE_TEXELS:
        return true;
      default:
        return false;
    }
  }

  static vk::DescriptorType descriptor_type(uint32_t binding) {
    if (binding == BINDING_SCENE) return vk::DescriptorType::eUniformBuffer;
    return is_texel_binding(binding) ? vk::DescriptorType::eUniformTexelBuffer : vk::DescriptorType::eStorageBuffer;
  }

  template <typename T>
  void add_texels(uint32_t binding, const std::vector<T>& data, const char* what, vk::Format format = vk::Format::eR32G32B32A32Uint) {
    const uint64_t texelBytes = format == vk::Format::eR32G32B32A32Uint ? 16 : format == vk::Format::eR32G32Uint ? 8 : 4;
    static_assert(sizeof(T) % 4 == 0);
    if (sizeof(T) % texelBytes != 0) throw RenderError("internal error: a record is not a whole number of texels");
    uint64_t bytes = data.size() * sizeof(T);
    uint64_t maxBytes = ctx.info().maxTexelBufferElements * texelBytes;
    if (bytes > maxBytes) {
      throw RenderError(std::string("the scene's ") + what + " need " + std::to_string(bytes >> 20) + " MiB but " +
                        ctx.info().name + " allows " + std::to_string(maxBytes >> 20) + " MiB per texel buffer");
    }
    buffers[binding] = std::make_unique<Buffer>(ctx, bytes, vk::BufferUsageFlagBits::eUniformTexelBuffer | vk::BufferUsageFlagBits::eTransferDst, false);
    ctx.upload(*buffers[binding], data.data(), bytes);
    views[binding] = vk::raii::BufferView(ctx.device(), vk::BufferViewCreateInfo({}, buffers[binding]->handle(),
                                                                                  format, 0, VK_WHOLE_SIZE));
  }

  void add_work(uint32_t binding, uint64_t bytes, vk::BufferUsageFlags extra = {}) {
    using U = vk::BufferUsageFlagBits;
    buffers[binding] = std::make_unique<Buffer>(ctx, bytes, U::eStorageBuffer | U::eTransferDst | U::eTransferSrc | extra, false);
  }

  // A work buffer the kernels also read as RGBA32UI texels, through `view`.
  void add_readable_work(uint32_t binding, uint32_t view, uint64_t bytes, vk::Format format = vk::Format::eR32G32B32A32Uint) {
    add_work(binding, bytes, vk::BufferUsageFlagBits::eUniformTexelBuffer);
    views[view] = vk::raii::BufferView(ctx.device(), vk::BufferViewCreateInfo({}, buffers[binding]->handle(), format, 0, VK_WHOLE_SIZE));
  }

  void create_buffers(uint32_t pixels, uint64_t maxRange) {
    buffers.resize(BINDING_COUNT);
    for (uint32_t b = 0; b < BINDING_COUNT; ++b) views.emplace_back(nullptr);
    buffers[BINDING_SCENE] = std::make_unique<Buffer>(ctx, sizeof(shader::SceneParams),
                                                      vk::BufferUsageFlagBits::eUniformBuffer | vk::BufferUsageFlagBits::eTransferDst, false);
    shader::SceneParams params = scene.params;
    params.counts.z = traversal_step_cap();
    ctx.upload(*buffers[BINDING_SCENE], &params, sizeof(shader::SceneParams));
    add_texels(BINDING_NODES, scene.nodes, "BVH nodes");
    add_texels(BINDING_WIDE_NODES, scene.wideNodes, "wide BVH nodes");
    add_texels(BINDING_TRIANGLES, scene.triangles, "primitives");
    add_texels(BINDING_TRIANGLE_SHADING, scene.triangleShading, "vertex normals and UVs");
    add_texels(BINDING_SPHERES, scene.spheres, "spheres");
    add_texels(BINDING_MATERIALS, scene.materials, "materials");
    add_texels(BINDING_EMITTERS, scene.emitters, "emitters");
    add_texels(BINDING_TEXTURES, scene.textures, "textures");
    add_texels(BINDING_POINT_LIGHTS, scene.pointLights, "point lights");
    add_texels(BINDING_TEXELS, scene.texels, "image texels", vk::Format::eR32G32Uint);
    add_texels(BINDING_ENVIRONMENT_CDF, scene.environmentCdf, "environment map distribution", vk::Format::eR32Sfloat);
    add_work(BINDING_PIXEL_LIST, uint64_t(std::max(pixels, 1u)) * sizeof(uint32_t));
    add_readable_work(BINDING_PATHS, BINDING_PATH_TEXELS, uint64_t(capacity) * sizeof(shader::PathState));
    add_readable_work(BINDING_HITS, BINDING_HIT_TEXELS, uint64_t(capacity) * sizeof(shader::Hit));
    // Queues 0 and 1, and with sorting by material class each sort key's.
    add_readable_work(BINDING_QUEUES, BINDING_QUEUE_TEXELS, uint64_t(capacity) * queue_count() * sizeof(uint32_t), vk::Format::eR32Uint);
    add_work(BINDING_SORT, SORT_KEYS * sizeof(uint32_t));
    add_readable_work(BINDING_SHADOW_RAYS, BINDING_SHADOW_RAY_TEXELS, uint64_t(capacity) * lightSamples * sizeof(shader::ShadowRay));
    add_work(BINDING_COUNTERS, COUNTER_COUNT * sizeof(uint32_t));
    add_work(BINDING_INDIRECT, INDIRECT_SLOTS * 3 * sizeof(uint32_t), vk::BufferUsageFlagBits::eIndirectBuffer);
    uint64_t accumBytes = uint64_t(pixels) * sizeof(shader::PixelAccum);
    if (accumBytes > maxRange) {
      throw RenderError("a " + std::to_string(scene.width) + "x" + std::to_string(scene.height) + " image needs " +
                        std::to_string(accumBytes >> 20) + " MiB of accumulators, more than the " +
                        std::to_string(maxRange >> 20) + " MiB per storage buffer " + ctx.info().name + " allows");
    }
    add_work(BINDING_ACCUM, accumBytes);
    readAccum = std::make_unique<Buffer>(ctx, accumBytes, vk::BufferUsageFlagBits::eTransferDst, true);
    readCounters = std::make_unique<Buffer>(ctx, COUNTER_COUNT * sizeof(uint32_t), vk::BufferUsageFlagBits::eTransferDst, true);
  }

  // Lavapipe ends all loops of an invocation after 65,535 iterations in all,
  // silently. The wavefront kernels trace one ray per invocation, so each ray
  // may take the scene's whole cap. The megakernel traces every ray of a path
  // in one invocation: up to max bounces + 1 closest-hit rays and light
  // samples x max bounces shadow rays, and the bounce loop's own iterations.
  uint32_t traversal_step_cap() const {
    const uint32_t cap = scene.params.counts.z;
    if (!settings.megakernel) return cap;
    const uint64_t bounces = scene.params.image.z, lightSamples = std::max(1u, scene.params.mode.w);
    const uint64_t budget = TRAVERSAL_STEP_BUDGET, traversals = bounces + 1 + bounces * lightSamples;
    const uint64_t perRay = (budget - std::min(budget, bounces + 1)) / traversals;
    if (perRay < kMegakernelMinimumCap) {
      throw RenderError("the megakernel variant fits " + std::to_string(bounces) + " bounces into lavapipe's loop budget only with " +
                        std::to_string(perRay) + " traversal steps per ray (at least " + std::to_string(kMegakernelMinimumCap) +
                        " needed); use fewer bounces or the wavefront kernels");
    }
    return uint32_t(std::min<uint64_t>(cap, perRay));
  }
  static constexpr uint64_t kMegakernelMinimumCap = 256;

  // Rays per invocation of the tracing kernels (trace_items.glsl; with
  // several, a subgroup's lanes share theirs): several where lanes of a SIMD
  // group would wait for each other's rays (CPU devices, incoherent rays)
  // and the walk can resume rays (the wide BVH; with compaction, so every
  // queued ray is live). Each gets the step cap's
  // share; where a ray needs more, the work is done again one ray per
  // invocation (render_samples, run_on_rays). Coherent rays (the ray-casting
  // benchmark's camera rays and the shadow rays from their hits, cast_rays)
  // finish together anyway: on the dragon they ran 16 % slower several to an
  // invocation. (A render's camera rays
  // are a ninth of its closest-hit rays at 8 bounces: not worth a second
  // extend kernel.) Nor do the short walks of a shallow tree need balancing:
  // on the Cornell box (depth 2) renders lost 9 % to the per-ray start and
  // store, while the 100k-triangle scenes (depth 6 to 10) gained.
  uint32_t rays_per_invocation() const {
    if (settings.raysPerInvocation != 0) return settings.raysPerInvocation;
    bool several = cpu_device() && scene.params.accel.x == BVH_LAYOUT_WIDE && settings.compaction &&
                   scene.bvhDepth >= kMultiRayMinDepth;
    return several ? kRaysPerInvocationOnCpus : 1u;
  }
  static constexpr uint32_t kRaysPerInvocationOnCpus = 16;
  static constexpr int kMultiRayMinDepth = 4;

  uint32_t groups_for(uint32_t n) const {
    return (n + settings.workgroupSize - 1) / settings.workgroupSize;
  }

  // Workgroup interleave of the kernels that take work in image order, one
  // item to an invocation (dispatch_item, kernel.glsl): the megakernel and the
  // ray caster's coherent rays. lavapipe gives each thread one contiguous
  // block of a dispatch's workgroups, so on CPU devices their workgroups are
  // dealt out in columns of this many. GPUs schedule workgroups as they free
  // up. (Extend and connect take one ray to an invocation only on shallow
  // trees or GPUs; interleaved, they were 9 % slower on the Cornell box, whose
  // pixels all cost about the same.)
  uint32_t workgroup_interleave() const { return cpu_device() ? kWorkgroupInterleaveOnCpus : 1u; }
  static constexpr uint32_t kWorkgroupInterleaveOnCpus = 32;

  // Workgroups for n items of an interleaved kernel, one to an invocation, in
  // whole rows of the interleave.
  uint32_t interleaved_groups(uint32_t n) const {
    const uint32_t t = workgroup_interleave();
    return (groups_for(n) + t - 1) / t * t;
  }

  // Workgroups of the ray caster (or texprobe) for n rays, perInvocation to
  // an invocation. One ray to an invocation rounds up to whole rows of the
  // interleave; texprobe, which does not interleave, takes the extra
  // workgroups' items as out of range.
  uint32_t tracing_groups(uint32_t n, uint32_t perInvocation) const {
    return perInvocation > 1 ? groups_for((n + perInvocation - 1) / perInvocation) : interleaved_groups(n);
  }

  // Queues of paths in the queue buffer: the two that alternate between
  // bounces and, sorting, the sort keys' (the misses and each class).
  uint32_t queue_count() const { return QUEUE_SORTED + (sorting ? 1 + uint32_t(scene.shadeClasses.size()) : 0); }

  // Whether the wavefront kernels sort paths by material class.
  bool sort_by_material() const { return settings.sortByMaterial && !settings.megakernel; }

  // lavapipe and other CPU implementations: SIMD lanes in a loop, private
  // arrays in memory (the stack and rays-per-invocation choices follow).
  bool cpu_device() const { return ctx.info().type == "cpu"; }

  // Every kernel, by name, whether or not this renderer made it.
  std::vector<std::pair<std::string, const vk::raii::Pipeline*>> kernels() const {
    std::vector<std::pair<std::string, const vk::raii::Pipeline*>> k{
        {"generate", &generate}, {"prepare", &prepare},       {"extend", &extend},
        {"sort", &sort},         {"shade", &shade},           {"connect", &connect},
        {"accumulate", &accumulate}, {"megakernel", &megakernel}, {"raycast", &raycast},
        {"raycast-single", &raycastSingle}, {"occlude", &occlude}, {"occlude-single", &occludeSingle},
        {"texprobe", &texprobe}};
    for (size_t i = 0; i < shadeByKey.size(); ++i)
      k.emplace_back(shadeKeys[i] == SORT_KEY_MISS ? "shade-misses" : "shade-class-" + std::to_string(shadeKeys[i] - 1), &shadeByKey[i]);
    return k;
  }

  // How a pipeline specializes its kernel beyond the renderer's settings.
  struct PipelineOptions {
    bool single = false;       // a tracing kernel takes one ray per invocation, whatever tracingRays says
    bool interleaved = false;  // workgroups dealt out in columns (workgroup_interleave)
    bool anyHit = false;       // the ray caster looks for any hit, not the closest
    uint32_t shadeKey = SORT_KEYS;  // shade: the sort key it shades (SORT_KEYS: all paths, unsorted)
  };

  vk::raii::Pipeline make_pipeline(Kernel k) { return make_pipeline(k, PipelineOptions()); }
  vk::raii::Pipeline make_pipeline(Kernel k, PipelineOptions o) {
    vk::raii::ShaderModule module(ctx.device(), vk::ShaderModuleCreateInfo({}, k.bytes, k.code));
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
    values[SPEC_MATERIAL_KINDS] = kinds.x;
    values[SPEC_TEXTURE_KINDS] = kinds.y;
    values[SPEC_LIGHT_KINDS] = kinds.z;
    values[SPEC_FEATURES] = kinds.w;
    values[SPEC_STACK_SIZE] = stackSlots;
    values[SPEC_COMPACTION] = settings.compaction ? 1u : 0u;  // bools are 32-bit 0 or 1
    values[SPEC_SORT_BY_MATERIAL] = sorting ? 1u : 0u;
    values[SPEC_RAYS_PER_INVOCATION] = o.single ? 1u : tracingRays;
    values[SPEC_WORKGROUP_INTERLEAVE] = o.interleaved ? workgroup_interleave() : 1u;
    values[SPEC_ANY_HIT] = o.anyHit ? 1u : 0u;  // raycast.comp
    values[SPEC_SHADE_KEY] = o.shadeKey;        // shade.comp
    vk::SpecializationMapEntry entries[kConstants];
    for (uint32_t i = 0; i < kConstants; ++i) entries[i] = vk::SpecializationMapEntry(i, i * sizeof(uint32_t), sizeof(uint32_t));
    vk::SpecializationInfo spec(kConstants, entries, sizeof(values), values);
    vk::PipelineShaderStageCreateInfo stage({}, vk::ShaderStageFlagBits::eCompute, *module, "main", &spec);
    vk::PipelineCreateFlags flags;
    if (settings.captureStatistics && ctx.info().pipelineStatistics) flags |= vk::PipelineCreateFlagBits::eCaptureStatisticsKHR;
    return vk::raii::Pipeline(ctx.device(), nullptr, vk::ComputePipelineCreateInfo(flags, stage, *pipelineLayout));
  }

  // The kernels whose code depends on tracingRays, (re)made from it.
  void create_tracing_pipelines() {
    prepare = make_pipeline(kernel(prepare_spv));
    extend = make_pipeline(kernel(extend_spv));
    if (scene.params.mode.w > 1u) {
      if (!ctx.info().floatAtomicAdd) {
        throw RenderError(ctx.info().name + " lacks float atomics (VK_EXT_shader_atomic_float), which " +
                          std::to_string(scene.params.mode.w) + " light samples per vertex need; use one (-l 1)");
      }
      connect = make_pipeline(kernel(connect_multi_spv));
    } else {
      connect = make_pipeline(kernel(connect_spv));
    }
    raycast = vk::raii::Pipeline(nullptr);  // the ray caster's multi-ray pipelines are remade on use (ray_caster)
    occlude = vk::raii::Pipeline(nullptr);
  }

  void create_pipelines() {
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
      infos[b] = vk::DescriptorBufferInfo(buffers[b]->handle(), 0, VK_WHOLE_SIZE);
      writes.emplace_back(*set, b, 0, 1, bindings[b].descriptorType, nullptr, &infos[b]);
    }
    ctx.device().updateDescriptorSets(writes, {});
    tracingRays = rays_per_invocation();
    create_tracing_pipelines();
    generate = make_pipeline(kernel(generate_spv));
    if (sorting) {
      sort = make_pipeline(kernel(sort_spv));
      shadeKeys.push_back(SORT_KEY_MISS);
      for (uint32_t c = 0; c < scene.shadeClasses.size(); ++c) shadeKeys.push_back(c + 1);
      for (uint32_t key : shadeKeys) {
        PipelineOptions o;
        o.shadeKey = key;
        shadeByKey.push_back(make_pipeline(kernel(shade_spv), o));
      }
    } else {
      shade = make_pipeline(kernel(shade_spv));
    }
    accumulate = make_pipeline(kernel(accumulate_spv));
    if (settings.megakernel) megakernel = make_pipeline(kernel(megakernel_spv), {false, true, false});
    // texprobe (eval_textures, for the tests) is made on first use.
  }

  void dispatch(vk::CommandBuffer cb, const vk::raii::Pipeline& p, const KernelPush& push, uint32_t groups, Stage stage) {
    cb.bindPipeline(vk::PipelineBindPoint::eCompute, *p);
    cb.pushConstants<KernelPush>(*pipelineLayout, vk::ShaderStageFlagBits::eCompute, 0, push);
    cb.dispatch(groups, 1, 1);
    stage_barrier(cb);
    stamp(cb, stage);
  }

  // `last`: the barrier and the timestamp after it; false for a dispatch that
  // may run beside the next one (which times both).
  void dispatch_indirect(vk::CommandBuffer cb, const vk::raii::Pipeline& p, const KernelPush& push, uint32_t slot, Stage stage,
                         bool last = true) {
    cb.bindPipeline(vk::PipelineBindPoint::eCompute, *p);
    cb.pushConstants<KernelPush>(*pipelineLayout, vk::ShaderStageFlagBits::eCompute, 0, push);
    cb.dispatchIndirect(buffers[BINDING_INDIRECT]->handle(), slot * 3 * sizeof(uint32_t));
    if (!last) return;
    stage_barrier(cb);
    stamp(cb, stage);
  }

  // One wave: a sample for `pathCount` pixels from `waveStart`, all bounces.
  void record_wave(vk::CommandBuffer cb, uint32_t waveStart, uint32_t pathCount, uint32_t sampleIndex, bool listed) {
    KernelPush push{};
    push.waveStart = waveStart;
    push.pathCount = pathCount;
    push.sampleIndex = sampleIndex;
    push.capacity = capacity;
    push.phase = listed ? GENERATE_FROM_LIST : GENERATE_CONSECUTIVE;
    if (settings.megakernel) return dispatch(cb, megakernel, push, interleaved_groups(pathCount), StageTimes::kMegakernel);
    dispatch(cb, generate, push, groups_for(pathCount), StageTimes::kGenerate);
    // Bounce b extends the rays of paths with b scattering events behind them;
    // path_shade ends every path at max bounces, so there are max + 1 passes.
    const uint32_t passes = scene.params.image.z + 1;
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

  // Renders every pixel at scene.spp samples; with adaptive sampling, in
  // batches, dropping the pixels that have converged after each batch.
  ImageStats render(Progress& progress) {
    const uint32_t pixels = uint32_t(scene.width) * uint32_t(scene.height);
    const uint32_t spp = uint32_t(scene.spp);
    ImageStats image(scene.width, scene.height);
    uint64_t truncated = 0;
    times = StageTimes{};
    if (!scene.adaptive.enabled()) {
      render_samples(image, truncated, progress, 0, spp, pixels, false);
    } else {
      std::vector<uint32_t> active(pixels);
      for (uint32_t p = 0; p < pixels; ++p) active[p] = p;
      const uint32_t batch = uint32_t(scene.adaptive.batch);
      for (uint32_t first = 0; first < spp && !active.empty(); first += batch) {
        ctx.upload(*buffers[BINDING_PIXEL_LIST], active.data(), active.size() * sizeof(uint32_t));
        render_samples(image, truncated, progress, first, std::min(first + batch, spp), uint32_t(active.size()), true);
        std::vector<uint32_t> still;
        for (uint32_t p : active) {
          if (!pixel_converged(image.count[p], image.illuminance_sum(p), image.illuminanceSumSq[p], scene.adaptive.tolerance))
            still.push_back(p);
        }
        active.swap(still);
      }
    }
    progress.finish();
    if (truncated > 0) {
      throw RenderError(std::to_string(truncated) + " rays needed more than " + std::to_string(traversal_step_cap()) +
                        " BVH traversal steps; the image would be wrong, so none was written" +
                        (settings.megakernel ? " (the megakernel shares lavapipe's loop budget among a path's rays: "
                                               "use the wavefront kernels)"
                                             : ""));
    }
    return image;
  }

  // Samples [first, end) of `count` pixels: consecutive ones, or (listed)
  // those in the pixel-list buffer. Folds the results into `image`.
  void render_samples(ImageStats& image, uint64_t& truncated, Progress& progress, uint32_t first, uint32_t end,
                      uint32_t count, bool listed) {
    vk::raii::CommandBuffers cbs(ctx.device(), vk::CommandBufferAllocateInfo(*commandPool, vk::CommandBufferLevel::ePrimary, 1));
    vk::CommandBuffer cb = *cbs[0];
    vk::raii::Fence fence(ctx.device(), vk::FenceCreateInfo());
    uint32_t perSubmit = 1;
    const uint32_t wavesPerSample = (count + capacity - 1) / capacity;
    const uint32_t dispatchesPerBounce = sorting ? 7 : 5;
    const uint32_t dispatchesPerWave = settings.megakernel ? 1 : 2 + dispatchesPerBounce * (scene.params.image.z + 1);
    for (uint32_t sample = first; sample < end;) {
      uint32_t n = std::min(perSubmit, end - sample);
      cb.reset();
      cb.begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
      reserve_queries(n * wavesPerSample * dispatchesPerWave + 1);
      stageOf.clear();
      if (timestamps) cb.resetQueryPool(*queries, 0, queryCapacity);
      cb.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipelineLayout, 0, *set, {});
      cb.fillBuffer(buffers[BINDING_ACCUM]->handle(), 0, VK_WHOLE_SIZE, 0);
      cb.fillBuffer(buffers[BINDING_COUNTERS]->handle(), 0, VK_WHOLE_SIZE, 0);
      stage_barrier(cb);
      if (timestamps) cb.writeTimestamp(vk::PipelineStageFlagBits::eComputeShader, *queries, 0);
      for (uint32_t s = sample; s < sample + n; ++s)
        for (uint32_t start = 0; start < count; start += capacity) record_wave(cb, start, std::min(capacity, count - start), s, listed);
      cb.copyBuffer(buffers[BINDING_ACCUM]->handle(), readAccum->handle(), vk::BufferCopy(0, 0, readAccum->size()));
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
      // Aim for submissions of about targetSubmitSeconds: long enough to keep
      // the device busy, short enough for a live progress line. Float sums in
      // the accumulators stay exact enough for a few hundred samples.
      if (seconds < settings.targetSubmitSeconds * 0.5) perSubmit = std::min(perSubmit * 2, 256u);
    }
  }

  // The ray caster (raycast.comp), made on first use: renders never need it.
  // single: one ray per invocation; anyHit: the shadow rays' query. One ray
  // per invocation is for coherent rays, in image order, so the workgroups
  // are interleaved (the multi-ray loop spreads its items by itself). For the
  // benchmark's shadow rays from camera hits, interleaving took the Cornell
  // dragon from 0.37-0.38 to 0.47-0.48 of Embree.
  const vk::raii::Pipeline& ray_caster(bool single, bool anyHit) {
    vk::raii::Pipeline& p = anyHit ? (single ? occludeSingle : occlude) : (single ? raycastSingle : raycast);
    if (!*p) p = make_pipeline(kernel(raycast_spv), {single, true, anyHit});
    return p;
  }

  std::vector<shader::Hit> cast_rays(const std::vector<shader::ShadowRay>& rays, uint64_t* truncated, double* kernelSeconds,
                                     bool coherent, bool anyHit) {
    if (coherent) return run_on_rays(ray_caster(true, anyHit), nullptr, rays, truncated, kernelSeconds);
    return run_on_rays(ray_caster(false, anyHit), &ray_caster(true, anyHit), rays, truncated, kernelSeconds);
  }

  // Runs `kernel` (a ray caster or texprobe) over `rays` in chunks of the path
  // capacity: each ray in the shadow-ray buffer, each result in the hit
  // buffer. A ray caster taking tracingRays rays per invocation names
  // `single`, its one-ray pipeline, for chunks where a ray outran its share
  // of the loop budget.
  std::vector<shader::Hit> run_on_rays(const vk::raii::Pipeline& kernel, const vk::raii::Pipeline* single,
                                       const std::vector<shader::ShadowRay>& rays, uint64_t* truncated, double* kernelSeconds) {
    std::vector<shader::Hit> hits(rays.size());
    const bool timed = timestamps;
    reserve_queries(2);
    timestamps = false;  // no per-stage bookkeeping: only the kernel's dispatch is timed
    double kernelTime = 0.0;
    const Buffer& rayBuffer = *buffers[BINDING_SHADOW_RAYS];
    if (!readHits) readHits = std::make_unique<Buffer>(ctx, uint64_t(capacity) * sizeof(shader::Hit), vk::BufferUsageFlagBits::eTransferDst, true);
    if (!rayBuffer.mapped() && !rayStaging)
      rayStaging = std::make_unique<Buffer>(ctx, uint64_t(capacity) * sizeof(shader::ShadowRay), vk::BufferUsageFlagBits::eTransferSrc, true);
    // One chunk through `p`: the rays truncated, and the kernel's GPU time added to kernelTime.
    auto run_chunk = [&](const vk::raii::Pipeline& p, uint32_t n, uint32_t perInvocation) {
      ctx.run_now([&](vk::CommandBuffer cb) {
        if (!rayBuffer.mapped()) cb.copyBuffer(rayStaging->handle(), rayBuffer.handle(), vk::BufferCopy(0, 0, n * sizeof(shader::ShadowRay)));
        cb.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipelineLayout, 0, *set, {});
        cb.fillBuffer(buffers[BINDING_COUNTERS]->handle(), 0, VK_WHOLE_SIZE, 0);
        stage_barrier(cb);
        KernelPush push{};
        push.pathCount = n;
        push.capacity = capacity;
        if (timed) {
          cb.resetQueryPool(*queries, 0, 2);
          cb.writeTimestamp(vk::PipelineStageFlagBits::eComputeShader, *queries, 0);
        }
        dispatch(cb, p, push, tracing_groups(n, perInvocation), StageTimes::kExtend);
        if (timed) cb.writeTimestamp(vk::PipelineStageFlagBits::eComputeShader, *queries, 1);
        cb.copyBuffer(buffers[BINDING_HITS]->handle(), readHits->handle(), vk::BufferCopy(0, 0, n * sizeof(shader::Hit)));
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
      std::memcpy(rayBuffer.mapped() ? rayBuffer.mapped() : rayStaging->mapped(), rays.data() + start, n * sizeof(shader::ShadowRay));
      uint32_t chunkLost = run_chunk(kernel, n, perInvocation);
      // A ray past its share of the loop budget: the chunk again, one ray per invocation.
      if (chunkLost > 0 && perInvocation > 1) {
        ++oneRayReruns;
        chunkLost = run_chunk(*single, n, 1);
      }
      std::memcpy(hits.data() + start, readHits->mapped(), n * sizeof(shader::Hit));
      lost += chunkLost;
    }
    if (truncated) *truncated = lost;
    if (kernelSeconds) *kernelSeconds = kernelTime;
    timestamps = timed;
    return hits;
  }

  // Adds one submission's float accumulators into the double-precision image,
  // and its counters into the totals.
  void fold(ImageStats& image, uint64_t& truncated) {
    const auto* acc = static_cast<const shader::PixelAccum*>(readAccum->mapped());
    for (size_t p = 0; p < image.pixels(); ++p) add_to_pixel(image, p, acc[p]);
    const auto* counters = static_cast<const uint32_t*>(readCounters->mapped());
    truncated += counters[COUNTER_TRUNCATED];
    image.nonFinite += counters[COUNTER_NONFINITE];
    auto count64 = [counters](uint32_t slot) { return uint64_t(counters[slot]) | uint64_t(counters[slot + 1]) << 32; };
    times.closestHitRays += count64(COUNTER_CLOSEST_RAYS);
    times.shadowRays += count64(COUNTER_SHADOW_RAYS);
  }
};

WavefrontRenderer::WavefrontRenderer(const VulkanContext& ctx, const CompiledScene& scene, const WavefrontSettings& settings)
    : impl_(std::make_unique<Impl>(ctx, scene, settings)) {}

WavefrontRenderer::~WavefrontRenderer() = default;

ImageStats WavefrontRenderer::render(Progress& progress) {
  return impl_->render(progress);
}

const StageTimes& WavefrontRenderer::stage_times() const {
  return impl_->times;
}

uint64_t WavefrontRenderer::one_ray_reruns() const {
  return impl_->oneRayReruns;
}

std::vector<shader::Hit> WavefrontRenderer::cast_shadow_rays(const std::vector<shader::ShadowRay>& rays, uint64_t* truncated,
                                                             double* kernelSeconds, bool coherent) {
  return impl_->cast_rays(rays, truncated, kernelSeconds, coherent, true);
}

std::vector<shader::Hit> WavefrontRenderer::cast_rays(const std::vector<shader::ShadowRay>& rays, uint64_t* truncated,
                                                      double* kernelSeconds, bool coherent) {
  return impl_->cast_rays(rays, truncated, kernelSeconds, coherent, false);
}

std::vector<glm::vec3> WavefrontRenderer::eval_textures(const std::vector<TextureQuery>& queries) {
  std::vector<shader::ShadowRay> rays(queries.size());
  for (size_t i = 0; i < queries.size(); ++i) {
    rays[i].origin = queries[i].p;
    rays[i].dir = glm::vec3(queries[i].uv, 0.0f);
    rays[i].path = queries[i].texture;
  }
  if (!*impl_->texprobe) impl_->texprobe = impl_->make_pipeline(kernel(texprobe_spv));
  std::vector<shader::Hit> out = impl_->run_on_rays(impl_->texprobe, nullptr, rays, nullptr, nullptr);
  std::vector<glm::vec3> colors(out.size());
  for (size_t i = 0; i < out.size(); ++i) colors[i] = glm::vec3(out[i].t, out[i].u, out[i].v);
  return colors;
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
