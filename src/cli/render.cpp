// `wavepath render`: a scene to PNG and EXR, on a kernel variant or the CPU
// reference, with the CS184 pathtracer's short options.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/render_args.h"
#include "job/render_job.h"
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

  // An image the host cannot hold is refused before any work: -r's before
  // the scene is loaded.
  if (a.resolution.size() == 2) check_image_fits_host(a.resolution[0], a.resolution[1], a.aovs);
  Scene scene = load_scene_with_overrides(a);
  check_image_fits_host(scene.camera.width, scene.camera.height, a.aovs);
  RenderJob job = plan_render(scene, a);
  const CompiledScene& first = job.first();
  const ImageStats& image = job.image;

  // Between passes: stop on a signal or a spent budget, and checkpoint.
  StopSignals signals;
  g_stopSignal = 0;
  auto write_partial = [&](const std::string& path, const ImageStats& img, const std::vector<SampleRange>& ranges,
                           const std::string& status, bool exactSums) {
    RenderRecord r = job.record;
    r.samples = format_sample_ranges(ranges);
    r.status = status;
    write_exr(path, img, r, exactSums);
  };
  auto lastCheckpoint = std::chrono::steady_clock::now();
  RenderControl control;
  control.start = commandStart;
  control.budgetSeconds = budget;
  control.budgetText = a.time;
  control.stopReason = [] {
    const int sig = g_stopSignal;
    return sig == 0 ? std::string() : std::string("interrupted by ") + (sig == SIGINT ? "SIGINT" : "SIGTERM");
  };
  // The partial file the render can go on from, and its samples: the file
  // resumed, then each checkpoint written.
  std::string kept = job.done.empty() ? "" : a.resume;
  std::vector<SampleRange> keptRanges = job.done;
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
  control.afterPass = [&](const ImageStats& img, const std::vector<SampleRange>& sofar) {
    auto now = std::chrono::steady_clock::now();
    if (a.checkpoint.empty() || std::chrono::duration<double>(now - lastCheckpoint).count() < checkpointEvery) return;
    lastCheckpoint = now;
    write_checkpoint(img, sofar, "checkpoint");
  };
  const RenderOutcome run = run_render_job(job, a, control);
  const int stopSignal = g_stopSignal;
  const bool complete = run.complete;
  const bool deviceLost = run.deviceLost;
  const std::string& status = run.status;
  const std::vector<SampleRange>& done = job.done;
  if (run.imageBroken) {
    std::fprintf(stderr, "wavepath: device lost: %s, part-way through a batch of adaptive samples, which no image records; %s\n",
                 run.lostNames.c_str(),
                 kept.empty() ? "no samples kept (--checkpoint keeps them); run the command again"
                              : ("kept " + kept + " (samples " + format_sample_ranges(keptRanges) + "); finish with: " +
                                 resume_command_line(a, kept)).c_str());
    return kExitDeviceLost;
  }
  if (done.empty()) {  // lost before a single pass (run_render_job throws for every other stop)
    std::fprintf(stderr, "wavepath: device lost: %s, before a single pass was done: no samples kept, no image written; run the command again\n",
                 run.lostNames.c_str());
    return kExitDeviceLost;
  }

  const bool exactSums = keeps_exact_sums(a, complete);
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
  for (const std::string& d : run.lostDevices) {
    if (!deviceLost) std::fprintf(stderr, "wavepath: device lost: %s; the other devices rendered the rest\n", d.c_str());
  }
  if (deviceLost) {
    std::fprintf(stderr, "wavepath: device lost: %s: kept samples %s (of %s) in %s%s; finish with: %s\n", run.lostNames.c_str(), samples.c_str(),
                 format_sample_ranges({job.range}).c_str(), written.c_str(),
                 a.checkpoint.empty() ? "" : (", and the checkpoint " + a.checkpoint).c_str(),
                 resume_command_line(a, a.checkpoint.empty() ? exr : a.checkpoint).c_str());
  } else if (!complete) {
    std::fprintf(stderr, "wavepath: %s: wrote the partial image of samples %s (of %s) to %s%s\n", status.c_str(),
                 samples.c_str(), format_sample_ranges({job.range}).c_str(), written.c_str(),
                 a.checkpoint.empty() ? "" : (", and the checkpoint " + a.checkpoint).c_str());
  }
  if (!a.quiet) {
    double total = 0.0;
    for (double n : image.count) total += n;
    // "N spp" for the whole render, else the ranges held.
    const std::string held = samples == "0:" + std::to_string(first.spp) ? std::to_string(first.spp) + " spp"
                                                                          : "samples " + samples + " of " + std::to_string(first.spp);
    std::printf("wrote %s: %dx%d, %s, %d max bounces, %.2f s on %s (%.2f Msamples/s)\n", written.c_str(),
                first.width, first.height, held.c_str(), int(first.params.image.z), run.seconds, run.where.c_str(),
                double(uint64_t(image.pixels()) * (run.samplesNow - run.samplesBefore)) / run.seconds * 1e-6);
    if (!rate.empty()) {
      std::printf("adaptive sampling: %.1f samples per pixel on average (at most %d); sample rates in %s\n",
                  total / double(image.pixels()), first.spp, rate.c_str());
    }
  }
  if (a.stageTimes && job.devices.size() == 1 && job.devices[0].renderer != "cpu") print_stage_times(run.times);
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
