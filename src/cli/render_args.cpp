#include "cli/render_args.h"

#include <cstdio>

#include "util/error.h"

namespace wp::cli {

void add_scene_options(CLI::App& app, RenderArgs& r, bool& hemisphere) {
  app.add_option("-a,--adaptive", r.adaptive,
                     "adaptive sampling: BATCH TOLERANCE, e.g. 32 0.05; --spp is then the maximum. Writes OUT_rate.png (CS184: -a)")
      ->expected(2);
  app.add_option("-s,--spp", r.spp, "samples per pixel (default: the scene's sampler) (CS184: -s)")
      ->check(CLI::Range(1, MAX_SAMPLES_PER_PIXEL));
  app.add_option("-m,--max-bounces", r.maxBounces, "maximum scattering events per path (default: the scene's) (CS184: -m)")
      ->check(CLI::Range(0, 1024));
  app.add_option("--integrator", r.integrator,
                     "integrator, overriding the scene's: normals, ao, \"path tracer mats|nee|mis|mixture|hemisphere\"");
  app.add_flag("-H,--hemisphere", hemisphere,
                   "uniform hemisphere sampling instead of light sampling: --integrator \"path tracer hemisphere\" (CS184: -H)");
  app.add_option("--sampler", r.sampler, "sampler, overriding the scene's: independent or cmj");
  app.add_flag("--spectral", r.spectral,
               "render spectrally: each path carries four wavelengths, RGB inputs are uplifted to smooth spectra, the film "
               "converts to sRGB (default: the scene's integrator \"spectral\" key, else RGB)");
  app.add_flag("--rgb", r.rgb, "render in RGB, overriding a scene's \"spectral\": true");
  app.add_option("-b,--aperture", r.aperture, "thin-lens radius, overriding the scene's (CS184: -b)")->check(CLI::Range(0.0f, 1e6f));
  app.add_option("-d,--focus-distance", r.focusDistance, "thin-lens focus distance, overriding the scene's (CS184: -d)")
      ->check(CLI::PositiveNumber);
  app.add_option("-l,--light-samples", r.lightSamples,
                     "next-event-estimation samples per path vertex, 1 to " + std::to_string(MAX_LIGHT_SAMPLES) + " (CS184: -l)")
      ->check(CLI::Range(1, int(MAX_LIGHT_SAMPLES)));
  app.add_option("-e,--env", r.environment, "equirectangular environment map (HDR, EXR, PNG...) replacing the background (CS184: -e); none: no environment, a black "
                     "background; sky: a uniform white sky of radiance 1 (what a glTF model without a light worth the name gets)");
  app.add_option("--camera", r.camera, "the glTF camera to render through, by name or index (default: the first; without one, a camera framing the scene)");
  app.add_flag("--flatten-instances", r.flattenInstances,
               "place every instance's triangles in world space, as one flat BVH, instead of walking each instanced mesh's own tree");
  app.add_option("-c,--camera-settings", r.cameraSettings, "a CS184 camera settings file, as its viewer writes with D (CS184: -c)");
  app.add_flag("--consistent-lights", r.consistentLights,
                   "CS184 scenes: read the lights physically (area lights are visible quads, emissive meshes light the "
                   "scene) instead of as the course's estimator does");
  app.add_option("--cs184", r.cs184Skeleton,
                     "CS184 scenes: the skeleton whose scene conventions to follow, 3-1 (default: emissive meshes glow, area "
                     "lights are not geometry) or 3-2 (emissive meshes are black, area lights are visible quads, as the "
                     "course's 3-2 renderer draws them)")
      ->check(CLI::IsMember({"3-1", "3-2"}));
  app.add_option("--seed", r.seed, "random seed; renders with equal seeds take the same samples");
  app.add_option("--device", r.device, "Vulkan device: index or part of the name (see `wavepath devices`)");
  app.add_flag("--validation", r.validation, "enable Vulkan validation; any message fails the render (also WAVEPATH_VALIDATION=1)");
  app.add_option("--variant", r.variant, "kernel variant (wavepath devices lists them); default: the device's, as devices shows");
  app.add_option("--photon-pass", r.photonPass,
                 "photon mapper on a Vulkan device: who traces the photons, its kernels or the host's cores (default auto: "
                 "kernels on GPUs, the host beside CPU devices such as lavapipe)")
      ->check(CLI::IsMember({"auto", "kernels", "host"}));
  app.add_option("--tile-pixels", r.tilePixels,
                 "a Vulkan device renders the image in tiles of at most this many consecutive pixels (default: as many as "
                 "its buffers hold; larger images are tiled anyway)")
      ->check(CLI::Range(1u, uint32_t(MAX_IMAGE_SIZE) * uint32_t(MAX_IMAGE_SIZE)));
  app.add_option("-r,--resolution", r.resolution, "image size W H, overriding the scene's (CS184: -r)")
      ->expected(2)
      ->check(CLI::Range(1, MAX_IMAGE_SIZE));
}

void apply_hemisphere_flag(RenderArgs& r, bool hemisphere) {
  if (!hemisphere) return;
  if (!r.integrator.empty() && r.integrator != "path tracer hemisphere")
    throw InputError("-H (uniform hemisphere sampling) and --integrator \"" + r.integrator + "\" contradict each other");
  r.integrator = "path tracer hemisphere";
}

namespace {

// `word` as one word of a shell's command line.
std::string quoted(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+.,/:=@%") == std::string::npos)
    return word;
  std::string q = "'";
  for (char c : word) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

std::string render_command_line(const RenderArgs& a) {
  auto number = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", v);
    return std::string(text);
  };
  std::string line = "wavepath render " + quoted(a.scene);
  auto add = [&](const char* option, const std::string& value) {
    if (!value.empty()) line += std::string(" ") + option + " " + quoted(value);
  };
  auto ints = [](const std::vector<int>& values) {
    std::string out;
    for (int v : values) out += " " + std::to_string(v);
    return out;
  };
  add("-o", a.output);
  add("-c", a.cameraSettings);
  add("--camera", a.camera);
  if (a.spp > 0) add("--spp", std::to_string(a.spp));
  if (a.maxBounces >= 0) add("-m", std::to_string(a.maxBounces));
  if (!a.resolution.empty()) line += " -r" + ints(a.resolution);
  if (!a.cell.empty()) line += " -p" + ints(a.cell);
  add("--integrator", a.integrator);
  add("--sampler", a.sampler);
  if (a.spectral) line += " --spectral";
  if (a.rgb) line += " --rgb";
  if (a.lightSamples > 1) add("-l", std::to_string(a.lightSamples));
  if (a.aperture >= 0.0f) add("-b", number(a.aperture));
  if (a.focusDistance > 0.0f) add("-d", number(a.focusDistance));
  add("-e", a.environment);
  if (a.consistentLights) line += " --consistent-lights";
  if (a.flattenInstances) line += " --flatten-instances";
  add("--cs184", a.cs184Skeleton);
  if (!a.adaptive.empty()) line += " -a " + number(a.adaptive[0]) + " " + number(a.adaptive.size() > 1 ? a.adaptive[1] : 0.0);
  std::string aovs;
  for (const std::string& l : a.aovs) aovs += (aovs.empty() ? "" : ",") + l;
  add("--aov", aovs);
  if (a.seed != 0) add("--seed", std::to_string(a.seed));
  if (!a.variant.empty()) add("--variant", a.variant);
  if (a.photonPass != "auto") add("--photon-pass", a.photonPass);
  if (a.tilePixels > 0) add("--tile-pixels", std::to_string(a.tilePixels));
  add("--resume", a.resume);
  return line;
}

std::string resume_command_line(const RenderArgs& a, const std::string& partial) {
  RenderArgs image = a;
  image.resume.clear();
  std::string line = render_command_line(image);
  auto add = [&](const char* option, const std::string& value) {
    if (!value.empty()) line += std::string(" ") + option + " " + quoted(value);
  };
  add("--format", a.format);
  add("--exr", a.exr);
  add("--samples", a.samples);
  add("--device", a.device);
  std::string devices;
  for (const std::string& d : a.devices) devices += (devices.empty() ? "" : ",") + d;
  add("--devices", devices);
  if (a.threads > 0) add("--threads", std::to_string(a.threads));
  add("--checkpoint", a.checkpoint);
  if (!a.checkpoint.empty() && a.checkpointEvery != "60s") add("--checkpoint-every", a.checkpointEvery);
  add("--resume", partial);
  return line;
}

}  // namespace wp::cli
