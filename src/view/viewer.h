// viewer.h — `wavepath view`: a window on a render refining, on the same
// kernels as `render` (docs/viewer.md). Built where GLFW is found
// (WAVEPATH_VIEWER); everything else builds and runs without it.
#pragma once

#include <string>

#include "cli/render_args.h"

namespace wp {

struct ViewerArgs {
  RenderArgs render;       // the scene and the render options `render` takes
  bool exitWhenDone = false;    // render --spp samples, write -o and its EXR, exit 0
};

// Opens the window and runs until Esc or the window is closed (or, with
// exitWhenDone, the samples are done). Returns the exit status: 0, or 2
// where there is no display or the device cannot present to it (one line on
// stderr). Throws InputError / RenderError as `render` does.
int run_viewer(const ViewerArgs& args);

// The keys, one line each, as `view --help` and the ? key print them.
const char* viewer_keys();

}  // namespace wp
