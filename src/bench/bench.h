// bench.h — `wavepath bench`: kernel variants timed side by side on a set of
// scenes. A variant's timings only count after `wavepath compare`'s test has
// found it agrees with the CPU reference on that scene.
#pragma once

#include <string>
#include <vector>

namespace wp {

struct BenchOptions {
  std::vector<std::string> scenes;
  std::vector<std::string> variants;  // kernel variant names
  int spp = 4;                        // samples per timed render
  int repeats = 3;                    // timed renders per variant (after one warm-up)
  std::vector<int> resolution;        // W H override, or empty
  int checkSize = 64;                 // the correctness check renders checkSize^2 pixels...
  int checkSpp = 64;                  // ...at this many samples, against the CPU reference
  float plantedBias = 1.0f;           // debug: planted in the GPU side of the check
  std::string device;
  bool validation = false;
  std::string jsonPath;
  std::string csvPath;
  std::string* results = nullptr;  // if set, receives the JSON document --out writes (the Python module's rows)
  // Ray casting instead of rendering: primary rays from the scene's camera and
  // one cosine-distributed bounce from each hit, traced by each variant (after
  // its hits are checked against the CPU traversal) and by Embree if built in.
  bool raycast = false;
  // BVH builds instead of rendering: each scene's tree built as the renderer
  // builds it, timed against Embree's build of the same triangles.
  bool build = false;
  // The SIMT model instead of timing (simt_model.h): the ray sets of
  // --raycast replayed through the walks in warps of these widths on a model
  // of this GPU, beside a GPU's measured --raycast JSON where given.
  bool simt = false;
  std::vector<int> warpWidths{32, 64};
  std::string gpuModel = "h200";
  std::string measuredPath;
  std::vector<std::string> reorders;  // --simt: bounce and shadow rays also sorted so ("octant", "morton")
  uint32_t nodeStrideBytes = 0;       // --simt: also model each variant's nodes at this stride (SimtWalk)
};

// Prints the results table; writes JSON / CSV when asked. Returns 0 when every
// variant passed its check, 1 otherwise (those were not timed).
int run_bench(const BenchOptions& options);
int run_raycast_bench(const BenchOptions& options);
int run_build_bench(const BenchOptions& options);
int run_simt_bench(const BenchOptions& options);

// The variants whose walks differ on a GPU: the SIMT model's default set.
std::vector<std::string> simt_variants();

}  // namespace wp
