// `wavepath info`: what the renderer builds for a scene (sizes, BVH, memory,
// the kinds its kernels hold) and, with --kernels, the driver's statistics.
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "gpu/vulkan_context.h"
#include "gpu/wavefront.h"
#include "render/compiled_scene.h"
#include "job/scene_info.h"
#include "scene/load_scene.h"
#include "util/error.h"

namespace wp::cli {

namespace {

// What the renderer would build for a scene: sizes, BVH quality and memory.
int run_info(const std::string& scenePath, int maxLeafSize, const std::string& variant, const std::string* kernelsDevice, bool flatten) {
  const RenderOptions options = info_options(RenderOptions{}, variant);  // an unknown variant fails before any work
  if (kernelsDevice && variant == "cpu") throw InputError("--kernels: the cpu reference has no kernels");
  auto t0 = std::chrono::steady_clock::now();
  Scene scene = load_scene(scenePath);
  if (flatten) flatten_instances(scene);
  double loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (maxLeafSize > 0) scene.accelerator.maxLeafSize = maxLeafSize;
  CompiledScene cs = compile_scene(scene, options);
  std::fputs(scene_info(scenePath, scene, cs, loadSeconds).c_str(), stdout);
  if (kernelsDevice) {
    // The variant's kernels as the device's compiler built them for this scene.
    VulkanContext ctx(*kernelsDevice, VulkanContext::validation_requested_by_environment());
    WavefrontSettings settings = kernel_variant(variant).settings;
    settings.captureStatistics = true;
    WavefrontRenderer renderer(ctx, cs, settings);
    std::vector<KernelStatistics> kernels = renderer.kernel_statistics();
    std::printf("kernels      as compiled for %s (%s):\n", ctx.info().name.c_str(), ctx.info().driver.c_str());
    for (const KernelStatistics& k : kernels) {
      std::printf("  %s (%s):", k.kernel.c_str(), k.executable.c_str());
      for (const auto& [name, value] : k.values) std::printf(" %s %s;", name.c_str(), value.c_str());
      std::printf("\n");
    }
  }
  return 0;
}

}  // namespace

Command add_info(CLI::App& app) {
  struct InfoArgs {
    std::string scene;
    int maxLeafSize = 0;
    std::string variant = "gpu";
    std::string device;
    bool flatten = false;
  };
  auto a = std::make_shared<InfoArgs>();
  CLI::App* info = app.add_subcommand("info", "load a scene, build its BVH and report sizes, build time and memory");
  info->add_option("scene", a->scene, "scene file (darts JSON, glTF 2.0)")->required();
  info->add_option("--max-leaf-size", a->maxLeafSize, "override the scene's BVH leaf size")->check(CLI::Range(1, BVH_MAX_LEAF_SIZE));
  info->add_option("--variant", a->variant, "the kernel variant (or cpu) whose BVH layout to build; default gpu");
  info->add_flag("--flatten-instances", a->flatten, "place every instance's triangles in world space, as one flat BVH");
  CLI::Option* infoKernels = info->add_flag("--kernels", "also compile the variant's kernels and show the driver's statistics of each (registers, spills, ...)");
  info->add_option("--device", a->device, "Vulkan device for --kernels: index or part of the name")->needs(infoKernels);
  return {info, [a, infoKernels] { return run_info(a->scene, a->maxLeafSize, a->variant, *infoKernels ? &a->device : nullptr, a->flatten); }};
}

}  // namespace wp::cli
