// `wavepath info`: what the renderer builds for a scene (sizes, BVH, memory,
// the kinds its kernels hold) and, with --kernels, the driver's statistics.
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "gpu/vulkan_context.h"
#include "gpu/wavefront.h"
#include "render/compiled_scene.h"
#include "scene/kinds.h"
#include "scene/load_scene.h"
#include "util/error.h"

namespace wp::cli {

namespace {

// What the renderer would build for a scene: sizes, BVH quality and memory.
int run_info(const std::string& scenePath, int maxLeafSize, const std::string& variant, const std::string* kernelsDevice, bool flatten) {
  RenderOptions options = variant_options(RenderOptions{}, variant);  // an unknown variant fails before any work
  options.photonsOnHost = true;  // the photon map it reports
  if (kernelsDevice && variant == "cpu") throw InputError("--kernels: the cpu reference has no kernels");
  auto t0 = std::chrono::steady_clock::now();
  Scene scene = load_scene(scenePath);
  if (flatten) flatten_instances(scene);
  double loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (maxLeafSize > 0) scene.accelerator.maxLeafSize = maxLeafSize;
  CompiledScene cs = compile_scene(scene, options);
  size_t gpuBytes = cs.gpu_bytes();
  // With instances: the bytes per triangle placed, and the build's rate over
  // the primitives its trees were built over.
  const size_t prims = scene.triangles.size() + scene.spheres.size() + cs.instancing.instancedTriangles;
  const size_t built = scene.triangles.size() + scene.spheres.size() + cs.instancing.instances + cs.instancing.uniqueTriangles;
  std::printf("scene        %s\n", scenePath.c_str());
  std::printf("primitives   %zu triangles, %zu spheres, %zu materials, %u emitters\n", scene.triangles.size(),
              scene.spheres.size(), scene.materials.size(), cs.params.counts.x);
  std::printf("image        %dx%d, %d spp, %u max bounces\n", cs.width, cs.height, cs.spp, cs.params.image.z);
  std::printf("load         %.3f s (parsing and OBJ)\n", loadSeconds);
  bool wide = cs.bvhLayout == BvhLayout::Wide;
  std::printf("BVH          %s, %s, %zu nodes, depth %d, SAH cost %.2f, built in %.3f s (%.3g Mprims/s)\n",
              wide ? "8-wide compressed" : "binary", split_method_name(cs.bvhSplit), wide ? cs.wideNodes.size() : cs.nodes.size(),
              cs.bvhDepth, cs.bvh_sah_cost(), cs.bvhBuildSeconds, cs.bvhBuildSeconds > 0 ? built / cs.bvhBuildSeconds * 1e-6 : 0.0);
  std::printf("GPU scene    %.2f MiB (%.1f bytes per primitive, BVH included; instanced triangles counted as placed)\n", gpuBytes / 1048576.0,
              prims ? double(gpuBytes) / double(prims) : 0.0);
  const InstancingStats& inst = cs.instancing;
  if (inst.instances > 0) {
    // The BVH line above is the top level's tree.
    std::printf("instances    %zu instances of %zu mesh%s: %zu unique triangles place %zu (%.3g per unique one); top level %.2f MiB "
                "(its tree, %zu world triangles and the instances' placeholders and records), meshes' trees and triangles %.2f MiB\n",
                inst.instances, inst.meshes, inst.meshes == 1 ? "" : "es", inst.uniqueTriangles, inst.instancedTriangles,
                inst.uniqueTriangles ? double(inst.instancedTriangles) / double(inst.uniqueTriangles) : 0.0,
                inst.topLevelBytes / 1048576.0, scene.triangles.size(), inst.bottomLevelBytes / 1048576.0);
  }
  if (cs.params.mode.x == INTEGRATOR_PHOTONS) {
    const IntegratorSettings& in = scene.integrator;
    std::printf("photons      %u traced on the host in %.3f s, %zu records (%.2f MiB); the gather takes %s within %g\n", in.photons,
                cs.photonPassSeconds, cs.photons.size(), double(cs.photons.size() * sizeof(shader::Photon)) / 1048576.0,
                in.searchCount > 0 ? ("the " + std::to_string(in.searchCount) + " nearest").c_str() : "every photon", double(in.searchRadius));
  }
  // On a CPU device every branch a kernel has costs each path, taken or not:
  // what the scene uses is what its kernels pay for.
  std::printf("kinds        %s (compiled into the kernels)\n", kinds_description(cs.params.kinds).c_str());
  if (!scene.media.empty()) {
    std::printf("media       ");
    for (size_t i = 0; i < scene.media.size(); ++i) {
      const SceneMedium& m = scene.media[i];
      std::printf(" %s (%s%s)%s", m.name.c_str(), kind_list(medium_kinds(), KIND_BIT(m.kind)).c_str(),
                  scene.cameraMedium == i ? ", the camera's" : "", i + 1 < scene.media.size() ? "," : "\n");
    }
    for (const SceneMedium& m : scene.media) {
      if (!m.grid) continue;
      const DensityGrid& g = *m.grid;
      const glm::ivec3 extent = g.indexMax - g.indexMin + 1;
      const glm::uvec3 cells = majorant_cells(m);
      std::printf("grid         %s: \"%s\" of %s, %dx%dx%d voxels (%llu active, %u leaves), largest density %g, %.2f MiB; "
                  "majorant grid %ux%ux%u\n",
                  m.name.c_str(), g.name.c_str(), g.file.c_str(), extent.x, extent.y, extent.z, (unsigned long long)g.activeVoxels,
                  g.leaves, g.maxDensity, double(g.words.size()) * 4.0 / (1 << 20), cells.x, cells.y, cells.z);
    }
  }
  // gpu-sort shades each class of materials with a kernel of its own kinds.
  std::printf("shade classes");
  for (size_t c = 0; c < cs.shadeClasses.size(); ++c) {
    const glm::uvec4 k = cs.shade_key_kinds(uint32_t(c) + 1);
    std::printf(" %zu: %s / %s;", c, kind_list(material_kinds(), k.x, ", ").c_str(), kind_list(texture_kinds(), k.y, ", ").c_str());
  }
  std::printf(" misses: textures %s (material / texture kinds of each gpu-sort shade kernel)\n",
              kind_list(texture_kinds(), cs.shade_key_kinds(SORT_KEY_MISS).y, ", ").c_str());
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
