// wavepath test FILE: runs a darts file of "type": "tests" (darts-2022
// src/tests/*.cpp) through the renderer's own code (stats/darts_tests.h),
// prints what darts prints and says which tests failed.
//
// Exit status: 0 every test passed, 1 a test failed, 2 the file or a test
// could not be read.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "stats/darts_tests.h"

namespace wp::cli {

int run_darts_tests(const TestArgs& a) {
  DartsTestOptions o;
  o.cpu = a.cpu;
  o.device = a.device;
  o.threads = a.threads;
  o.seed = a.seed;
  o.validation = a.validation;
  std::vector<DartsTestResult> results = wp::run_darts_tests(a.file, o, stdout);
  int passed = 0;
  bool unreadable = false;
  for (const DartsTestResult& r : results) {
    passed += r.passed;
    unreadable = unreadable || r.unreadable;
    if (r.unreadable) std::fprintf(stderr, "wavepath: error: %s\n", r.message.c_str());
    else if (!r.passed) std::fprintf(stderr, "Test failed: \"%s\" (%s): %s\n", r.name.c_str(), r.where.c_str(), r.message.c_str());
  }
  std::fflush(stdout);
  const int count = int(results.size());
  if (passed == count) {
    std::printf("Passed all %d/%d tests. Also examine the generated images.\n", passed, count);
    return 0;
  }
  std::fprintf(stderr, "Failed %d/%d tests. Also examine the generated images.\n", count - passed, count);
  return unreadable ? 2 : 1;
}

Command add_test(CLI::App& app) {
  auto a = std::make_shared<TestArgs>();
  CLI::App* test = app.add_subcommand("test", "run a darts test file (\"type\": \"tests\"): material, surface and intersection tests");
  test->add_option("file", a->file, "darts JSON file of \"type\": \"tests\"")->required();
  test->add_flag("--cpu", a->cpu, "run the tests on the CPU reference instead of a Vulkan device");
  test->add_option("--device", a->device, "Vulkan device: index or part of the name (see `wavepath devices`)");
  test->add_option("-t,--threads", a->threads, "CPU threads for --cpu (default: all cores)")->check(CLI::Range(0, 1024));
  test->add_option("--seed", a->seed, "random seed of the samples");
  test->add_flag("--validation", a->validation, "enable Vulkan validation; any message fails the run (also WAVEPATH_VALIDATION=1)");
  return {test, [a] { return run_darts_tests(*a); }};
}

}  // namespace wp::cli
