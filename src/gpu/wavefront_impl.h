// wavefront_impl.h — the GPU renderer's state, shared by the files that
// implement it (src/gpu/): resources and pipelines (pipelines.cpp), the
// wavefront loop (wavefront.cpp), and the ray caster and the probes that
// only the benchmarks and the tests use (ray_caster.cpp). Not part of the
// renderer's interface (wavefront.h).
#pragma once

#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "gpu/vulkan_context.h"
#include "gpu/specialize.h"
#include "gpu/wavefront.h"
#include "util/error.h"

namespace wp {

using shader::KernelPush;

// A kernel's SPIR-V, compiled from shaders/*.comp at build time.
struct Kernel {
  const uint32_t* code;
  size_t bytes;
  Folding folding;  // how far the host folds its constants (gpu/specialize.h)
};

// A kernel, compiled for RGB or for the spectral mode (whose colours carry
// four wavelengths: common.glsl's Spectrum); one whose work is the walk
// (extend, connect, raycast) takes the host's folding of branches only,
// which its loops run faster for. WP_KERNEL(name) names both compiles.
template <size_t N, size_t M>
Kernel kernel(bool spectral, const uint32_t (&rgb)[N], const uint32_t (&spectrum)[M], Folding folding = Folding::ThroughLocals) {
  return spectral ? Kernel{spectrum, M * sizeof(uint32_t), folding} : Kernel{rgb, N * sizeof(uint32_t), folding};
}
#define WP_KERNEL(name) name##_spv, name##_spectral_spv

// Whether a scene's kernels are the spectral mode's.
inline bool spectral_kernels(const shader::SceneParams& p) {
  return (p.kinds.w & KIND_BIT(FEATURE_SPECTRAL)) != 0u;
}

// The bytes of a path's record and of a shadow ray's (types.glsl), in the
// kernels of scene parameters p.
inline uint64_t path_state_bytes(const shader::SceneParams& p) {
  return 16u * (spectral_kernels(p) ? PATH_STATE_TEXELS_SPECTRAL : PATH_STATE_TEXELS_RGB);
}
inline uint64_t shadow_ray_bytes(const shader::SceneParams& p) {
  return 16u * (spectral_kernels(p) ? SHADOW_RAY_TEXELS_SPECTRAL : SHADOW_RAY_TEXELS_RGB);
}

// Every stage reads what the previous one wrote, indirect arguments included.
void stage_barrier(vk::CommandBuffer cb);

// The scene parameters a renderer's kernels and buffers are made for: those
// make_pipeline turns into specialization constants (integrator, light
// samples, BVH layout and stack, kind masks) and the image size the buffers
// hold. The rest the kernels read at run time (update_params).
inline std::tuple<uint32_t, uint32_t, uint32_t, uint32_t, glm::uvec4, glm::uvec4> kernel_defining_params(const shader::SceneParams& p) {
  return {p.image.x, p.image.y, p.mode.x, p.mode.w, p.accel, p.kinds};
}

struct WavefrontRenderer::Impl {
  const VulkanContext& ctx;
  const CompiledScene& scene;
  const shader::SceneParams compiledParams = scene.params;  // as the kernels were made for (update_params)
  WavefrontSettings settings;
  uint32_t capacity = 0;  // path slots per wave
  uint32_t lightSamples = 1;  // shadow rays per path and bounce, at most
  std::vector<std::unique_ptr<Buffer>> buffers;  // indexed by BINDING_*
  std::vector<vk::raii::BufferView> views;        // the texel buffers' views, indexed by BINDING_*
  std::unique_ptr<Buffer> readAccum;
  std::unique_ptr<Buffer> readAovAccum;
  std::unique_ptr<Buffer> readCounters;
  // run_on_rays' transfer buffers, made on first use and kept: a fresh pinned
  // buffer per call made an H100's ray casts 4 to 5 times slower after a few
  // dozen calls. The staging buffer only where the rays' buffer is not mapped.
  std::unique_ptr<Buffer> rayStaging, readHits;
  // trace_photons' read-back of the records, where the shadow-ray buffer is not mapped.
  std::unique_ptr<Buffer> readRecords;
  // Records in the photon map this renderer traced (photonMapLeftToDevice), else the scene's.
  uint32_t photonMapSize = 0;
  double photonPassSeconds = 0.0;  // build_photon_map's wall time
  vk::raii::DescriptorSetLayout setLayout{nullptr};
  vk::raii::PipelineLayout pipelineLayout{nullptr};
  vk::raii::DescriptorPool pool{nullptr};
  vk::raii::DescriptorSet set{nullptr};
  vk::raii::Pipeline generate{nullptr}, prepare{nullptr}, extend{nullptr}, sort{nullptr}, shade{nullptr}, connect{nullptr},
      accumulate{nullptr}, megakernel{nullptr}, raycast{nullptr}, raycastSingle{nullptr}, occlude{nullptr},
      occludeSingle{nullptr}, probe{nullptr}, photons{nullptr};
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

