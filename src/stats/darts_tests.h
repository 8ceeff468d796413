// darts_tests.h — runs a darts test file (scene/darts_tests.h) through the
// renderer's own code: materials sampled by bsdf_sample, surfaces by the
// emitter sampling of next-event estimation, rays traced by the BVH walk,
// all through the probes of probes.glsl, on a Vulkan device (probe.comp) or
// on the CPU reference. Each test checks what its darts counterpart checks
// and writes what it writes, beside the file: NAME-sampled.png/.exr (the
// histogram of sampled directions) and, for the sampling tests,
// NAME-pdf.png/.exr. Beyond darts, a chi-square of the histogram against
// the pdf (stats/direction_test.h) decides too.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace wp {

struct DartsTestOptions {
  bool cpu = false;    // the CPU reference instead of a Vulkan device
  std::string device;  // Vulkan device selector
  int threads = 0;     // CPU threads (0: all)
  uint32_t seed = 0;   // of the samples' random numbers
  bool validation = false;
  // For the tests only: the pdf a sampling test checks against is that of a
  // normal tilted by this many radians (material tests) or of a viewpoint
  // moved this far along x (surface tests), or each photon's power is
  // scaled by 1 + this (photon map tests), so that a verdict can be shown
  // to fail.
  float plantedPdfError = 0.0f;
};

struct DartsTestResult {
  std::string name;
  std::string where;  // FILE: at /tests/N
  bool passed = false;
  bool unreadable = false;  // the test could not be read (message says why)
  std::string message;      // why it failed
};

// Runs every test of `file`, printing darts' messages to `log` (if not
// null). Throws InputError where the file as a whole cannot be read, and
// RenderError where the device fails.
std::vector<DartsTestResult> run_darts_tests(const std::string& file, const DartsTestOptions& options, FILE* log);

}  // namespace wp
