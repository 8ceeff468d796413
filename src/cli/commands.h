// commands.h — the subcommands of the `wavepath` command line, one file each
// in src/cli/. Each add_* declares its subcommand's options on `app` and
// returns the function that runs it once the command line is parsed; main.cpp
// runs the one given and turns errors into exit codes.
//
// Exit status: 0 success (compare: the images agree), 1 compare: they differ
// (bench: a variant disagreed with the CPU reference and was not timed), 2 bad
// input (scene, mesh, options), 3 rendering failed (no Vulkan device, out of
// memory, validation messages, truncated traversal, an output that could not
// be written), 75 (EX_TEMPFAIL) the render's device was lost: the samples
// done are kept, and the command printed finishes the render.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <string>

namespace wp::cli {

constexpr int kExitDeviceLost = 75;

struct Command {
  CLI::App* app;             // the subcommand, to tell whether it was given
  std::function<int()> run;  // runs it; throws InputError / RenderError
};

Command add_render(CLI::App& app);
Command add_merge(CLI::App& app);
Command add_compare(CLI::App& app);
Command add_bench(CLI::App& app);
Command add_convergence(CLI::App& app);
Command add_info(CLI::App& app);
Command add_devices(CLI::App& app);
Command add_test(CLI::App& app);
Command add_view(CLI::App& app);

// `wavepath test FILE` (test.cpp); `wavepath render` runs a test file this way too.
struct TestArgs {
  std::string file;
  bool cpu = false;
  std::string device;
  int threads = 0;
  uint32_t seed = 0;
  bool validation = false;
};
int run_darts_tests(const TestArgs& a);

}  // namespace wp::cli