  Impl(const VulkanContext& c, const CompiledScene& s, const WavefrontSettings& st);

  // Makes room for `count` timestamps in the query pool.
  void reserve_queries(uint32_t count);

  void stamp(vk::CommandBuffer cb, Stage stage);

  // Attributes the intervals between a submission's timestamps to stages.
  void collect_times();

  // The scene's arrays, which the kernels read as texel buffers (bindings.glsl):
  // records as RGBA32UI, image texels as RG32UI, the environment CDF as R32F.
  static bool is_texel_binding(uint32_t binding);

  static vk::DescriptorType descriptor_type(uint32_t binding);
  // The texel binding whose buffer a storage binding of the walks' records
  // (BINDING_*_WORDS) views, or `binding` itself.
  static uint32_t walk_records_of(uint32_t binding);

  template <typename T>
  void add_texels(uint32_t binding, const std::vector<T>& data, const char* what, vk::Format format = vk::Format::eR32G32B32A32Uint) {
    add_texels(binding, data.data(), data.size(), what, format);
  }
  template <class T>
  void add_texels(uint32_t binding, const T* data, size_t count, const char* what, vk::Format format = vk::Format::eR32G32B32A32Uint) {
    const bool wide = format == vk::Format::eR32G32B32A32Uint || format == vk::Format::eR32G32B32A32Sfloat;
    const uint64_t texelBytes = wide ? 16 : format == vk::Format::eR32G32Uint ? 8 : 4;
    static_assert(sizeof(T) % 4 == 0);
    if (sizeof(T) % texelBytes != 0) throw RenderError("internal error: a record is not a whole number of texels");
    uint64_t bytes = count * sizeof(T);
    uint64_t maxBytes = ctx.info().maxTexelBufferElements * texelBytes;
    if (bytes > maxBytes) {
      throw RenderError(std::string("the scene's ") + what + " need " + std::to_string(bytes >> 20) + " MiB but " +
                        ctx.info().name + " allows " + std::to_string(maxBytes >> 20) + " MiB per texel buffer");
    }
    // Every scene buffer may also be viewed as a storage buffer (the walks'
    // records are, in the *-loads variants).
    make_buffer(buffers[binding], bytes,
                vk::BufferUsageFlagBits::eUniformTexelBuffer | vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst,
                false);
    if (measured) return;
    ctx.upload(*buffers[binding], data, bytes);
    views[binding] = vk::raii::BufferView(ctx.device(), vk::BufferViewCreateInfo({}, buffers[binding]->handle(),
                                                                                  format, 0, VK_WHOLE_SIZE));
  }

  // Makes a buffer in `slot`, or where `measured` is set, adds its bytes to
  // *measured and makes none: the scene's and the tiles' buffers are
  // counted by the code that makes them, for the messages of a device
  // without room for them.
  uint64_t* measured = nullptr;
  void make_buffer(std::unique_ptr<Buffer>& slot, uint64_t bytes, vk::BufferUsageFlags usage, bool hostVisible);

  void add_work(uint32_t binding, uint64_t bytes, vk::BufferUsageFlags extra = {});

  // A work buffer the kernels also read as RGBA32UI texels, through `view`.
  void add_readable_work(uint32_t binding, uint32_t view, uint64_t bytes, vk::Format format = vk::Format::eR32G32B32A32Uint);

  // The scene's arrays, which every tile reads.
  void create_scene_buffers();
  // The buffers of paths, rays and accumulators, for `capacity` path slots
  // and tiles of `tilePixels`; and where the device has no room for them,
  // freed again.
  void create_tile_buffers();
  void release_tile_buffers();
  // The bytes of device memory the scene's buffers, or the tiles', take.
  uint64_t measure(void (Impl::*create)());
  // Makes the tile buffers, in smaller tiles (and fewer path slots) where
  // the device has no room for them (WavefrontRenderer's constructor).
  void fit_tile_buffers(uint64_t maxRange);

