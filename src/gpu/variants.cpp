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
    std::vector<KernelVariant> v{
        {"gpu", "wavefront kernels, 8-wide compressed BVH, workgroups of 64", WavefrontSettings{}, BvhLayout::Wide},
        {"gpu-greedy", "wavefront kernels, wide BVH collapsed greedily (largest child opened first) instead of by SAH",
         WavefrontSettings{}, BvhLayout::Wide, false, WideCollapse::Greedy},
        {"gpu-bvh2", "wavefront kernels, binary BVH, workgroups of 64", WavefrontSettings{}, BvhLayout::Binary},
        {"gpu-nocompact", "wavefront kernels without path compaction: every bounce runs over every path", noCompaction,
         BvhLayout::Wide},
        {"gpu-mega", "one kernel per path (camera ray to pixel), its rays sharing lavapipe's loop budget", megakernel,
         BvhLayout::Wide},
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
         BvhLayout::Wide}};
    return v;
  }();
  return variants;
}

RenderOptions variant_options(RenderOptions options, const std::string& renderer) {
  if (renderer == "cpu") return reference_options(options);
  const KernelVariant& v = kernel_variant(renderer);
  options.bvhLayout = v.bvhLayout;
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

}  // namespace wp
