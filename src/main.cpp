// wavepath — a wavefront path tracer on Vulkan compute, with a CPU reference.
//
//   wavepath render SCENE.json [-o out.png] [--exr PATH] [--spp N] [--max-bounces N] [--seed N] [--resolution W H]
//                   [--integrator NAME] [--sampler NAME] [--aperture R] [--focus-distance D] [--env MAP]
//                   (CS184: -f -s -m -r -t -b -d -e)
//                              [--device INDEX|NAME] [--variant NAME] [--cpu] [--threads N] [--quiet] [--stage-times]
//   wavepath compare SCENE.json [--a VARIANT|cpu] [--b cpu|VARIANT] [--spp N] [--report DIR]
//   wavepath compare --images A.exr B.exr [--report DIR]
//   wavepath bench [--scenes LIST] [--variants LIST] [--spp N] [--repeats N] [--raycast | --build] [--out results.json] [--csv results.csv]
//   wavepath devices
//   wavepath info SCENE.json [--max-leaf-size N] [--variant NAME|cpu]
//
// Exit status: 0 success (compare: the images agree), 1 compare: they differ
// (bench: a variant disagreed with the CPU reference and was not timed),
// 2 bad input (scene, mesh, options), 3 rendering failed (no Vulkan device, out
// of memory, validation messages, truncated traversal).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <unistd.h>

#include "bench/bench.h"
#include "cpu/reference.h"
#include "gpu/vulkan_context.h"
#include "gpu/wavefront.h"
#include "image/image.h"
#include "render/compiled_scene.h"
#include "report/html_report.h"
#include "stats/compare.h"
#include "scene/kinds.h"
#include "scene/load_scene.h"
#include "util/error.h"
#include "util/progress.h"

namespace {

using namespace wp;

struct RenderArgs {
  std::string scene;
  std::string output;
  std::string exr;
  int spp = -1;
  int maxBounces = -1;
  uint32_t seed = 0;
  std::string device;
  bool cpu = false;
  int threads = 0;
  bool quiet = false;
  bool validation = false;
  std::vector<int> resolution;
  bool stageTimes = false;
  std::string variant = "gpu";
  std::string integrator;  // darts integrator name, overriding the scene's
  std::string sampler;     // independent or cmj
  float aperture = -1.0f;  // lens radius, overriding the scene's (CS184 -b)
  float focusDistance = -1.0f;  // (CS184 -d)
  std::string environment;      // environment map replacing the background (CS184 -e)
  std::vector<double> adaptive;  // batch, tolerance (CS184 -a)
  int lightSamples = 1;          // NEE samples per vertex (CS184 -l)
};

// CS184 writes the sample-rate image of out.png as out_rate.png.
std::string rate_image_path(const std::string& out) {
  std::filesystem::path p(out);
  return (p.parent_path() / (p.stem().string() + "_rate.png")).string();
}

std::string default_output(const std::string& scenePath) {
  return std::filesystem::path(scenePath).stem().string() + ".png";
}

// Renders with `renderer`: "cpu" (the reference) or a kernel variant ("gpu",
// "gpu-wg128", ...) on the chosen Vulkan device. Sets *where to a description
// of what rendered it, and *times (if given) to the GPU's per-stage times.
ImageStats render_on(const std::string& renderer, const CompiledScene& compiled, const RenderArgs& a, std::string* where,
                     StageTimes* times = nullptr) {
  bool progressOn = !a.quiet && Progress::stderr_is_terminal();
  uint64_t total = uint64_t(compiled.width) * uint64_t(compiled.height) * uint64_t(compiled.spp);
  if (renderer == "cpu") {
    Progress progress("cpu", total, progressOn);
    *where = "the CPU reference";
    return render_cpu(compiled, a.threads, progress);
  }
  const KernelVariant& variant = kernel_variant(renderer);  // checked before any Vulkan work
  bool validation = a.validation || VulkanContext::validation_requested_by_environment();
  VulkanContext ctx(a.device, validation);
  ImageStats image;
  {
    WavefrontRenderer gpu(ctx, compiled, variant.settings);
    Progress progress(ctx.info().name, total, progressOn);
    image = gpu.render(progress);
    if (times) *times = gpu.stage_times();
  }
  if (ctx.validation_messages() > 0) {
    throw RenderError(std::to_string(ctx.validation_messages()) + " Vulkan validation message(s) reported; no image written");
  }
  *where = ctx.info().name + (variant.name == "gpu" ? "" : ", " + variant.name);
  return image;
}

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

// Checks where an output file goes before any time is spent on the work
// whose result it holds.
void require_output_directory(const std::string& path) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::is_directory(dir, ec)) throw InputError(path + ": the output directory does not exist");
  if (::access(dir.empty() ? "." : dir.c_str(), W_OK) != 0) throw InputError(path + ": the output directory is not writable");
}