  // Lavapipe ends all loops of an invocation after 65,535 iterations in all,
  // silently. The wavefront kernels trace one ray per invocation, so each ray
  // may take the scene's whole cap. The megakernel traces every ray of a path
  // in one invocation: up to max bounces + 1 closest-hit rays and light
  // samples x max bounces shadow rays, and the bounce loop's own iterations.
  uint32_t traversal_step_cap() const;
  // The scene's parameters as the kernels get them: the step cap of
  // traversal_step_cap (or, wholeCap, the scene's own, for kernels that
  // trace one ray an invocation), the photon map's size.
  shader::SceneParams device_params(bool wholeCap = false) const;
  // Extend-shade-connect passes per wave: path_passes_max (integrator.glsl).
  uint32_t path_passes() const {
    const bool interfaces = (scene.params.kinds.w & KIND_BIT(FEATURE_MEDIA)) && (scene.params.kinds.x & KIND_BIT(MAT_INTERFACE));
    return scene.params.image.z + 1 + (interfaces ? MEDIUM_CROSSINGS_MAX : 0u);
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
  uint32_t rays_per_invocation() const;
  // Samples of a pixel one megakernel invocation renders (WavefrontSettings),
  // and the traversal steps each of their rays gets of lavapipe's loop budget.
  uint32_t megakernel_samples() const;
  uint64_t megakernel_steps_per_ray(uint64_t paths) const;
  static constexpr uint32_t kRaysPerInvocationOnCpus = 16;
  static constexpr int kMultiRayMinDepth = 4;

  uint32_t groups_for(uint32_t n) const;

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
  uint32_t interleaved_groups(uint32_t n) const;

  // Workgroups of the ray caster (or the probes) for n rays, perInvocation to
  // an invocation. One ray to an invocation rounds up to whole rows of the
  // interleave; probe, which does not interleave, takes the extra
  // workgroups' items as out of range.
  uint32_t tracing_groups(uint32_t n, uint32_t perInvocation) const;
  // The fewest invocations of a tracing dispatch that shares rays among a
  // subgroup's lanes: 0 on CPU devices (TRACING_INVOCATIONS_ON_GPUS).
  uint32_t tracing_fill() const;

  // Queues of paths in the queue buffer: the two that alternate between
  // bounces and, sorting, the sort keys' (the misses and each class).
  uint32_t queue_count() const { return QUEUE_SORTED + (sorting ? 1 + uint32_t(scene.shadeClasses.size()) : 0); }

  // Whether the wavefront kernels sort paths by material class.
  bool sort_by_material() const { return settings.sortByMaterial && !settings.megakernel; }

  // lavapipe and other CPU implementations: SIMD lanes in a loop, private
  // arrays in memory (the stack and rays-per-invocation choices follow).
  bool cpu_device() const { return ctx.info().type == "cpu"; }

  // Every kernel, by name, whether or not this renderer made it.
  std::vector<std::pair<std::string, const vk::raii::Pipeline*>> kernels() const;

  // How a pipeline specializes its kernel beyond the renderer's settings.
  struct PipelineOptions {
    bool single = false;       // a tracing kernel takes one ray per invocation, whatever tracingRays says
    bool interleaved = false;  // workgroups dealt out in columns (workgroup_interleave)
    bool anyHit = false;       // the ray caster looks for any hit, not the closest
    uint32_t shadeKey = SORT_KEYS;  // shade: the sort key it shades (SORT_KEYS: all paths, unsorted)
  };

  // Kernel `WP_KERNEL(name)` as this renderer's scene runs it (RGB or spectral).
  template <size_t N, size_t M>
  Kernel kernel(const uint32_t (&rgb)[N], const uint32_t (&spectrum)[M], Folding folding = Folding::ThroughLocals) const {
    return wp::kernel(spectral_kernels(compiledParams), rgb, spectrum, folding);
  }
  vk::raii::Pipeline make_pipeline(Kernel k) { return make_pipeline(k, PipelineOptions()); }
  vk::raii::Pipeline make_pipeline(Kernel k, PipelineOptions o);

  // The kernels whose code depends on tracingRays, (re)made from it.
  void create_tracing_pipelines();

  void create_pipelines();

  void dispatch(vk::CommandBuffer cb, const vk::raii::Pipeline& p, const KernelPush& push, uint32_t groups, Stage stage);

  // `last`: the barrier and the timestamp after it; false for a dispatch that
  // may run beside the next one (which times both).
  void dispatch_indirect(vk::CommandBuffer cb, const vk::raii::Pipeline& p, const KernelPush& push, uint32_t slot, Stage stage,
                         bool last = true);

  // One wave: a sample for `pathCount` pixels from `waveStart`, all bounces.
  // One wave: `samples` consecutive samples, from sampleIndex, of `span`
  // pixels from waveStart (span x samples paths).
  void record_wave(vk::CommandBuffer cb, uint32_t waveStart, uint32_t span, uint32_t sampleIndex, uint32_t samples, bool listed,
                   uint32_t accumBase);
  // The samples a wave of a tile of `pixels` holds: as many as its path
  // slots take (a sample of a small image is a short wave, and on CPU devices
  // a dispatch costs about 80 us whatever its size), one for the megakernel,
  // which adds each path to its pixel as it ends.
  uint32_t samples_per_wave(uint32_t pixels) const;

  // A tile: pixels [base, base + span) of the image, whose accumulators the
  // device holds at once. Consecutive pixels: waves over the span; listed
  // (adaptive sampling): `count` entries of the pixel list from `first`, all
  // within the span.
  struct Tile {
    uint32_t base = 0, span = 0;
    uint32_t first = 0, count = 0;
  };
  // The tiles of `count` consecutive pixels, or of the ascending `list`.
  std::vector<Tile> tiles_of(uint32_t count, const std::vector<uint32_t>* list) const;
  // Pixels a tile holds: as many as the device's buffers allow, at most
  // settings.maxTilePixels.
  uint32_t tilePixels = 0;

  // Renders samples `range` of every pixel into `image`; with adaptive
  // sampling, in batches, dropping the pixels that have converged after
  // each batch. Returns the sample reached (WavefrontRenderer::render).
  uint32_t render(ImageStats& image, SampleRange range, Progress& progress, const PassHook& afterPass);

  // Samples [first, end) of the image's pixels, or (list) of the listed
  // ones, tile after tile each round of samples. Folds the results into
  // `image`. Calls `afterPass` (if any) after each round, when every pixel
  // has the same samples, and stops where it returns false; returns the
  // sample reached. A lost device's DeviceLost says the sample the image
  // holds for every pixel (a round's start).
  uint32_t render_samples(ImageStats& image, uint64_t& truncated, Progress& progress, uint32_t first, uint32_t end,
                          const std::vector<uint32_t>* list, const PassHook& afterPass);
  // One submission: samples [sample, sample + n) of a tile; its seconds.
  double submit_tile(vk::CommandBuffer cb, const vk::raii::Fence& fence, const Tile& tile, uint32_t sample, uint32_t n, bool listed);

  // The ray caster (raycast.comp), made on first use: renders never need it.
  // single: one ray per invocation; anyHit: the shadow rays' query. One ray
  // per invocation is for coherent rays, in image order, so the workgroups
  // are interleaved (the multi-ray loop spreads its items by itself). For the
  // benchmark's shadow rays from camera hits, interleaving took the Cornell
  // dragon from 0.37-0.38 to 0.47-0.48 of Embree.
  const vk::raii::Pipeline& ray_caster(bool single, bool anyHit);

  void write_shadow_rays(void* mapped, const shader::ShadowRay* rays, uint32_t n) const;
  std::vector<shader::Hit> cast_rays(const std::vector<shader::ShadowRay>& rays, uint64_t* truncated, double* kernelSeconds,
                                     bool coherent, bool anyHit);

  // Runs `kernel` (a ray caster or the probe kernel) over `rays` in chunks of the path
  // capacity: each ray in the shadow-ray buffer, each result in the hit
  // buffer. A ray caster taking tracingRays rays per invocation names
  // `single`, its one-ray pipeline, for chunks where a ray outran its share
  // of the loop budget.
  std::vector<shader::Hit> run_on_rays(const vk::raii::Pipeline& kernel, const vk::raii::Pipeline* single,
                                       const std::vector<shader::ShadowRay>& rays, uint64_t* truncated, double* kernelSeconds);

  // The photons kernel (photons.comp), made on first use: the records of
  // `count` photons of `seed`, in the order the host's trace_photons gives
  // them (photon_pass.h). Throws RenderError where a photon's ray outran the
  // step cap.
  std::vector<shader::Photon> trace_photons(uint32_t count, uint32_t seed);

  static constexpr uint64_t kPhotonBatch = 1u << 18;
  // Waves of a small image: several samples each, up to this many paths (a
  // few MiB of path state) and this many samples (accumulate's loop a pixel).
  static constexpr uint64_t kSmallImageWavePaths = 1u << 16;
  static constexpr uint32_t kMaxSamplesPerWave = 256;
  // Traces the scene's photons (photonMapLeftToDevice; settings.photonPass
  // says where), balances them into the map and binds it in place of the
  // scene's empty one.
  void build_photon_map();

  // Adds a submission's float sums of `tile`'s pixels (and their AOVs',
  // where the image has AOV layers) into the double-precision image.
  void fold(ImageStats& image, const Tile& tile, const shader::PixelAccum* acc, const shader::AovAccum* aov);
  // Adds the last submission's counters into the totals (truncated rays,
  // traced rays); returns its non-finite samples.
  uint64_t fold_counters(uint64_t& truncated);
};

}  // namespace wp
