// `wavepath render`: a scene to PNG and EXR, on a kernel variant or the CPU
// reference, with the CS184 pathtracer's short options.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <numeric>
#include <optional>

#include "cli/commands.h"
#include "cli/render_args.h"
#include "gpu/vulkan_context.h"
#include "image/image.h"
#include "image/image_file.h"
#include "render/partial.h"
#include "scene/darts_tests.h"
#include "util/error.h"

namespace wp::cli {

namespace {

// CS184 writes the sample-rate image of out.png as out_rate.png.
std::string rate_image_path(const std::string& out) {
  std::filesystem::path p(out);
  return (p.parent_path() / (p.stem().string() + "_rate.png")).string();
}

// SCENE.FORMAT in the current directory. (darts names its output after the
// scene file, beside it, with the time appended; a name that changes on
// every run would break scripts and merges, so wavepath keeps one.)
std::string default_output(const std::string& scenePath, const std::string& format) {
  return std::filesystem::path(scenePath).stem().string() + "." + (format.empty() ? "png" : format);
}

void print_stage_times(const StageTimes& times) {
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
  std::printf("host: %llu submissions' sums read back and added to the image in %.3f s (wall)\n", (unsigned long long)times.submissions,
              times.foldSeconds);
  if (times.photonPassSeconds > 0.0)
    std::printf("photon map: %llu records, traced, balanced and uploaded in %.3f s (wall)\n", (unsigned long long)times.photonRecords,
                times.photonPassSeconds);
}

// The signal that asked the render to stop (SIGINT, SIGTERM), or 0. A second
// one aborts at once: the handler puts the default action back and raises it.
volatile std::sig_atomic_t g_stopSignal = 0;

extern "C" void on_stop_signal(int sig) {
  if (g_stopSignal != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_stopSignal = sig;
}

// Installs on_stop_signal for the life of a render, then puts back what was there.
class StopSignals {
 public:
  StopSignals() {
    oldInt_ = std::signal(SIGINT, on_stop_signal);
    oldTerm_ = std::signal(SIGTERM, on_stop_signal);
  }
  ~StopSignals() {
    std::signal(SIGINT, oldInt_);
    std::signal(SIGTERM, oldTerm_);
  }

 private:
  void (*oldInt_)(int);
  void (*oldTerm_)(int);
};

// "90s", "1.5m", "2h", "45" (seconds) as seconds; throws InputError naming `option`.
double parse_duration(const std::string& text, const std::string& option) {
  char* end = nullptr;
  double v = std::strtod(text.c_str(), &end);
  std::string unit = end ? std::string(end) : "";
  double scale = unit.empty() || unit == "s" ? 1.0 : unit == "m" || unit == "min" ? 60.0 : unit == "h" ? 3600.0 : -1.0;
  if (end == text.c_str() || scale < 0.0 || !(v > 0.0) || !std::isfinite(v))
    throw InputError(option + ": \"" + text + "\" is not a duration (a positive number of seconds, or with s, m or h)");
  return v * scale;
}

// What the render itself will take, before any work: the range of the whole
// render's samples and, resuming, the image that holds some of them.
struct RenderPlan {
  SampleRange range;
  ImageStats image;
  std::vector<SampleRange> done;  // the ranges `image` holds (resumed), joined
};

RenderPlan plan_render(const RenderArgs& a, const CompiledScene& compiled, const RenderRecord& identity) {
  RenderPlan plan;
  const uint32_t spp = uint32_t(compiled.spp);
  plan.range = {0, spp};
  if (!a.samples.empty()) {
    std::vector<SampleRange> r = parse_sample_ranges(a.samples, "--samples");
    if (r.size() != 1) throw InputError("--samples: one range A:B, not several");
    plan.range = r[0];
    if (plan.range.end > spp)
      throw InputError("--samples " + a.samples + " goes past the render's " + std::to_string(spp) +
                       " samples per pixel (--spp, or the scene's sampler): a range is part of one render of 0:" + std::to_string(spp));
    if (compiled.adaptive.enabled() && plan.range.begin > 0)
      throw InputError("--samples " + a.samples + ": under adaptive sampling a pixel stops on all its samples so far, which a "
                       "range starting past 0 does not have; render 0:B, or continue a checkpoint with --resume");
  }
  if (compiled.adaptive.enabled() && a.devices.size() > 1)
    throw InputError("--devices: adaptive sampling decides after each batch from all of a pixel's samples, so it runs on one device");
  plan.image = ImageStats(compiled.width, compiled.height, image_layers(compiled.aovs));
  if (a.resume.empty()) return plan;
  std::error_code ec;
  if (a.resume == a.checkpoint && !std::filesystem::exists(a.resume, ec)) return plan;  // the first run of a restartable render
  PartialFile part = read_partial(a.resume);
  PartialFile self;  // its image is replaced by the part's below
  self.path = "this render";
  self.width = compiled.width;
  self.height = compiled.height;
  self.aovs = compiled.aovs;
  self.record = identity;
  require_same_render(self, part);
  for (SampleRange r : part.ranges) {
    if (r.begin < plan.range.begin || r.end > plan.range.end)
      throw InputError(a.resume + " holds samples " + part.record.samples + ", outside this render's " + format_sample_ranges({plan.range}));
  }
  if (compiled.adaptive.enabled()) {
    SampleRange r = part.ranges[0];
    if (part.ranges.size() != 1 || r.begin != plan.range.begin || (r.end % uint32_t(compiled.adaptive.batch) != 0 && r.end != plan.range.end))
      throw InputError(a.resume + " holds samples " + part.record.samples + ": under adaptive sampling a render resumes from whole "
                       "batches from its start");
  }
  plan.image = std::move(part.image);
  plan.done = join_ranges(part.ranges);
  return plan;
}

int run_render(const RenderArgs& a) {
  const auto commandStart = std::chrono::steady_clock::now();
  // A darts test file is run, as darts runs it, not rendered.
  if (is_darts_test_file(a.scene)) return run_darts_tests(TestArgs{a.scene, a.cpu, a.device, a.threads, a.seed, a.validation});
  std::string format = a.format;
  std::string output = a.output;
  // darts' -f names a format (-f exr); CS184's -f a file (-f out.png).
  if (format.empty() && image_format_named(output) && output.find('.') == std::string::npos) {
    format = output;
    output.clear();
  }
  if (!format.empty() && !image_format_named(format))
    throw InputError("--format " + format + ": not an image format wavepath writes (" + image_format_names() + ")");
  std::string out = output.empty() ? default_output(a.scene, format) : output;
  std::optional<ImageFormat> outFormat = image_format_of(out);
  if (!outFormat) throw InputError(out + ": the output image's extension must name one of " + image_format_names());
  if (!format.empty() && *outFormat != *image_format_named(format))
    throw InputError(out + ": the extension contradicts --format " + format);
  // The EXR of statistics goes beside the image, unless the image is that EXR.
  const bool outIsExr = *outFormat == ImageFormat::Exr && (a.exr.empty() || a.exr == out);
  std::string exr = a.exr.empty() ? std::filesystem::path(out).replace_extension(".exr").string() : a.exr;
  if (std::filesystem::path(exr).extension() != ".exr") throw InputError(exr + ": the linear image must be an .exr file");
  if (!a.checkpoint.empty() && std::filesystem::path(a.checkpoint).extension() != ".exr")
    throw InputError(a.checkpoint + ": a checkpoint is a partial EXR and must be an .exr file");
  const double budget = a.time.empty() ? 0.0 : parse_duration(a.time, "--time");
  const double checkpointEvery = parse_duration(a.checkpointEvery, "--checkpoint-every");
  if (!a.cpu && !a.variant.empty()) kernel_variant(a.variant);  // an unknown variant fails before any work
  if (a.cpu && !a.devices.empty()) throw InputError("--cpu and --devices: name the CPU reference among the devices (--devices 0,cpu)");
  for (const std::string& path : {out, exr, a.checkpoint})
    if (!path.empty()) require_output_directory(path);

  // The renderers: one (the CPU reference or a variant on --device), or
  // those --devices names, each with the scene compiled for it (a device's
  // default variant may choose the BVH layout). An image the host cannot
  // hold is refused before any work: -r's before the scene is loaded.
  if (a.resolution.size() == 2) check_image_fits_host(a.resolution[0], a.resolution[1], a.aovs);
  Scene scene = load_scene_with_overrides(a);
  check_image_fits_host(scene.camera.width, scene.camera.height, a.aovs);
  std::vector<RenderDevice> devices;
  if (a.devices.empty()) devices.push_back({a.cpu ? "cpu" : resolve_variant(a.variant, a.device), a.device, nullptr});
  for (const std::string& d : a.devices) devices.push_back({d == "cpu" ? "cpu" : resolve_variant(a.variant, d), d == "cpu" ? "" : d, nullptr});
  std::map<std::string, CompiledScene> compiled;  // by renderer; its elements stay where they are
  for (RenderDevice& d : devices) {
    auto found = compiled.find(d.renderer);
    if (found == compiled.end())
      found = compiled.emplace(d.renderer, compile_scene(scene, variant_options(options_from(a, a.seed), d.renderer))).first;
    d.scene = &found->second;
  }
  const CompiledScene& first = *devices[0].scene;
  RenderRecord record;
  record.sceneHash = scene_content_hash(scene);
  record.settings = render_settings(first);
  record.version = wavepath_version();
  record.renderer = a.devices.empty() ? (a.cpu ? "the CPU reference" : devices[0].renderer) : "several devices";
  RenderPlan plan = plan_render(a, first, record);
  ImageStats& image = plan.image;
  std::vector<SampleRange> todo = missing_ranges(plan.done, plan.range.end);
  todo.erase(std::remove_if(todo.begin(), todo.end(), [&](SampleRange& r) {
               r.begin = std::max(r.begin, plan.range.begin);
               return r.size() == 0;
             }),
             todo.end());
  uint64_t samplesBefore = 0;
  for (SampleRange r : plan.done) samplesBefore += r.size();

  // Between passes: stop on a signal or a spent budget, and checkpoint.
  StopSignals signals;
  g_stopSignal = 0;
  bool budgetSpent = false;
  auto shouldStop = [&] {
    if (budget > 0.0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - commandStart).count() >= budget)
      budgetSpent = true;
    return g_stopSignal != 0 || budgetSpent;
  };
  auto write_partial = [&](const std::string& path, const ImageStats& img, const std::vector<SampleRange>& ranges,
                           const std::string& status, bool exactSums) {
    RenderRecord r = record;
    r.samples = format_sample_ranges(ranges);
    r.status = status;
    write_exr(path, img, r, exactSums);
  };
  auto lastCheckpoint = std::chrono::steady_clock::now();
  auto checkpoint_due = [&] {
    auto now = std::chrono::steady_clock::now();
    if (a.checkpoint.empty() || std::chrono::duration<double>(now - lastCheckpoint).count() < checkpointEvery) return false;
    lastCheckpoint = now;
    return true;
  };
  // The partial file the render can go on from, and its samples: the file
  // resumed, then each checkpoint written.
  std::string kept = plan.done.empty() ? "" : a.resume;
  std::vector<SampleRange> keptRanges = plan.done;
  auto write_checkpoint = [&](const ImageStats& img, const std::vector<SampleRange>& ranges, const std::string& status) {
    try {
      write_partial(a.checkpoint, img, ranges, status, true);
    } catch (const RenderError& e) {  // a full disk: say what is still there
      if (kept != a.checkpoint) throw;
      throw RenderError(std::string(e.what()) + " (the checkpoint there, of samples " + format_sample_ranges(keptRanges) + ", is intact)");
    }
    kept = a.checkpoint;
    keptRanges = ranges;
  };
  auto start = std::chrono::steady_clock::now();
  StageTimes times;
  std::string where = "nothing (the resumed file held every sample)";
  std::vector<SampleRange> done = plan.done;
  std::optional<DeviceLost> lost;       // the one device, lost
  std::vector<std::string> lostDevices;  // devices lost among several
  if (todo.size() == 1 && devices.size() == 1) {
    // One renderer, one range: straight into the image, pass by pass.
    const SampleRange r = todo[0];
    PassHook afterPass = [&](const ImageStats& img, uint32_t reached) {
      if (checkpoint_due()) {
        std::vector<SampleRange> sofar = done;
        sofar.push_back({r.begin, reached});
        write_checkpoint(img, join_ranges(sofar), "checkpoint");
      }
      return !shouldStop();
    };
    RenderArgs one = a;
    one.device = devices[0].device;
    uint32_t reached = r.begin;
    try {
      reached = render_on(devices[0].renderer, *devices[0].scene, one, image, r, afterPass, &where, &times);
    } catch (const DeviceLost& e) {
      lost = e;
      where = e.device + " (lost)";
      if (e.intact) reached = e.reached;
    }
    if (lost && !lost->intact) {
      // Its image holds samples of an adaptive batch part done, which no
      // partial file can record: what is kept is what was written before.
      std::fprintf(stderr, "wavepath: device lost: %s, part-way through a batch of adaptive samples, which no image records; %s\n",
                   lost->device.c_str(),
                   kept.empty() ? "no samples kept (--checkpoint keeps them); run the command again"
                                : ("kept " + kept + " (samples " + format_sample_ranges(keptRanges) + "); finish with: " +
                                   resume_command_line(a, kept)).c_str());
      return kExitDeviceLost;
    }
    done.push_back({r.begin, reached});
    done = join_ranges(done);
  } else if (!todo.empty()) {
    done = render_on_devices(devices, a, image, done, todo, shouldStop,
                             [&](const ImageStats& img, const std::vector<SampleRange>& sofar) {
                               if (checkpoint_due()) write_checkpoint(img, sofar, "checkpoint");
                             },
                             &where, &lostDevices);
  }
  if (!todo.empty()) record.renderer = where;
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const int stopSignal = g_stopSignal;
  const bool complete = done.size() == 1 && done[0].begin == plan.range.begin && done[0].end == plan.range.end;
  // Stopped by a lost device: the one, or every one of several.
  const bool deviceLost = !complete && (lost || (!lostDevices.empty() && !stopSignal && !budgetSpent));
  std::string lostNames = lost ? lost->device : "";
  for (const std::string& d : lostDevices) lostNames += (lostNames.empty() ? "" : ", ") + d;
  std::string status = complete     ? "complete"
                       : deviceLost ? "device lost: " + lostNames
                       : stopSignal ? std::string("interrupted by ") + (stopSignal == SIGINT ? "SIGINT" : "SIGTERM")
                                    : "time budget of " + a.time + " spent";
  if (done.empty() && deviceLost) {
    std::fprintf(stderr, "wavepath: device lost: %s, before a single pass was done: no samples kept, no image written; run the command again\n",
                 lostNames.c_str());
    return kExitDeviceLost;
  }
  if (done.empty()) throw RenderError("stopped (" + status + ") before a single pass was done: no image written");
  uint64_t samplesNow = 0;
  for (SampleRange r : done) samplesNow += r.size();

  // The EXR holds the exact sums where it may be merged or resumed: a part
  // of the render's samples, or one whose render was resumed, budgeted,
  // checkpointed or stopped early. A plain render's is the smaller file.
  const bool exactSums = !a.samples.empty() || !a.time.empty() || !a.checkpoint.empty() || !a.resume.empty() || !complete;
  // With adaptive sampling, CS184's sample-rate image goes beside the render.
  std::string rate = first.adaptive.enabled() ? rate_image_path(out) : "";
  write_partial(exr, image, done, status, exactSums);
  try {
    if (!outIsExr) write_image(out, mean_rgb(image), scene.eightBitCurve);
    if (!rate.empty()) write_sample_rate_png(rate, image, first.spp);
    if (!a.checkpoint.empty()) write_checkpoint(image, done, status);
  } catch (...) {
    std::remove(exr.c_str());  // all images or none
    if (!outIsExr) std::remove(out.c_str());
    throw;
  }
  if (image.nonFinite > 0) {
    std::fprintf(stderr, "wavepath: warning: %llu non-finite samples were dropped\n", (unsigned long long)image.nonFinite);
  }
  const std::string samples = format_sample_ranges(done);
  const std::string written = outIsExr ? exr : out + " and " + exr;
  for (const std::string& d : lostDevices) {
    if (!deviceLost) std::fprintf(stderr, "wavepath: device lost: %s; the other devices rendered the rest\n", d.c_str());
  }
  if (deviceLost) {
    std::fprintf(stderr, "wavepath: device lost: %s: kept samples %s (of %s) in %s%s; finish with: %s\n", lostNames.c_str(), samples.c_str(),
                 format_sample_ranges({plan.range}).c_str(), written.c_str(),
                 a.checkpoint.empty() ? "" : (", and the checkpoint " + a.checkpoint).c_str(),
                 resume_command_line(a, a.checkpoint.empty() ? exr : a.checkpoint).c_str());
  } else if (!complete) {
    std::fprintf(stderr, "wavepath: %s: wrote the partial image of samples %s (of %s) to %s%s\n", status.c_str(),
                 samples.c_str(), format_sample_ranges({plan.range}).c_str(), written.c_str(),
                 a.checkpoint.empty() ? "" : (", and the checkpoint " + a.checkpoint).c_str());
  }
  if (!a.quiet) {
    double total = 0.0;
    for (double n : image.count) total += n;
    // "N spp" for the whole render, else the ranges held.
    const std::string held = samples == "0:" + std::to_string(first.spp) ? std::to_string(first.spp) + " spp"
                                                                          : "samples " + samples + " of " + std::to_string(first.spp);
    std::printf("wrote %s: %dx%d, %s, %d max bounces, %.2f s on %s (%.2f Msamples/s)\n", written.c_str(),
                first.width, first.height, held.c_str(), int(first.params.image.z), seconds, where.c_str(),
                double(uint64_t(image.pixels()) * (samplesNow - samplesBefore)) / seconds * 1e-6);
    if (!rate.empty()) {
      std::printf("adaptive sampling: %.1f samples per pixel on average (at most %d); sample rates in %s\n",
                  total / double(image.pixels()), first.spp, rate.c_str());
    }
  }
  if (a.stageTimes && devices.size() == 1 && devices[0].renderer != "cpu") print_stage_times(times);
  // Interrupted: the shell's status for death by that signal, so that scripts
  // see the render did not finish (a spent time budget is a success); a
  // lost device's, for a farm to run the printed command again.
  return deviceLost ? kExitDeviceLost : stopSignal ? 128 + stopSignal : 0;
}

}  // namespace

Command add_render(CLI::App& app) {
  auto r = std::make_shared<RenderArgs>();
  auto hemisphere = std::make_shared<bool>(false);
  CLI::App* render = app.add_subcommand("render", "render a scene to PNG (and a linear EXR with statistics)");
  render->add_option("scene", r->scene, "scene file (darts JSON, glTF 2.0, CS184 COLLADA)")->required();
  // Short options in parentheses are the CS184 pathtracer's, for its students.
  render->add_option("-o,-f,--output", r->output,
                     std::string("image to write: ") + image_format_names() +
                         " by its extension (default: SCENE-NAME.png); a linear EXR of statistics goes beside it (CS184: -f FILE; "
                         "darts: -f FORMAT)");
  render->add_option("--format", r->format, std::string("format of the default output name (darts' -f): ") + image_format_names());
  render->add_option("--exr", r->exr,
                     "linear EXR: mean, variance, sample count, AOV layers, and the exact sums a merge or resume needs "
                     "(default: next to the PNG)");
  render->add_option("--samples", r->samples,
                     "render samples A to B-1 of every pixel (A:B) of the render of --spp samples; parts merge with `wavepath merge`");
  render->add_option("--aov", r->aovs, "first-hit layers to add to the EXR: " + aov_layer_names())->delimiter(',');
  render->add_option("--time", r->time, "time budget (90s, 5m, 1h): whole passes until it is spent; the EXR records the samples reached");
  render->add_option("--checkpoint", r->checkpoint, "partial EXR to write every --checkpoint-every and when the render stops");
  // The last given counts: a script's own (scripts/slurm/render-array.sh) gives way to one passed after it.
  render->add_option("--checkpoint-every", r->checkpointEvery, "how often to write the checkpoint (default 60s; the last given counts)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  render->add_option("--resume", r->resume,
                     "continue the render a checkpoint or partial EXR holds samples of, rendering only those missing (the "
                     "checkpoint's own path: resume if it exists, else start)");
  add_scene_options(*render, *r, *hemisphere);
  render->add_option("-p,--cell", r->cell, "render one cell X Y DX DY of the frame, rows counted from the bottom (CS184: -p)")
      ->expected(4)
      ->check(CLI::Range(0, MAX_IMAGE_SIZE));
  render->add_option("--devices", r->devices,
                     "render on several devices at once, in one process: Vulkan device indices or names, and cpu for the "
                     "CPU reference (e.g. 0,1 or 0,cpu); chunks of samples go to whichever is free")
      ->delimiter(',');
  render->add_flag("--cpu", r->cpu, "render with the CPU reference renderer instead of Vulkan");
  render->add_option("-t,--threads", r->threads, "CPU threads for --cpu (default: all cores) (CS184: -t)")->check(CLI::Range(0, 1024));
  render->add_flag("-q,--quiet", r->quiet, "no progress line and no summary");
  render->add_flag("--stage-times", r->stageTimes, "print the GPU time of each kernel stage (Vulkan timestamps)");
  return {render, [r, hemisphere] {
            apply_hemisphere_flag(*r, *hemisphere);
            return run_render(*r);
          }};
}

}  // namespace wp::cli
