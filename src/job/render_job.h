// render_job.h — a render as `wavepath render` runs it, for the command line
// and the Python module alike: the renderers the arguments name, the scene
// compiled for each, the render's identity, the samples it is to take (less
// those a resumed partial file holds), and the render itself, pass by pass,
// until its samples are done or it is told to stop (docs/partial-renders.md).
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "image/image.h"
#include "job/render_args.h"
#include "render/compiled_scene.h"
#include "render/render_control.h"
#include "scene/scene.h"

namespace wp {

struct RenderJob {
  std::vector<RenderDevice> devices;              // one, or those --devices names; each points into `compiled`
  std::map<std::string, CompiledScene> compiled;  // by renderer (a map's elements stay where they are when it moves)
  // The render's identity (scene content, settings, version, renderer);
  // run_render_job fills in the samples held and the status.
  RenderRecord record;
  SampleRange range;              // the samples of every pixel the render is to hold
  ImageStats image;               // what it holds: a resumed file's samples, then this run's
  std::vector<SampleRange> done;  // the ranges `image` holds, joined

  const CompiledScene& first() const { return *devices[0].scene; }
  RenderJob() = default;
  RenderJob(RenderJob&&) = default;
  RenderJob& operator=(RenderJob&&) = default;
  RenderJob(const RenderJob&) = delete;  // `devices` point into `compiled`
};

// The render of `scene` that `a` asks for, before any work: its renderers
// (a.cpu, a.devices, a.device and a.variant), the scene compiled for each,
// its identity, the range of samples (a.samples, else all) and, resuming
// (a.resume), the image the file holds. Throws InputError for an unknown
// variant, a range past the render's samples, a file of another render.
RenderJob plan_render(const Scene& scene, const RenderArgs& a);

// How a run may end before its samples are done, and what it is told
// between passes.
struct RenderControl {
  double budgetSeconds = 0.0;  // a time budget counted from `start` (0: none)
  std::string budgetText;      // that budget as given ("90s"), for the status
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  // Polled between passes (from the renderers' threads where there are
  // several): why to stop, such as "interrupted by SIGINT", or "" to go on.
  std::function<std::string()> stopReason;
  // After each pass (one renderer) or chunk (several), with the image so far
  // and the ranges it holds.
  ChunkHook afterPass;
};

struct RenderOutcome {
  bool complete = false;  // every sample of job.range is in the image
  std::string status;     // "complete", the stop reason, or "time budget of 90s spent"
  std::string where;      // what rendered it
  StageTimes times;       // per stage (one GPU renderer)
  double seconds = 0.0;   // rendering
  uint64_t samplesBefore = 0, samplesNow = 0;  // per pixel: resumed, and held at the end
  // Devices lost (DeviceLost, docs/partial-renders.md's Faults). One
  // renderer stops there; among several the others take over, and the
  // render stops only where every one is lost.
  bool deviceLost = false;   // it stopped for that: status "device lost: " + lostNames; job.done may be empty
  bool imageBroken = false;  // lost part-way through a batch of adaptive samples: job.image holds samples no range
                             // records, not to be written; job.done and job.record are as planned
  std::string lostNames;     // the device lost, or those lost among several (with their chunks)
  std::vector<std::string> lostDevices;  // among several: each lost, its chunk and what it kept
};

// Renders the samples of job.range that job.done lacks into job.image,
// with one renderer pass by pass or with several in chunks
// (render_on_devices), until they are done, control.stopReason gives a
// reason or the budget is spent. Updates job.done and job.record (samples,
// status, renderer). A device lost ends the run as a stop does (the
// outcome says so) rather than throwing. Throws RenderError where it stopped
// for another reason before a single pass was done.
RenderOutcome run_render_job(RenderJob& job, const RenderArgs& a, const RenderControl& control = {});

// Whether a render's EXR keeps the exact sums (a partial file that merges
// and resumes): a part of the render's samples, one resumed, budgeted,
// checkpointed or stopped early. A plain render's is the smaller file.
bool keeps_exact_sums(const RenderArgs& a, bool complete);

}  // namespace wp