int run_render(const RenderArgs& a) {
  std::string out = a.output.empty() ? default_output(a.scene) : a.output;
  if (std::filesystem::path(out).extension() != ".png") throw InputError(out + ": the output image must be a .png file");
  std::string exr = a.exr.empty() ? std::filesystem::path(out).replace_extension(".exr").string() : a.exr;
  if (std::filesystem::path(exr).extension() != ".exr") throw InputError(exr + ": the linear image must be an .exr file");
  if (!a.cpu) kernel_variant(a.variant);  // an unknown variant fails before any work
  for (const std::string& path : {out, exr}) require_output_directory(path);

  CompiledScene compiled = compile_scene(load_scene_with_overrides(a), variant_options(options_from(a, a.seed), a.cpu ? "cpu" : a.variant));
  auto start = std::chrono::steady_clock::now();
  std::string where;
  StageTimes times;
  ImageStats image = render_on(a.cpu ? "cpu" : a.variant, compiled, a, &where, &times);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // With adaptive sampling, CS184's sample-rate image goes beside the render.
  std::string rate = compiled.adaptive.enabled() ? rate_image_path(out) : "";
  write_exr(exr, image);
  try {
    write_png(out, image);
    if (!rate.empty()) write_sample_rate_png(rate, image, compiled.spp);
  } catch (...) {
    std::remove(exr.c_str());  // all images or none
    std::remove(out.c_str());
    throw;
  }
  if (image.nonFinite > 0) {
    std::fprintf(stderr, "wavepath: warning: %llu non-finite samples were dropped\n", (unsigned long long)image.nonFinite);
  }
  if (!a.quiet) {
    double total = std::accumulate(image.count.begin(), image.count.end(), 0.0);  // samples taken
    std::printf("wrote %s and %s: %dx%d, %d spp, %d max bounces, %.2f s on %s (%.2f Msamples/s)\n", out.c_str(), exr.c_str(),
                compiled.width, compiled.height, compiled.spp, int(compiled.params.image.z), seconds, where.c_str(),
                double(total) / seconds * 1e-6);
    if (!rate.empty()) {
      std::printf("adaptive sampling: %.1f samples per pixel on average (at most %d); sample rates in %s\n",
                  total / double(image.pixels()), compiled.spp, rate.c_str());
    }
  }
  if (a.stageTimes && !a.cpu) {
    double gpu = times.total();
    std::printf("%-11s %10s %7s %11s\n", "stage", "GPU s", "share", "dispatches");
    for (int s = 0; s < StageTimes::kStages; ++s) {
      std::printf("%-11s %10.3f %6.1f%% %11llu\n", StageTimes::kNames[s], times.seconds[s], gpu > 0 ? 100.0 * times.seconds[s] / gpu : 0.0,
                  (unsigned long long)times.dispatches[s]);
    }
    std::printf("%-11s %10.3f\n", "total", gpu);
    std::printf("rays: %llu closest-hit (%.2f Mrays/s in extend), %llu shadow (%.2f Mrays/s in connect)\n",
                (unsigned long long)times.closestHitRays, times.closest_hit_rays_per_second() * 1e-6,
                (unsigned long long)times.shadowRays, times.shadow_rays_per_second() * 1e-6);
  }
  return 0;
}

