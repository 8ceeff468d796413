// `wavepath view SCENE [render options]`: the render in a window, refining
// (src/view/viewer.h). Where wavepath was built without GLFW the command
// says so and exits 2.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/render_args.h"
#include "gpu/wavefront.h"
#include "image/image_file.h"
#include "util/error.h"
#ifdef WAVEPATH_HAVE_VIEWER
#include "view/viewer.h"
#endif

namespace wp::cli {

Command add_view(CLI::App& app) {
  auto r = std::make_shared<RenderArgs>();
  auto hemisphere = std::make_shared<bool>(false);
  auto exitWhenDone = std::make_shared<bool>(false);
  auto keys = std::make_shared<bool>(false);
  CLI::App* view = app.add_subcommand("view", "render a scene in a window, refining, with the CS184 pathtracer's controls (--keys lists them)");
  view->add_option("scene", r->scene, "scene file (darts JSON, glTF 2.0, CS184 COLLADA)");
  view->add_option("-o,--output", r->output,
                   std::string("image S, Esc and closing the window write (") + image_format_names() +
                       "), with its EXR and camera file beside it (default: SCENE_screenshot_M-D_h-m-s.png)");
  add_scene_options(*view, *r, *hemisphere);
  view->add_flag("--exit-when-done", *exitWhenDone, "render --spp samples, write --output (and its EXR), and exit");
  view->add_flag("--keys", *keys, "list the keys and the mouse's controls");
  view->add_flag("-q,--quiet", r->quiet, "no summary on exit");
#ifdef WAVEPATH_HAVE_VIEWER
  view->footer(std::string("\nKeys and mouse:\n") + viewer_keys());
#endif
  return {view, [r, hemisphere, exitWhenDone, keys]() -> int {
#ifdef WAVEPATH_HAVE_VIEWER
            if (*keys) {
              std::fputs(viewer_keys(), stdout);
              return 0;
            }
            if (r->scene.empty()) throw InputError("view: which scene? (wavepath view SCENE)");
            apply_hemisphere_flag(*r, *hemisphere);
            if (!r->output.empty()) {
              std::optional<ImageFormat> f = image_format_of(r->output);
              if (!f || *f == ImageFormat::Exr)
                throw InputError(r->output + ": the window's image is an 8-bit image (" + image_format_names() + " but exr, which is written beside it)");
              require_output_directory(r->output);
            }
            if (!r->variant.empty()) kernel_variant(r->variant);  // an unknown variant fails before the window opens
            return run_viewer(ViewerArgs{*r, *exitWhenDone});
#else
            (void)hemisphere;
            (void)exitWhenDone;
            (void)keys;
            std::fprintf(stderr, "wavepath view: this wavepath was built without a window (GLFW not found: install libglfw3-dev and build again)\n");
            return 2;
#endif
          }};
}

}  // namespace wp::cli
