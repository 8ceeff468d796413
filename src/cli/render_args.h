// render_args.h (cli) — the options of a render as the command line takes
// them (CLI11), into the RenderArgs that job/render_args.h renders by, and
// the command line that renders what a RenderArgs asks for.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "job/render_args.h"

namespace wp::cli {

// The options of what and how to render that `render` and `view` share
// (samples, bounces, integrator, lens, camera, device...), into `r`; -H sets
// `hemisphere`, which apply_hemisphere_flag turns into the integrator.
void add_scene_options(CLI::App& app, RenderArgs& r, bool& hemisphere);
void apply_hemisphere_flag(RenderArgs& r, bool hemisphere);

// The `wavepath render` command line that renders what `a` asks for: the
// scene and every option that changes the image (the view prints it to
// render its window's view again).
std::string render_command_line(const RenderArgs& a);
// The `wavepath render` command line that continues the render `a` asks
// for from the partial file `partial`: the same image, outputs, sample
// range, devices and checkpoint.
std::string resume_command_line(const RenderArgs& a, const std::string& partial);

}  // namespace wp::cli