struct CompareArgs {
  RenderArgs render;  // scene, spp, bounces, seed, device, threads, quiet, validation
  std::vector<std::string> images;
  std::string a = "gpu";
  std::string b = "cpu";
  std::string report;
  float plantBias = 1.0f;
  std::vector<uint32_t> plantRegion;
};

// Renders the scene twice with independent seeds (or reads two EXR renders) and
// decides whether both estimate the same image. Exit 0: agree, 1: differ.
int run_compare(const CompareArgs& c) {
  ImageStats a, b;
  ReportLabels labels;
  if (!c.images.empty()) {
    a = read_exr(c.images[0]);
    b = read_exr(c.images[1]);
    labels = ReportLabels{c.images[0] + " vs " + c.images[1], c.images[0], c.images[1]};
  } else {
    for (const std::string& r : {c.a, c.b})
      if (r != "cpu") kernel_variant(r);  // fails early, naming the known variants
    Scene scene = load_scene_with_overrides(c.render);
    RenderOptions oa = options_from(c.render, c.render.seed), ob = options_from(c.render, c.render.seed + 1);
    std::string whereA, whereB;
    a = render_on(c.a, compile_scene(scene, variant_options(oa, c.a)), c.render, &whereA);
    if (c.plantBias != 1.0f) {
      const std::vector<uint32_t>& r = c.plantRegion;
      plant_bias(a, c.plantBias, r.empty() ? glm::uvec4(0u, 0u, ~0u, ~0u) : glm::uvec4(r[0], r[1], r[2], r[3]));
    }
    b = render_on(c.b, compile_scene(scene, variant_options(ob, c.b)), c.render, &whereB);
    auto label = [&](const std::string& r, const std::string& where, uint32_t seed, bool planted) {
      std::string l = r + " (" + where + "), seed " + std::to_string(seed);
      if (planted) {
        char factor[32];
        std::snprintf(factor, sizeof(factor), "%g", double(c.plantBias));
        l += std::string(", planted bias x") + factor;
      }
      return l;
    };
    labels = ReportLabels{c.render.scene, label(c.a, whereA, c.render.seed, c.plantBias != 1.0f),
                          label(c.b, whereB, c.render.seed + 1, false)};
  }
  CompareResult result = compare_images(a, b);
  std::printf("%s\n", result.summary().c_str());
  if (!c.report.empty()) {
    write_html_report(c.report, a, b, result, labels);
    std::printf("report: %s/index.html\n", c.report.c_str());
  }
  return result.passed() ? 0 : 1;
}

// Convergence of the camera samplers: RMSE against a high-sample reference
// at 1, 2, 4, ... samples per pixel, for the independent and the CMJ sampler.
// Renders with the CPU reference (the kernels' own code, and faster than
// lavapipe); one CSV row per sampler and sample count.
struct ConvergenceArgs {
  RenderArgs render;
  int maxSpp = 256;
  int referenceSpp = 4096;
  std::string csv;
};

int run_convergence(const ConvergenceArgs& c) {
  if (!c.csv.empty()) require_output_directory(c.csv);
  Scene scene = load_scene_with_overrides(c.render);
  Progress quiet("", 0, false);
  RenderOptions ro = options_from(c.render, 1000);
  ro.spp = c.referenceSpp;
  ro.sampler = SamplerKind::Independent;
  ImageStats reference = render_cpu(compile_scene(scene, reference_options(ro)), c.render.threads, quiet);
  std::string rows = "sampler,spp,rmse\n";
  std::printf("%-12s %6s %12s\n", "sampler", "spp", "RMSE");
  for (SamplerKind sampler : {SamplerKind::Independent, SamplerKind::Cmj}) {
    const char* name = sampler == SamplerKind::Cmj ? "cmj" : "independent";
    for (int spp = 1; spp <= c.maxSpp; spp *= 2) {
      RenderOptions o = options_from(c.render, 1);
      o.spp = spp;
      o.sampler = sampler;
      ImageStats img = render_cpu(compile_scene(scene, reference_options(o)), c.render.threads, quiet);
      double se = 0.0;
      for (size_t p = 0; p < img.pixels(); ++p) {
        glm::dvec3 d = img.mean(p) - reference.mean(p);
        se += glm::dot(d, d);
      }
      double rmse = std::sqrt(se / (3.0 * double(img.pixels())));
      std::printf("%-12s %6d %12.6g\n", name, spp, rmse);
      rows += std::string(name) + "," + std::to_string(spp) + "," + std::to_string(rmse) + "\n";
    }
  }
  if (!c.csv.empty()) {
    FILE* f = std::fopen(c.csv.c_str(), "w");
    if (!f || std::fputs(rows.c_str(), f) < 0 || std::fclose(f) != 0) throw InputError(c.csv + ": cannot write");
  }
  return 0;
}

