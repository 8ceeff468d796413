#include "cli/render_args.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "cpu/reference.h"
#include "gpu/vulkan_context.h"
#include "scene/load_scene.h"
#include "util/error.h"
#include "util/progress.h"

namespace wp::cli {

RenderOptions options_from(const RenderArgs& a, uint32_t seed) {
  RenderOptions options;
  options.spp = a.spp;
  options.maxBounces = a.maxBounces;
  options.seed = seed;
  if (!a.integrator.empty()) {
    options.integrator = integrator_named(a.integrator);
    if (!options.integrator) throw InputError("--integrator: unknown integrator \"" + a.integrator + "\" (expected " + kIntegratorNames + ")");
  }
  options.lightSamples = a.lightSamples;
  options.aovs = a.aovs;
  if (!a.adaptive.empty()) {
    double batch = a.adaptive[0], tolerance = a.adaptive[1];
    if (!(batch >= 1.0 && batch <= 65536.0 && batch == std::floor(batch)))
      throw InputError("--adaptive: the batch size must be a whole number from 1 to 65536, got " + std::to_string(batch));
    if (!(tolerance > 0.0 && tolerance < 1e6)) throw InputError("--adaptive: the tolerance must be positive");
    options.adaptive.batch = int(batch);
    options.adaptive.tolerance = float(tolerance);
  }
  if (!a.sampler.empty()) {
    options.sampler = sampler_named(a.sampler);
    if (!options.sampler) throw InputError("--sampler: unknown sampler \"" + a.sampler + "\" (expected independent or cmj)");
  }
  return options;
}

Scene load_scene_with_overrides(const RenderArgs& a) {
  Scene scene = load_scene(a.scene);
  if (!a.resolution.empty()) {
    scene.camera.width = a.resolution[0];
    scene.camera.height = a.resolution[1];
  }
  if (a.aperture >= 0.0f) scene.camera.apertureRadius = a.aperture;
  if (a.focusDistance > 0.0f) scene.camera.focusDistance = a.focusDistance;
  if (!a.environment.empty()) scene.environment = add_image_texture(scene, a.environment, "given by --env");
  return scene;
}

uint32_t render_on(const std::string& renderer, const CompiledScene& compiled, const RenderArgs& a, ImageStats& image,
                   SampleRange range, const PassHook& afterPass, std::string* where, StageTimes* times) {
  bool progressOn = !a.quiet && Progress::stderr_is_terminal();
  uint64_t total = uint64_t(compiled.width) * uint64_t(compiled.height) * uint64_t(range.size());
  if (renderer == "cpu") {
    Progress progress("cpu", total, progressOn);
    *where = "the CPU reference";
    return render_cpu(compiled, a.threads, image, range, progress, afterPass);
  }
  const KernelVariant& variant = kernel_variant(renderer);  // checked before any Vulkan work
  bool validation = a.validation || VulkanContext::validation_requested_by_environment();
  VulkanContext ctx(a.device, validation);
  uint32_t reached;
  {
    WavefrontRenderer gpu(ctx, compiled, variant.settings);
    Progress progress(ctx.info().name, total, progressOn);
    reached = gpu.render(image, range, progress, afterPass);
    if (times) *times = gpu.stage_times();
  }
  if (ctx.validation_messages() > 0) {
    throw RenderError(std::to_string(ctx.validation_messages()) + " Vulkan validation message(s) reported; no image written");
  }
  *where = ctx.info().name + (variant.name == "gpu" ? "" : ", " + variant.name);
  return reached;
}

ImageStats render_on(const std::string& renderer, const CompiledScene& compiled, const RenderArgs& a, std::string* where,
                     StageTimes* times) {
  ImageStats image(compiled.width, compiled.height, image_layers(compiled.aovs));
  render_on(renderer, compiled, a, image, SampleRange{0, uint32_t(compiled.spp)}, {}, where, times);
  return image;
}

void require_output_directory(const std::string& path) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::is_directory(dir, ec)) throw InputError(path + ": the output directory does not exist");
  if (::access(dir.empty() ? "." : dir.c_str(), W_OK) != 0) throw InputError(path + ": the output directory is not writable");
}

}  // namespace wp::cli
