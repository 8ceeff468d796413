#include "job/render_job.h"

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <optional>

#include "gpu/vulkan_context.h"
#include "gpu/wavefront.h"
#include "render/partial.h"
#include "util/error.h"

namespace wp {

RenderJob plan_render(const Scene& scene, const RenderArgs& a) {
  RenderJob job;
  // The renderers: one (the CPU reference or a variant on --device, the
  // variant checked), or those --devices names, each with the scene
  // compiled for it (a device's default variant may choose the BVH layout).
  if (a.devices.empty()) job.devices.push_back({a.cpu ? "cpu" : resolve_variant(a.variant, a.device), a.device, nullptr});
  for (const std::string& d : a.devices)
    job.devices.push_back({d == "cpu" ? "cpu" : resolve_variant(a.variant, d), d == "cpu" ? "" : d, nullptr});
  for (RenderDevice& d : job.devices) {
    auto found = job.compiled.find(d.renderer);
    if (found == job.compiled.end())
      found = job.compiled.emplace(d.renderer, compile_scene(scene, variant_options(options_from(a, a.seed), d.renderer))).first;
    d.scene = &found->second;
  }
  const CompiledScene& compiled = job.first();
  job.record.sceneHash = scene_content_hash(scene);
  job.record.settings = render_settings(compiled);
  job.record.version = wavepath_version();
  job.record.renderer = a.devices.empty() ? (a.cpu ? "the CPU reference" : job.devices[0].renderer) : "several devices";

  const uint32_t spp = uint32_t(compiled.spp);
  job.range = {0, spp};
  if (!a.samples.empty()) {
    std::vector<SampleRange> r = parse_sample_ranges(a.samples, "--samples");
    if (r.size() != 1) throw InputError("--samples: one range A:B, not several");
    job.range = r[0];
    if (job.range.end > spp)
      throw InputError("--samples " + a.samples + " goes past the render's " + std::to_string(spp) +
                       " samples per pixel (--spp, or the scene's sampler): a range is part of one render of 0:" + std::to_string(spp));
    if (compiled.adaptive.enabled() && job.range.begin > 0)
      throw InputError("--samples " + a.samples + ": under adaptive sampling a pixel stops on all its samples so far, which a "
                       "range starting past 0 does not have; render 0:B, or continue a checkpoint with --resume");
  }
  if (compiled.adaptive.enabled() && a.devices.size() > 1)
    throw InputError("--devices: adaptive sampling decides after each batch from all of a pixel's samples, so it runs on one device");
  job.image = ImageStats(compiled.width, compiled.height, image_layers(compiled.aovs));
  if (a.resume.empty()) return job;
  std::error_code ec;
  if (a.resume == a.checkpoint && !std::filesystem::exists(a.resume, ec)) return job;  // the first run of a restartable render
  PartialFile part = read_partial(a.resume);
  PartialFile self;  // its image is replaced by the part's below
  self.path = "this render";
  self.width = compiled.width;
  self.height = compiled.height;
  self.aovs = compiled.aovs;
  self.record = job.record;
  require_same_render(self, part);
  for (SampleRange r : part.ranges) {
    if (r.begin < job.range.begin || r.end > job.range.end)
      throw InputError(a.resume + " holds samples " + part.record.samples + ", outside this render's " + format_sample_ranges({job.range}));
  }
  if (compiled.adaptive.enabled()) {
    SampleRange r = part.ranges[0];
    if (part.ranges.size() != 1 || r.begin != job.range.begin || (r.end % uint32_t(compiled.adaptive.batch) != 0 && r.end != job.range.end))
      throw InputError(a.resume + " holds samples " + part.record.samples + ": under adaptive sampling a render resumes from whole "
                       "batches from its start");
  }
  job.image = std::move(part.image);
  job.done = join_ranges(part.ranges);
  return job;
}

RenderOutcome run_render_job(RenderJob& job, const RenderArgs& a, const RenderControl& control) {
  RenderOutcome out;
  std::vector<SampleRange> todo = missing_ranges(job.done, job.range.end);
  todo.erase(std::remove_if(todo.begin(), todo.end(), [&](SampleRange& r) {
               r.begin = std::max(r.begin, job.range.begin);
               return r.size() == 0;
             }),
             todo.end());
  for (SampleRange r : job.done) out.samplesBefore += r.size();

  // Between passes: stop for the caller's reason or a spent budget. With
  // several renderers this is asked from their threads.
  std::mutex stopMutex;
  std::string stoppedBy;
  bool budgetSpent = false;
  auto shouldStop = [&] {
    const std::string reason = control.stopReason ? control.stopReason() : std::string();
    const bool spent = control.budgetSeconds > 0.0 &&
                       std::chrono::duration<double>(std::chrono::steady_clock::now() - control.start).count() >= control.budgetSeconds;
    std::lock_guard<std::mutex> lock(stopMutex);
    if (!reason.empty() && stoppedBy.empty()) stoppedBy = reason;
    budgetSpent = budgetSpent || spent;
    return !stoppedBy.empty() || budgetSpent;
  };
  const auto start = std::chrono::steady_clock::now();
  out.where = "nothing (the resumed file held every sample)";
  std::optional<DeviceLost> lost;  // the one renderer's device, lost
  if (todo.size() == 1 && job.devices.size() == 1) {
    // One renderer, one range: straight into the image, pass by pass.
    const SampleRange r = todo[0];
    PassHook afterPass = [&](const ImageStats& img, uint32_t reached) {
      if (control.afterPass) {
        std::vector<SampleRange> sofar = job.done;
        sofar.push_back({r.begin, reached});
        control.afterPass(img, join_ranges(sofar));
      }
      return !shouldStop();
    };
    RenderArgs one = a;
    one.device = job.devices[0].device;
    uint32_t reached = r.begin;
    try {
      reached = render_on(job.devices[0].renderer, *job.devices[0].scene, one, job.image, r, afterPass, &out.where, &out.times);
    } catch (const DeviceLost& e) {
      lost = e;
      out.where = e.device + " (lost)";
      if (e.intact) reached = e.reached;
    }
    if (lost && !lost->intact) {
      // Its image holds samples of an adaptive batch part done, which no
      // partial file can record: the caller keeps what it wrote before.
      out.deviceLost = out.imageBroken = true;
      out.lostNames = lost->device;
      out.status = "device lost: " + out.lostNames;
      out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      for (SampleRange d : job.done) out.samplesNow += d.size();
      return out;
    }
    job.done.push_back({r.begin, reached});
    job.done = join_ranges(job.done);
  } else if (!todo.empty()) {
    job.done = render_on_devices(job.devices, a, job.image, job.done, todo, shouldStop, control.afterPass, &out.where, &out.lostDevices);
  }
  if (!todo.empty()) job.record.renderer = out.where;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.complete = job.done.size() == 1 && job.done[0].begin == job.range.begin && job.done[0].end == job.range.end;
  // Stopped by a lost device: the one, or every one of several (some lost
  // while the others were stopped is a stop).
  out.deviceLost = !out.complete && (lost || (!out.lostDevices.empty() && stoppedBy.empty() && !budgetSpent));
  out.lostNames = lost ? lost->device : "";
  for (const std::string& d : out.lostDevices) out.lostNames += (out.lostNames.empty() ? "" : ", ") + d;
  out.status = out.complete     ? "complete"
               : out.deviceLost ? "device lost: " + out.lostNames
               : !stoppedBy.empty() ? stoppedBy
                                    : "time budget of " + control.budgetText + " spent";
  if (job.done.empty() && !out.deviceLost) throw RenderError("stopped (" + out.status + ") before a single pass was done: no image written");
  for (SampleRange r : job.done) out.samplesNow += r.size();
  job.record.samples = format_sample_ranges(job.done);
  job.record.status = out.status;
  return out;
}

bool keeps_exact_sums(const RenderArgs& a, bool complete) {
  return !a.samples.empty() || !a.time.empty() || !a.checkpoint.empty() || !a.resume.empty() || !complete;
}

}  // namespace wp
