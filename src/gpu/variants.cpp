// The kernel variants `--variant` and `wavepath bench` choose from; which are
// kept, and why, is in docs/benchmarks.md.
#include "cpu/reference.h"
#include "gpu/wavefront.h"
#include "util/error.h"

namespace wp {

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
    WavefrontSettings multiRayFetch = multiRay;
    multiRayFetch.dynamicFetch = true;
    WavefrontSettings loads;
    loads.walkLoads = true;
    WavefrontSettings megaRegen = megakernel;
    megaRegen.megakernelSamples = 4;
    WavefrontSettings megaLoads = megakernel;
    megaLoads.walkLoads = true;
    std::vector<KernelVariant> v{
        {"gpu", "wavefront kernels, 8-wide compressed BVH, workgroups of 64", WavefrontSettings{}, BvhLayout::Wide},
        {"gpu-greedy", "wavefront kernels, wide BVH collapsed greedily (largest child opened first) instead of by SAH",
         WavefrontSettings{}, BvhLayout::Wide, false, WideCollapse::Greedy},
        {"gpu-nearest", "wavefront kernels, the wide walk taking each node's hit children nearest first (sorted by entry distance) in every scene (gpu: in scenes with instances)",
         WavefrontSettings{}, BvhLayout::Wide, false, WideCollapse::Sah, WideChildOrder::Distance},
        {"gpu-octant", "wavefront kernels, the wide walk taking each node's hit children in its ray's octant order in every scene (gpu: in scenes without instances)",
         WavefrontSettings{}, BvhLayout::Wide, false, WideCollapse::Sah, WideChildOrder::Octant},
        {"gpu-enter-root", "wavefront kernels, the wide walk visiting an instance's root in the iteration that enters it (a dependent load more, an iteration fewer)",
         WavefrontSettings{}, BvhLayout::Wide, false, WideCollapse::Sah, WideChildOrder::Auto, true},
        {"gpu-bvh2", "wavefront kernels, binary BVH, workgroups of 64", WavefrontSettings{}, BvhLayout::Binary},
        {"gpu-nocompact", "wavefront kernels without path compaction: every bounce runs over every path", noCompaction,
         BvhLayout::Wide},
        {"gpu-mega", "one kernel per path (camera ray to pixel), its rays sharing lavapipe's loop budget", megakernel,
         BvhLayout::Wide},
        {"gpu-mega-bvh2", "one kernel per path over the binary BVH (whose walk suits incoherent rays on GPUs)", megakernel,
         BvhLayout::Binary},
        {"gpu-clustered", "wavefront kernels, wide BVH from the clustered SAH build (Morton clusters at the top, exact sweep at the bottom)",
         WavefrontSettings{}, BvhLayout::Wide, true},
        {"gpu-sort", "wavefront kernels, paths sorted by the class of material their ray hit, each class shaded by a kernel holding only its kinds", sorted,
         BvhLayout::Wide},
        {"gpu-regstack", "wavefront kernels, the wide walk's stack in registers on every device (gpu: on CPU devices)",
         registerStack, BvhLayout::Wide},
        {"gpu-memstack", "wavefront kernels, the wide walk's stack in an indexed array on every device (gpu: on GPUs)",
         indexedStack, BvhLayout::Wide},
        {"gpu-oneray", "wavefront kernels, one ray per invocation of the tracing kernels (gpu: 16 on CPU devices, for trees of depth 4 or more)",
         oneRay, BvhLayout::Wide},
        {"gpu-multiray", "wavefront kernels, 16 rays per invocation of the tracing kernels (shared within subgroups) on every device and tree", multiRay,
         BvhLayout::Wide},
        {"gpu-multiray-fetch", "gpu-multiray, its subgroups taking their blocks of rays from a counter as they need them", multiRayFetch,
         BvhLayout::Wide},
        {"gpu-loads", "wavefront kernels, the walk reading nodes and primitives by storage-buffer loads instead of texel fetches", loads,
         BvhLayout::Wide},
        {"gpu-bvh2-fused", "wavefront kernels, binary BVH, each iteration of its walk testing a primitive and visiting a node (speculative traversal)",
         WavefrontSettings{}, BvhLayout::Binary, false, WideCollapse::Sah, WideChildOrder::Auto, false, true},
        {"gpu-mega-bvh2-fused", "one kernel per path over the binary BVH, each iteration of its walk testing a primitive and visiting a node",
         megakernel, BvhLayout::Binary, false, WideCollapse::Sah, WideChildOrder::Auto, false, true},
        {"gpu-mega-bvh2-regen", "one kernel per path over the binary BVH, an invocation rendering 4 samples of its pixel, each lane beginning its next path as one ends",
         megaRegen, BvhLayout::Binary},
        {"gpu-bvh2-loads", "wavefront kernels, binary BVH, its walk reading nodes and primitives by storage-buffer loads", loads,
         BvhLayout::Binary},
        {"gpu-mega-bvh2-loads", "one kernel per path over the binary BVH, its walk reading nodes and primitives by storage-buffer loads",
         megaLoads, BvhLayout::Binary}};
    return v;
  }();
  return variants;
}

namespace {

// The default variant of each class of device: the first row that matches
// wins, and a device no row matches gets the wavefront kernels. Each row is
// the winner of a measurement in docs/benchmarks.md ("The default variant of
// each device").
struct DeviceDefault {
  const char* type;    // GpuDeviceInfo::type, or "" for any
  const char* driver;  // text in GpuDeviceInfo::driver, or "" for any
  const char* variant;
};
constexpr DeviceDefault kDeviceDefaults[] = {
    // lavapipe: the megakernel is slower (its rays share the loop budget),
    // and the binary tree's walk too.
    {"cpu", "", "gpu"},
    // H100 and H200: one kernel per path over the binary tree, 1.7x the
    // wavefront kernels on the Cornell dragon (H200).
    {"", "NVIDIA", "gpu-mega-bvh2"},
};

}  // namespace

const KernelVariant& default_variant(const GpuDeviceInfo& device) {
  for (const DeviceDefault& row : kDeviceDefaults) {
    if (*row.type && device.type != row.type) continue;
    if (*row.driver && device.driver.find(row.driver) == std::string::npos) continue;
    return kernel_variant(row.variant);
  }
  return kernel_variant("gpu");
}

std::string resolve_variant(const std::string& variant, const std::string& deviceSelector) {
  if (!variant.empty()) return kernel_variant(variant).name;
  return default_variant(VulkanContext::selected_device(deviceSelector)).name;
}

RenderOptions variant_options(RenderOptions options, const std::string& renderer) {
  if (renderer == "cpu") return reference_options(options);
  const KernelVariant& v = kernel_variant(renderer);
  options.bvhLayout = v.bvhLayout;
  options.clusteredBuild = v.clusteredBuild;
  options.wideCollapse = v.wideCollapse;
  options.wideChildOrder = v.wideChildOrder;
  options.rootAtEntry = v.rootAtEntry;
  options.binaryFused = v.binaryFused;
  options.photonsOnHost = false;  // the renderer traces the photon map with its kernels
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

}  // namespace wp
