#include "job/render_args.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <unistd.h>
#include <cstdlib>
#include <fstream>
#include <filesystem>

#include "cpu/reference.h"
#include "gpu/vulkan_context.h"
#include "render/partial.h"
#include "scene/importers.h"
#include "scene/load_scene.h"
#include "util/error.h"
#include "util/progress.h"

namespace wp {

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
  if (a.spectral && a.rgb) throw InputError("--spectral and --rgb contradict each other");
  if (a.spectral || a.rgb) options.spectral = a.spectral;
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

Scene load_scene_content(const RenderArgs& a) {
  Scene scene = load_scene(a.scene);
  if (a.consistentLights) {
    if (!scene.cs184Estimator) throw InputError("--consistent-lights: " + a.scene + " is not a CS184 scene (.dae), whose lights it reads physically");
    if (a.cs184Skeleton == "3-2") throw InputError("--consistent-lights reads the lights physically; --cs184 3-2 reads them as that skeleton does: choose one");
    use_consistent_lights(scene);
  }
  if (a.cs184Skeleton == "3-2") {
    if (!scene.cs184Estimator) throw InputError("--cs184 3-2: " + a.scene + " is not a CS184 scene (.dae)");
    use_cs184_3_2_skeleton(scene);
  }
  if (a.flattenInstances) flatten_instances(scene);
  return scene;
}

void apply_camera_overrides(Scene& scene, const RenderArgs& a) {
  if (!a.camera.empty()) choose_camera(scene, a.camera);
  if (!a.resolution.empty()) set_resolution(scene.camera, a.resolution[0], a.resolution[1]);
  // As the course does: the settings file after the resolution, its fields winning.
  if (!a.cameraSettings.empty()) apply_cs184_camera_settings(a.cameraSettings, scene.camera);
  if (!a.cell.empty()) set_cell(scene.camera, a.cell[0], a.cell[1], a.cell[2], a.cell[3]);
  if (a.aperture >= 0.0f) scene.camera.apertureRadius = a.aperture;
  if (a.focusDistance > 0.0f) scene.camera.focusDistance = a.focusDistance;
}

Scene load_scene_with_overrides(const RenderArgs& a) {
  Scene scene = load_scene_content(a);
  apply_camera_overrides(scene, a);
  apply_environment(scene, a.environment);
  return scene;
}

double parse_duration(const std::string& text, const std::string& option) {
  char* end = nullptr;
  double v = std::strtod(text.c_str(), &end);
  std::string unit = end ? std::string(end) : "";
  double scale = unit.empty() || unit == "s" ? 1.0 : unit == "m" || unit == "min" ? 60.0 : unit == "h" ? 3600.0 : -1.0;
  if (end == text.c_str() || scale < 0.0 || !(v > 0.0) || !std::isfinite(v))
    throw InputError(option + ": \"" + text + "\" is not a duration (a positive number of seconds, or with s, m or h)");
  return v * scale;
}

void check_image_fits_host(int width, int height, const std::vector<std::string>& aovs) {
  const ImageStats layout(1, 1, image_layers(aovs));
  // Per pixel: sums and sums of squares of every channel and a count, in
  // double (ImageStats); a partial EXR's 92 bytes and more per layer while it is written.
  const uint64_t perPixel = (2 * layout.stride + 1) * sizeof(double) + 92 + 12 * (layout.layers.size() - 1);
  const uint64_t need = uint64_t(width) * uint64_t(height) * perPixel;
  // What this process may use: the machine's memory, or less where its
  // cgroup (a Slurm job's, a container's) or WAVEPATH_HOST_MEMORY_MIB says so.
  uint64_t have = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
  std::string where = "this machine's";
  if (std::ifstream cgroup("/sys/fs/cgroup/memory.max"); cgroup) {
    uint64_t limit = 0;
    if (cgroup >> limit && limit > 0 && limit < have) {
      have = limit;
      where = "its cgroup's";
    }
  }
  if (const char* env = std::getenv("WAVEPATH_HOST_MEMORY_MIB")) {
    const uint64_t mib = std::strtoull(env, nullptr, 10);
    if (mib > 0 && (mib << 20) < have) {
      have = mib << 20;
      where = "WAVEPATH_HOST_MEMORY_MIB's";
    }
  }
  if (need > have) {
    throw InputError("a " + std::to_string(width) + "x" + std::to_string(height) + " image needs about " +
                     std::to_string((need + (1 << 20) - 1) >> 20) + " MiB of memory to render and write, more than " + where + " " +
                     std::to_string(have >> 20) + " MiB");
  }
}

WavefrontSettings renderer_settings(const KernelVariant& variant, const RenderArgs& a) {
  WavefrontSettings s = variant.settings;
  s.photonPass = a.photonPass == "kernels" ? PhotonPass::Kernels : a.photonPass == "host" ? PhotonPass::Host : PhotonPass::Auto;
  s.maxTilePixels = a.tilePixels;
  return s;
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
    std::unique_ptr<WavefrontRenderer> gpu;
    try {
      gpu = std::make_unique<WavefrontRenderer>(ctx, compiled, renderer_settings(variant, a));
    } catch (DeviceLost& lost) {  // before a sample: the image is as it came
      lost.reached = range.begin;
      lost.intact = true;
      throw;
    }
    Progress progress(ctx.info().name, total, progressOn);
    reached = gpu->render(image, range, progress, afterPass);
    if (times) *times = gpu->stage_times();
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

std::vector<SampleRange> join_ranges(std::vector<SampleRange> ranges) {
  std::sort(ranges.begin(), ranges.end(), [](SampleRange x, SampleRange y) { return x.begin < y.begin; });
  std::vector<SampleRange> out;
  for (SampleRange r : ranges) {
    if (r.size() == 0) continue;
    if (!out.empty() && out.back().end == r.begin) out.back().end = r.end;
    else out.push_back(r);
  }
  return out;
}

std::vector<SampleRange> render_on_devices(const std::vector<RenderDevice>& devices, const RenderArgs& a, ImageStats& image,
                                           std::vector<SampleRange> done, const std::vector<SampleRange>& todo,
                                           const std::function<bool()>& shouldStop, const ChunkHook& afterChunk,
                                           std::string* where, std::vector<std::string>* lostDevices) {
  // Chunks: about four per renderer over all the work, so that a fast
  // renderer takes more of them than a slow one.
  uint64_t total = 0;
  for (SampleRange r : todo) total += r.size();
  const uint32_t chunk = uint32_t(std::max<uint64_t>(1, (total + 4 * devices.size() - 1) / (4 * devices.size())));
  std::vector<SampleRange> chunks;
  for (SampleRange r : todo)
    for (uint32_t b = r.begin; b < r.end; b += std::min(chunk, r.end - b)) chunks.push_back({b, std::min(b + chunk, r.end)});

  std::mutex mutex;  // guards image, done, chunks, next, own, pending, names and error
  std::condition_variable changed;  // a chunk was queued or ended, or the render fails
  // Each renderer's first chunk is its own, so that every one renders (on a
  // small render one slow to start might find none left); the others go to
  // whichever is free.
  std::vector<std::optional<SampleRange>> own(devices.size());
  size_t next = 0;
  for (size_t d = 0; d < devices.size() && next < chunks.size(); ++d) own[d] = chunks[next++];
  // Chunks owned or in hand: a renderer lost gives back what it had left of
  // its chunk, so the others wait for these before they end.
  size_t pending = std::min(devices.size(), chunks.size());
  std::vector<std::string> names(devices.size());
  std::exception_ptr error;
  bool validation = a.validation || VulkanContext::validation_requested_by_environment();
  bool progressOn = !a.quiet && Progress::stderr_is_terminal();
  Progress progress("devices", uint64_t(image.pixels()) * total, progressOn);
  // Progress lines of their own would interleave; one counts for all.
  Progress silent("", 0, false);
  PassHook keepGoing = [&](const ImageStats&, uint32_t) { return !shouldStop(); };

  auto run = [&](size_t d) {
    std::string lostAt;  // where a lost device stopped: its chunk and the samples it kept of it
    try {
      const RenderDevice& dev = devices[d];
      const CompiledScene& cs = *dev.scene;
      std::unique_ptr<VulkanContext> ctx;
      std::unique_ptr<WavefrontRenderer> gpu;
      if (dev.renderer != "cpu") {
        ctx = std::make_unique<VulkanContext>(dev.device, validation);
        {
          std::lock_guard<std::mutex> lock(mutex);
          names[d] = ctx->info().name + (dev.renderer == "gpu" ? "" : ", " + dev.renderer);
        }
        gpu = std::make_unique<WavefrontRenderer>(*ctx, cs, renderer_settings(kernel_variant(dev.renderer), a));
      } else {
        std::lock_guard<std::mutex> lock(mutex);
        names[d] = "the CPU reference";
      }
      for (;;) {
        SampleRange c;
        {
          std::unique_lock<std::mutex> lock(mutex);
          // With no chunk left, wait while others render: one may be lost
          // and give the rest of its chunk back.
          changed.wait(lock, [&] { return own[d] || next < chunks.size() || pending == 0 || error || shouldStop(); });
          if (error || shouldStop() || (!own[d] && next == chunks.size())) break;
          if (own[d]) {
            c = *own[d];
            own[d].reset();
          } else {
            c = chunks[next++];
            ++pending;
          }
        }
        ImageStats part(image.width, image.height, image.layers);
        uint32_t reached = c.begin;
        std::exception_ptr lost;
        try {
          reached = gpu ? gpu->render(part, c, silent, keepGoing) : render_cpu(cs, a.threads, part, c, silent, keepGoing);
        } catch (const DeviceLost& e) {
          // A chunk's image up to its last pass is whole (--devices renders
          // no adaptive batches, the one thing that breaks it).
          if (!e.intact) throw RenderError(std::string(e.what()) + " part-way through a batch of adaptive samples");
          reached = e.reached;
          lost = std::current_exception();
          lostAt = " during samples " + format_sample_ranges({c}) + " (it kept " +
                   (reached > c.begin ? format_sample_ranges({{c.begin, reached}}) : "none") + ")";
        }
        progress.add(uint64_t(image.pixels()) * (reached - c.begin));
        std::lock_guard<std::mutex> lock(mutex);
        --pending;
        if (lost && reached < c.end) chunks.push_back({reached, c.end});
        image.add(part);
        done.push_back({c.begin, reached});
        done = join_ranges(done);
        changed.notify_all();
        if (afterChunk) afterChunk(image, done);
        if (lost) std::rethrow_exception(lost);
        if (reached < c.end) break;
      }
      if (ctx && ctx->validation_messages() > 0)
        throw RenderError(std::to_string(ctx->validation_messages()) + " Vulkan validation message(s) reported; no image written");
    } catch (const DeviceLost& e) {
      // The others take over what it had left: its own chunk where it was
      // lost before it began, the rest of the chunk in hand (queued above),
      // and the chunks not yet dealt.
      std::lock_guard<std::mutex> lock(mutex);
      if (own[d]) {
        chunks.push_back(*own[d]);
        own[d].reset();
        --pending;
      }
      if (names[d].empty()) names[d] = e.device;
      lostDevices->push_back(names[d] + lostAt);
      names[d] += " (lost)";
      changed.notify_all();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!error) error = std::current_exception();
      changed.notify_all();
    }
    // Stopped before its own chunk began: that chunk stays undone.
    std::lock_guard<std::mutex> lock(mutex);
    if (own[d]) {
      own[d].reset();
      --pending;
      changed.notify_all();
    }
  };
  std::vector<std::thread> threads;
  for (size_t d = 0; d < devices.size(); ++d) threads.emplace_back(run, d);
  for (std::thread& t : threads) t.join();
  progress.finish();
  if (error) std::rethrow_exception(error);
  *where = "";
  for (const std::string& n : names) *where += (where->empty() ? "" : " + ") + n;
  return done;
}


}  // namespace wp
