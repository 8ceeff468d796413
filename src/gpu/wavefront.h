// wavefront.h — the GPU renderer: wavefront path tracing as separate compute
// pipelines (generate, extend, shade, connect, accumulate) over path queues in
// storage buffers. See docs/architecture.md for the stage-by-stage picture.
#pragma once

#include <string>
#include <vector>

#include "gpu/vulkan_context.h"
#include "image/image.h"
#include "render/compiled_scene.h"
#include "render/render_control.h"
#include "util/progress.h"

namespace wp {

// GPU time per pipeline stage, from Vulkan timestamp queries written after
// every dispatch of a render, and the rays the render traced.
struct StageTimes {
  enum Stage { kGenerate, kPrepare, kExtend, kSort, kShade, kConnect, kAccumulate, kMegakernel, kStages };
  static constexpr const char* kNames[kStages] = {"generate", "prepare", "extend", "sort", "shade", "connect", "accumulate", "megakernel"};
  double seconds[kStages] = {};
  uint64_t dispatches[kStages] = {};
  uint64_t closestHitRays = 0;  // extension rays (camera rays included)
  uint64_t shadowRays = 0;      // next-event estimation's any-hit rays
  // The photon map this renderer traced (photonMapLeftToDevice): the pass's
  // wall time (the photons kernel, ordering, balancing, upload) and records.
  double photonPassSeconds = 0.0;
  uint64_t photonRecords = 0;
  // The host's part of every submission: its sums read back and added to
  // the image in double (a tiled round's first held until the round ends),
  // in wall seconds; and the submissions.
  double foldSeconds = 0.0;
  uint64_t submissions = 0;
  // Rays per second of GPU time in the stage that traced them; 0 where that
  // stage did not run (the megakernel traces every ray in one kernel).
  double closest_hit_rays_per_second() const { return seconds[kExtend] > 0.0 ? double(closestHitRays) / seconds[kExtend] : 0.0; }
  double shadow_rays_per_second() const { return seconds[kConnect] > 0.0 ? double(shadowRays) / seconds[kConnect] : 0.0; }
  double total() const {
    double t = 0.0;
    for (double s : seconds) t += s;
    return t;
  }
};

// Where the wide BVH walk keeps its traversal stack (scene.glsl): in registers,
// every entry moved by selects on a push or a pop, or in an indexed array.
// Auto picks registers on CPU devices (lavapipe reaches an indexed private
// array lane by lane, through memory: 10-17 % slower walks on meshes) and the
// indexed array on GPUs (the register stack costs an H100 24 registers a
// thread and 2-14 % of its ray rate; docs/benchmarks.md).
enum class TraversalStack { Auto, Registers, Indexed };

// Who traces a photon map the scene left to its renderer
// (CompiledScene::photonMapLeftToDevice). Auto: the photons kernel on GPUs,
// the host's code (photon_pass.h) beside a CPU device, where lavapipe
// traced 2M photons 1.3 to 2.5 times slower than the same code compiled
// for the host (docs/benchmarks.md).
enum class PhotonPass { Auto, Kernels, Host };

struct WavefrontSettings {
  PhotonPass photonPass = PhotonPass::Auto;
  uint32_t workgroupSize = WORKGROUP_SIZE;  // invocations per workgroup of every kernel
  TraversalStack stack = TraversalStack::Auto;  // the wide walk's stack (the binary walk always indexes)
  bool compaction = true;                   // later bounces dispatch only live paths (kernel.glsl)
  bool megakernel = false;                  // one kernel per path instead of the wavefront stages
  // Samples of its pixel one megakernel invocation renders, one after
  // another, a lane starting the next as its path ends (megakernel.comp).
  uint32_t megakernelSamples = 1;
  // Paths sorted by the class of material their rays hit, each class shaded
  // by a kernel holding only its kinds (types.glsl, SORT_KEYS). Off by
  // default: on lavapipe it cut shade by 30-55 % on scenes that mix
  // textured, glass or blended materials with plain ones, but the sort and
  // one more kernel per class (0.17 s each to make) repaid that only on some
  // scenes on two cores (docs/benchmarks.md); GPUs are not measured yet.
  bool sortByMaterial = false;
  uint32_t maxPathsPerWave = 1u << 20;  // path slots; a larger image runs in several waves
  // Pixels whose accumulators the device holds at once (0: as many as one
  // storage buffer allows); a larger image renders in tiles of this many
  // consecutive pixels, each round of samples tile after tile.
  uint32_t maxTilePixels = 0;
  double targetSubmitSeconds = 0.5;     // samples per submission grow until one takes about this long
  bool captureStatistics = false;       // keep the driver's statistics of each pipeline (kernel_statistics)
  bool specializeSpirv = true;          // apply the specialization constants to the SPIR-V before the driver (gpu/specialize.h)
  uint32_t raysPerInvocation = 0;       // of the tracing kernels; 0: 16 on CPU devices for a wide BVH of depth 4 or more, else 1
  bool walkLoads = false;               // the walks read nodes and primitives by storage-buffer loads, not texel fetches (bindings.glsl)
  bool dynamicFetch = false;            // subgroups sharing rays take their blocks of rays from a counter, not in turn (trace_items.glsl)
};

// What the driver reports about one compiled kernel (VK_KHR_pipeline_executable_properties):
// per executable, named statistics such as registers or spilled bytes.
struct KernelStatistics {
  std::string kernel;      // generate, extend, ...
  std::string executable;  // the driver's name for the compiled code
  std::vector<std::pair<std::string, std::string>> values;  // statistic name, value
};

// Named kernel variants, selectable on the command line ("gpu" is the default).
// The BVH layout is chosen when the scene is compiled: compile it with
// `variant_options` before handing it to the variant's renderer.
struct KernelVariant {
  std::string name;
  std::string description;
  WavefrontSettings settings;
  BvhLayout bvhLayout = BvhLayout::Wide;
  bool clusteredBuild = false;  // the BVH built by SplitMethod::ClusteredSah where the scene's build would be binned SAH
  WideCollapse wideCollapse = WideCollapse::Sah;  // how the wide BVH's nodes are picked from the binary tree
  WideChildOrder wideChildOrder = WideChildOrder::Auto;  // how the wide walk orders a node's hit children
  bool rootAtEntry = false;  // RenderOptions::rootAtEntry
  bool binaryFused = false;  // RenderOptions::binaryFused
};
const std::vector<KernelVariant>& kernel_variants();
// Throws InputError naming the known variants if `name` is not one of them.
const KernelVariant& kernel_variant(const std::string& name);
// The variant a device renders with unless told otherwise: one table in
// variants.cpp, device class to variant, filled from measurements.
const KernelVariant& default_variant(const GpuDeviceInfo& device);
// `variant` (checked), or where it is empty the default of the device
// `deviceSelector` picks (VulkanContext::selected_device). Called before a
// scene is compiled, since a variant may choose the BVH layout.
std::string resolve_variant(const std::string& variant, const std::string& deviceSelector);
// `options` with the compile-time choices of `renderer`: a kernel variant's
// name (its BVH; a photon map left to its kernels), or "cpu" for the CPU
// reference (reference_options).
RenderOptions variant_options(RenderOptions options, const std::string& renderer);

class WavefrontRenderer {
 public:
  // Where the device's memory cannot hold the buffers of the image's tiles
  // (DeviceOutOfMemory), tries tiles of half as many pixels, down to one
  // row, saying so on stderr: tiles render the same image. Throws
  // RenderError naming the memory needed and the device's where even the
  // scene or one row does not fit.
  WavefrontRenderer(const VulkanContext& ctx, const CompiledScene& scene, const WavefrontSettings& settings = {});
  ~WavefrontRenderer();
  // Renders samples `range` of every pixel, adding them to `image` (which
  // may hold earlier samples: a resumed render) and calling `afterPass`
  // between passes (render_control.h). Returns the sample every pixel
  // reached: range.end, or where afterPass stopped the render. Throws
  // RenderError if a traversal was truncated (the image would be wrong),
  // and DeviceLost where the device is lost (vulkan_context.h): its
  // `reached` is the sample every pixel of `image` then holds, `intact`
  // whether the image holds just those (an image in tiles gets a round's
  // sums once every tile has them; under adaptive sampling a batch part
  // done breaks it).
  uint32_t render(ImageStats& image, SampleRange range, Progress& progress, const PassHook& afterPass = {});
  // All of the scene's samples, 0 to scene.spp, into a new image.
  ImageStats render(Progress& progress);
  // Uploads the scene's parameters again after the caller changed those the
  // kernels read at run time (the camera, max bounces, the seed; `wavepath
  // view`). Throws RenderError if a change needs other kernels (image size,
  // integrator, kinds, light samples): make a new renderer for those.
  void update_params();
  // Per-stage GPU time of the last render (zero where the device has no timestamps).
  const StageTimes& stage_times() const;
  // How often work was done again one ray per invocation because a ray
  // outran its share of lavapipe's loop budget in a tracing kernel taking
  // several (trace_items.glsl): ray chunks of cast_rays and
  // cast_shadow_rays, and submissions of render (after which the renderer
  // keeps one ray per invocation). 0 where every ray fit its share.
  uint64_t one_ray_reruns() const;
  // Closest hits of arbitrary rays, no shading (BVH tests, traversal benchmarks).
  // Each ray is origin, dir and tmax of a ShadowRay. Truncated traversals are
  // counted in *truncated (if given) and reported as misses. *kernelSeconds
  // (if given) receives the GPU time of the raycast dispatches alone, from
  // timestamps (0 where the device has none). `coherent` says the rays are
  // like camera rays, neighbours in the array close in origin and direction,
  // as Embree's coherent-context hint does: on CPU devices they are then
  // traced one per invocation.
  std::vector<shader::Hit> cast_rays(const std::vector<shader::ShadowRay>& rays, uint64_t* truncated = nullptr,
                                     double* kernelSeconds = nullptr, bool coherent = false);
  // The same for shadow rays: any hit, not the closest (a hit's prim is valid
  // where the segment is blocked; its t is some hit's, not the nearest).
  // Shadow rays from camera hits, in image order, are coherent.
  std::vector<shader::Hit> cast_shadow_rays(const std::vector<shader::ShadowRay>& rays, uint64_t* truncated = nullptr,
                                            double* kernelSeconds = nullptr, bool coherent = false);

  // The kernels' texture_eval at each query, for comparing GLSL with C++.
  struct TextureQuery {
    uint32_t texture;
    glm::vec2 uv;
    glm::vec3 p;
  };
  std::vector<glm::vec3> eval_textures(const std::vector<TextureQuery>& queries);

  // The probes of probes.glsl (run_probe) on the GPU, one answer a query
  // (an intersection past the step cap answers PROBE_TRUNCATED).
  std::vector<shader::Hit> run_probes(const std::vector<shader::ShadowRay>& queries);

  // The photons kernel's records of `count` photons of `seed` through the
  // scene, in the host's order and with each one's photon in `axis`
  // (trace_photons in photon_pass.h, which the tests compare).
  std::vector<shader::Photon> trace_photons(uint32_t count, uint32_t seed);

  // The driver's statistics of every kernel this renderer compiled. Needs
  // settings.captureStatistics; throws RenderError naming the device if its
  // driver reports none.
  std::vector<KernelStatistics> kernel_statistics() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wp
