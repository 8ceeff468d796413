// wavepath — a wavefront path tracer on Vulkan compute, with a CPU reference.
//
//   wavepath render SCENE [options]       render to PNG and EXR           (render.cpp)
//   wavepath merge PARTS -o OUT.png       add up partial renders          (merge.cpp)
//   wavepath compare SCENE | --images A B  do two renders agree?           (compare.cpp)
//   wavepath bench [options]              time kernel variants            (bench.cpp)
//   wavepath convergence SCENE            RMSE against spp per sampler    (convergence.cpp)
//   wavepath info SCENE                   what the renderer builds        (info.cpp)
//   wavepath devices                      Vulkan devices and variants     (devices.cpp)
//   wavepath test FILE                    run a darts test file           (test.cpp)
//
// Exit status (commands.h): 0 success, 1 compare or bench found a
// disagreement or a darts test failed, 2 bad input, 3 rendering failed, 75
// the device was lost (the samples done kept, a command to finish printed).
#include <cstdio>
#include <vector>

#include "cli/commands.h"
#include "gpu/vulkan_context.h"
#include "util/error.h"

int main(int argc, char** argv) {
  using namespace wp;
  CLI::App app{"wavepath: a wavefront path tracer on Vulkan compute, with a CPU reference renderer"};
  app.require_subcommand(1);
  const std::vector<cli::Command> commands = {cli::add_render(app), cli::add_merge(app), cli::add_compare(app), cli::add_bench(app),
                                              cli::add_convergence(app), cli::add_info(app), cli::add_devices(app),
                                              cli::add_test(app), cli::add_view(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --version and the like
    std::fprintf(stderr, "wavepath: error: %s (see wavepath --help)\n", e.what());
    return 2;
  }
  try {
    for (const cli::Command& c : commands)
      if (*c.app) return c.run();
  } catch (const InputError& e) {
    std::fprintf(stderr, "wavepath: error: %s\n", e.what());
    return 2;
  } catch (const RenderError& e) {
    std::fprintf(stderr, "wavepath: error: %s\n", e.what());
    return 3;
  } catch (const vk::SystemError& e) {
    std::fprintf(stderr, "wavepath: error: Vulkan: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "wavepath: error: %s\n", e.what());
    return 3;
  }
  return 0;
}