// What the renderer would build for a scene: sizes, BVH quality and memory.
int run_info(const std::string& scenePath, int maxLeafSize, const std::string& variant, const std::string* kernelsDevice) {
  RenderOptions options = variant_options(RenderOptions{}, variant);  // an unknown variant fails before any work
  if (kernelsDevice && variant == "cpu") throw InputError("--kernels: the cpu reference has no kernels");
  auto t0 = std::chrono::steady_clock::now();
  Scene scene = load_scene(scenePath);
  double loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (maxLeafSize > 0) scene.accelerator.maxLeafSize = maxLeafSize;
  CompiledScene cs = compile_scene(scene, options);
  size_t gpuBytes = cs.gpu_bytes();
  size_t prims = scene.triangles.size() + scene.spheres.size();
  std::printf("scene        %s\n", scenePath.c_str());
  std::printf("primitives   %zu triangles, %zu spheres, %zu materials, %u emitters\n", scene.triangles.size(),
              scene.spheres.size(), scene.materials.size(), cs.params.counts.x);
  std::printf("image        %dx%d, %d spp, %u max bounces\n", cs.width, cs.height, cs.spp, cs.params.image.z);
  std::printf("load         %.3f s (parsing and OBJ)\n", loadSeconds);
  bool wide = cs.bvhLayout == BvhLayout::Wide;
  std::printf("BVH          %s, %s, %zu nodes, depth %d, SAH cost %.2f, built in %.3f s (%.3g Mprims/s)\n",
              wide ? "8-wide compressed" : "binary", split_method_name(cs.bvhSplit), wide ? cs.wideNodes.size() : cs.nodes.size(),
              cs.bvhDepth, cs.bvh_sah_cost(), cs.bvhBuildSeconds, cs.bvhBuildSeconds > 0 ? prims / cs.bvhBuildSeconds * 1e-6 : 0.0);
  std::printf("GPU scene    %.2f MiB (%.1f bytes per primitive, BVH included)\n", gpuBytes / 1048576.0,
              prims ? double(gpuBytes) / double(prims) : 0.0);
  // On a CPU device every branch a kernel has costs each path, taken or not:
  // what the scene uses is what its kernels pay for.
  std::printf("kinds        %s (compiled into the kernels)\n", kinds_description(cs.params.kinds).c_str());
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

int run_devices(bool validation) {
  std::printf("kernel variants:");
  for (const KernelVariant& v : kernel_variants()) std::printf(" %s", v.name.c_str());
  std::printf("\n");
  auto devices = VulkanContext::list_devices(validation);
  if (devices.empty()) throw RenderError("no Vulkan device found; install a Vulkan driver, e.g. Debian's mesa-vulkan-drivers");
  for (const GpuDeviceInfo& d : devices) {
    std::printf("%u: %s\n   type %s, driver %s, Vulkan %s%s\n", d.index, d.name.c_str(), d.type.c_str(), d.driver.c_str(),
                d.apiVersion.c_str(), d.suitable ? "" : " (unsuitable: needs Vulkan 1.1, a compute queue and subgroup ballots in compute shaders)");
    std::printf("   max texel buffer %llu M texels (scene data), max storage buffer %llu MiB (work buffers), max workgroups %u,\n"
                "   max invocations %u, subgroup %u, device-local memory %llu MiB\n",
                (unsigned long long)(d.maxTexelBufferElements >> 20), (unsigned long long)(d.maxStorageBufferRange >> 20),
                d.maxComputeWorkGroupCount, d.maxComputeWorkGroupInvocations, d.subgroupSize,
                (unsigned long long)(d.deviceLocalMemory >> 20));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"wavepath: a wavefront path tracer on Vulkan compute, with a CPU reference renderer"};
  app.require_subcommand(1);
  RenderArgs r;
  CLI::App* render = app.add_subcommand("render", "render a darts JSON scene to PNG (and a linear EXR with statistics)");
  render->add_option("scene", r.scene, "scene file (darts JSON)")->required();
  // Short options in parentheses are the CS184 pathtracer's, for its students.
  render->add_option("-o,-f,--output", r.output, "PNG to write (default: SCENE-NAME.png) (CS184: -f)");
  render->add_option("--exr", r.exr, "linear EXR with mean, variance and sample count (default: next to the PNG)");
  render->add_option("-s,--spp", r.spp, "samples per pixel (default: the scene's sampler) (CS184: -s)")->check(CLI::Range(1, MAX_SAMPLES_PER_PIXEL));
  render->add_option("-m,--max-bounces", r.maxBounces, "maximum scattering events per path (default: the scene's) (CS184: -m)")
      ->check(CLI::Range(0, 1024));
  render->add_option("--integrator", r.integrator,
                     "integrator, overriding the scene's: normals, ao, \"path tracer mats|nee|mis|mixture|hemisphere\"");
  bool hemisphere = false;
  render->add_flag("-H,--hemisphere", hemisphere,
                   "uniform hemisphere sampling instead of light sampling: --integrator \"path tracer hemisphere\" (CS184: -H)");
  render->add_option("--sampler", r.sampler, "sampler, overriding the scene's: independent or cmj");
  render->add_option("-b,--aperture", r.aperture, "thin-lens radius, overriding the scene's (CS184: -b)")->check(CLI::Range(0.0f, 1e6f));
  render->add_option("-d,--focus-distance", r.focusDistance, "thin-lens focus distance, overriding the scene's (CS184: -d)")
      ->check(CLI::PositiveNumber);
  render->add_option("-l,--light-samples", r.lightSamples,
                     "next-event-estimation samples per path vertex, 1 to " + std::to_string(MAX_LIGHT_SAMPLES) + " (CS184: -l)")
      ->check(CLI::Range(1, int(MAX_LIGHT_SAMPLES)));
  render->add_option("-a,--adaptive", r.adaptive,
                     "adaptive sampling: BATCH TOLERANCE, e.g. 32 0.05; --spp is then the maximum. Writes OUT_rate.png (CS184: -a)")
      ->expected(2);
  render->add_option("-e,--env", r.environment, "equirectangular environment map (HDR, EXR, PNG...) replacing the background (CS184: -e)");
  render->add_option("--seed", r.seed, "random seed; renders with equal seeds are identical");
  render->add_option("--device", r.device, "Vulkan device: index or part of the name (see `wavepath devices`)");
  render->add_flag("--cpu", r.cpu, "render with the CPU reference renderer instead of Vulkan");
  render->add_option("-t,--threads", r.threads, "CPU threads for --cpu (default: all cores) (CS184: -t)")->check(CLI::Range(0, 1024));
  render->add_flag("-q,--quiet", r.quiet, "no progress line and no summary");
  render->add_flag("--validation", r.validation, "enable Vulkan validation; any message fails the render (also WAVEPATH_VALIDATION=1)");
  render->add_option("--variant", r.variant, "kernel variant (wavepath devices lists them); default gpu");
  render->add_flag("--stage-times", r.stageTimes, "print the GPU time of each kernel stage (Vulkan timestamps)");
  render->add_option("-r,--resolution", r.resolution, "image size W H, overriding the scene's (CS184: -r)")->expected(2)->check(CLI::Range(1, MAX_IMAGE_SIZE));

  CompareArgs cmp;
  CLI::App* compare = app.add_subcommand(
      "compare", "render a scene twice with independent seeds (default: GPU against the CPU reference), or read two EXR "
                 "renders, and decide statistically whether they estimate the same image. Exit 0: agree, 1: differ");
  compare->add_option("scene", cmp.render.scene, "scene file (darts JSON)");
  compare->add_option("--images", cmp.images, "compare two stored renders (EXR written by wavepath render) instead")->expected(2);
  compare->add_option("--a", cmp.a, "renderer of image A: cpu or a kernel variant such as gpu, gpu-wg128 (default gpu)");
  compare->add_option("--b", cmp.b, "renderer of image B: cpu or a kernel variant (default cpu)");
  compare->add_option("--spp", cmp.render.spp, "samples per pixel of each render")->check(CLI::Range(1, MAX_SAMPLES_PER_PIXEL));
  compare->add_option("--max-bounces", cmp.render.maxBounces, "maximum scattering events per path")->check(CLI::Range(0, 1024));
  compare->add_option("--integrator", cmp.render.integrator, "integrator, overriding the scene's (darts name)");
  compare->add_option("--seed", cmp.render.seed, "seed of A; B uses seed + 1 (default 1)")->default_val(1);
  compare->add_option("--resolution", cmp.render.resolution, "image size W H, overriding the scene's")->expected(2)->check(CLI::Range(1, MAX_IMAGE_SIZE));
  compare->add_option("--report", cmp.report, "write an HTML report to this directory");
  compare->add_option("--device", cmp.render.device, "Vulkan device: index or part of the name");
  compare->add_option("--threads", cmp.render.threads, "CPU threads for the CPU reference")->check(CLI::Range(0, 1024));
  compare->add_option("--plant-bias", cmp.plantBias, "debug: multiply A's radiance by this factor, to see what the test detects")
      ->check(CLI::Range(0.0, 100.0));
  compare->add_option("--plant-region", cmp.plantRegion, "debug: only inside pixels X0 Y0 X1 Y1 (exclusive ends)")->expected(4);
  compare->add_flag("-q,--quiet", cmp.render.quiet, "no progress line");
  compare->add_flag("--validation", cmp.render.validation, "enable Vulkan validation; any message is a failure");
  BenchOptions bench;
  CLI::App* benchCmd = app.add_subcommand(
      "bench", "time kernel variants side by side on scenes; a variant is timed only after it agrees with the CPU reference");
  benchCmd->add_option("--scenes", bench.scenes, "scene files, separated by commas (default scenes/cornell-box.json)")->delimiter(',');
  benchCmd->add_option("--variants", bench.variants, "kernel variants (default: all; wavepath devices lists them)")->delimiter(',');
  benchCmd->add_option("--spp", bench.spp, "samples per pixel of each timed render (default 4)")->check(CLI::Range(1, 1 << 20));
  benchCmd->add_option("--repeats", bench.repeats, "timed renders per variant, after one warm-up (default 3)")->check(CLI::Range(1, 1000));
  benchCmd->add_option("--resolution", bench.resolution, "image size W H, overriding the scenes'")->expected(2)->check(CLI::Range(1, MAX_IMAGE_SIZE));
  benchCmd->add_option("--check-spp", bench.checkSpp, "samples per pixel of the correctness check (default 64)")->check(CLI::Range(1, 1 << 20));
  benchCmd->add_option("--plant-bias", bench.plantedBias, "debug: plant this bias in the variants' check renders")->check(CLI::Range(0.0, 100.0));
  benchCmd->add_option("--device", bench.device, "Vulkan device: index or part of the name");
  benchCmd->add_option("--out", bench.jsonPath, "write the results as JSON");
  benchCmd->add_option("--csv", bench.csvPath, "write the results as CSV");
  benchCmd->add_flag("--validation", bench.validation, "enable Vulkan validation; any message is a failure");
  CLI::Option* raycastFlag = benchCmd->add_flag("--raycast", bench.raycast,
                     "trace fixed ray sets (camera rays, then one bounce and one shadow ray from each hit) instead of rendering; "
                     "compared with Embree when built in");
  CLI::Option* buildFlag = benchCmd->add_flag(
      "--build", bench.build, "time BVH builds (the renderer's 8-wide tree, and the binary layout) instead of rendering; compared with Embree when built in");
  buildFlag->excludes(raycastFlag);

  ConvergenceArgs conv;
  CLI::App* convergence = app.add_subcommand(
      "convergence", "RMSE against a high-sample reference at 1, 2, 4, ... spp, independent vs cmj sampler (CPU reference)");
  convergence->add_option("scene", conv.render.scene, "scene file (darts JSON)")->required();
  convergence->add_option("--max-spp", conv.maxSpp, "largest sample count (default 256)")->check(CLI::Range(1, 1 << 16));
  convergence->add_option("--reference-spp", conv.referenceSpp, "samples of the reference (default 4096)")->check(CLI::Range(1, 1 << 20));
  convergence->add_option("--integrator", conv.render.integrator, "integrator, overriding the scene's (darts name)");
  convergence->add_option("--max-bounces", conv.render.maxBounces, "maximum scattering events per path")->check(CLI::Range(0, 1024));
  convergence->add_option("-r,--resolution", conv.render.resolution, "image size W H, overriding the scene's")->expected(2)->check(CLI::Range(1, MAX_IMAGE_SIZE));
  convergence->add_option("--csv", conv.csv, "write sampler,spp,rmse rows (scripts/plot_convergence.py draws them)");
  convergence->add_option("-t,--threads", conv.render.threads, "CPU threads (default: all cores)")->check(CLI::Range(0, 1024));

  std::string infoScene;
  int infoLeaf = 0;
  CLI::App* info = app.add_subcommand("info", "load a scene, build its BVH and report sizes, build time and memory");
  info->add_option("scene", infoScene, "scene file (darts JSON)")->required();
  info->add_option("--max-leaf-size", infoLeaf, "override the scene's BVH leaf size")->check(CLI::Range(1, BVH_MAX_LEAF_SIZE));
  std::string infoVariant = "gpu";
  info->add_option("--variant", infoVariant, "the kernel variant (or cpu) whose BVH layout to build; default gpu");
  std::string infoDevice;
  CLI::Option* infoKernels = info->add_flag("--kernels", "also compile the variant's kernels and show the driver's statistics of each (registers, spills, ...)");
  info->add_option("--device", infoDevice, "Vulkan device for --kernels: index or part of the name")->needs(infoKernels);
  bool devValidation = false;
  CLI::App* devices = app.add_subcommand("devices", "list Vulkan devices and the limits that matter to wavepath");
  devices->add_flag("--validation", devValidation, "enable Vulkan validation");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --version and the like
    std::fprintf(stderr, "wavepath: error: %s (see wavepath --help)\n", e.what());
    return 2;
  }
  try {
    if (hemisphere) {
      if (!r.integrator.empty() && r.integrator != "path tracer hemisphere")
        throw InputError("-H (uniform hemisphere sampling) and --integrator \"" + r.integrator + "\" contradict each other");
      r.integrator = "path tracer hemisphere";
    }
    if (*render) return run_render(r);
    if (*compare) {
      if (cmp.images.empty() == cmp.render.scene.empty())
        throw InputError("compare needs either a scene file or --images A.exr B.exr (not both)");
      return run_compare(cmp);
    }
    if (*devices) return run_devices(devValidation);
    if (*benchCmd) {
      if (bench.scenes.empty()) bench.scenes.push_back("scenes/cornell-box.json");
      if (bench.variants.empty())
        for (const KernelVariant& v : kernel_variants()) bench.variants.push_back(v.name);
      for (const std::string* path : {&bench.jsonPath, &bench.csvPath})
        if (!path->empty()) require_output_directory(*path);
      if (bench.build) return run_build_bench(bench);
      return bench.raycast ? run_raycast_bench(bench) : run_bench(bench);
    }
    if (*info) return run_info(infoScene, infoLeaf, infoVariant, *infoKernels ? &infoDevice : nullptr);
    if (*convergence) return run_convergence(conv);
  } catch (const InputError& e) {
    std::fprintf(stderr, "wavepath: error: %s\n", e.what());
    return 2;
  } catch (const RenderError& e) {
    std::fprintf(stderr, "wavepath: error: %s\n", e.what());
    return 3;
  } catch (const vk::SystemError& e) {
    std::fprintf(stderr, "wavepath: error: Vulkan: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "wavepath: error: %s\n", e.what());
    return 3;
  }
  return 0;
}
