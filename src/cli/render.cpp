// `wavepath render`: a scene to PNG and EXR, on a kernel variant or the CPU
// reference, with the CS184 pathtracer's short options.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numeric>

#include "cli/commands.h"
#include "cli/render_args.h"
#include "image/image.h"
#include "util/error.h"

namespace wp::cli {

namespace {

// CS184 writes the sample-rate image of out.png as out_rate.png.
std::string rate_image_path(const std::string& out) {
  std::filesystem::path p(out);
  return (p.parent_path() / (p.stem().string() + "_rate.png")).string();
}

std::string default_output(const std::string& scenePath) {
  return std::filesystem::path(scenePath).stem().string() + ".png";
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

}  // namespace

Command add_render(CLI::App& app) {
  auto r = std::make_shared<RenderArgs>();
  auto hemisphere = std::make_shared<bool>(false);
  CLI::App* render = app.add_subcommand("render", "render a scene to PNG (and a linear EXR with statistics)");
  render->add_option("scene", r->scene, "scene file (darts JSON)")->required();
  // Short options in parentheses are the CS184 pathtracer's, for its students.
  render->add_option("-o,-f,--output", r->output, "PNG to write (default: SCENE-NAME.png) (CS184: -f)");
  render->add_option("--exr", r->exr, "linear EXR with mean, variance and sample count (default: next to the PNG)");
  render->add_option("-s,--spp", r->spp, "samples per pixel (default: the scene's sampler) (CS184: -s)")
      ->check(CLI::Range(1, MAX_SAMPLES_PER_PIXEL));
  render->add_option("-m,--max-bounces", r->maxBounces, "maximum scattering events per path (default: the scene's) (CS184: -m)")
      ->check(CLI::Range(0, 1024));
  render->add_option("--integrator", r->integrator,
                     "integrator, overriding the scene's: normals, ao, \"path tracer mats|nee|mis|mixture|hemisphere\"");
  render->add_flag("-H,--hemisphere", *hemisphere,
                   "uniform hemisphere sampling instead of light sampling: --integrator \"path tracer hemisphere\" (CS184: -H)");
  render->add_option("--sampler", r->sampler, "sampler, overriding the scene's: independent or cmj");
  render->add_option("-b,--aperture", r->aperture, "thin-lens radius, overriding the scene's (CS184: -b)")->check(CLI::Range(0.0f, 1e6f));
  render->add_option("-d,--focus-distance", r->focusDistance, "thin-lens focus distance, overriding the scene's (CS184: -d)")
      ->check(CLI::PositiveNumber);
  render->add_option("-l,--light-samples", r->lightSamples,
                     "next-event-estimation samples per path vertex, 1 to " + std::to_string(MAX_LIGHT_SAMPLES) + " (CS184: -l)")
      ->check(CLI::Range(1, int(MAX_LIGHT_SAMPLES)));
  render->add_option("-a,--adaptive", r->adaptive,
                     "adaptive sampling: BATCH TOLERANCE, e.g. 32 0.05; --spp is then the maximum. Writes OUT_rate.png (CS184: -a)")
      ->expected(2);
  render->add_option("-e,--env", r->environment, "equirectangular environment map (HDR, EXR, PNG...) replacing the background (CS184: -e)");
  render->add_option("--seed", r->seed, "random seed; renders with equal seeds are identical");
  render->add_option("--device", r->device, "Vulkan device: index or part of the name (see `wavepath devices`)");
  render->add_flag("--cpu", r->cpu, "render with the CPU reference renderer instead of Vulkan");
  render->add_option("-t,--threads", r->threads, "CPU threads for --cpu (default: all cores) (CS184: -t)")->check(CLI::Range(0, 1024));
  render->add_flag("-q,--quiet", r->quiet, "no progress line and no summary");
  render->add_flag("--validation", r->validation, "enable Vulkan validation; any message fails the render (also WAVEPATH_VALIDATION=1)");
  render->add_option("--variant", r->variant, "kernel variant (wavepath devices lists them); default gpu");
  render->add_flag("--stage-times", r->stageTimes, "print the GPU time of each kernel stage (Vulkan timestamps)");
  render->add_option("-r,--resolution", r->resolution, "image size W H, overriding the scene's (CS184: -r)")
      ->expected(2)
      ->check(CLI::Range(1, MAX_IMAGE_SIZE));
  return {render, [r, hemisphere] {
            if (*hemisphere) {
              if (!r->integrator.empty() && r->integrator != "path tracer hemisphere")
                throw InputError("-H (uniform hemisphere sampling) and --integrator \"" + r->integrator + "\" contradict each other");
              r->integrator = "path tracer hemisphere";
            }
            return run_render(*r);
          }};
}

}  // namespace wp::cli
