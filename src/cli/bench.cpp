// `wavepath bench`: the options of the benchmarks (src/bench/).
#include <memory>

#include "bench/bench.h"
#include "cli/commands.h"
#include "cli/render_args.h"
#include "gpu/wavefront.h"

namespace wp::cli {

Command add_bench(CLI::App& app) {
  auto bench = std::make_shared<BenchOptions>();
  CLI::App* benchCmd = app.add_subcommand(
      "bench", "time kernel variants side by side on scenes; a variant is timed only after it agrees with the CPU reference");
  benchCmd->add_option("--scenes", bench->scenes, "scene files, separated by commas (default scenes/cornell-box.json)")->delimiter(',');
  benchCmd->add_option("--variants", bench->variants,
                       "kernel variants (default: all; wavepath devices lists them); NAME:spectral renders in the spectral mode")
      ->delimiter(',');
  benchCmd->add_option("--spp", bench->spp, "samples per pixel of each timed render (default 4)")->check(CLI::Range(1, 1 << 20));
  benchCmd->add_option("--repeats", bench->repeats, "timed renders per variant, after one warm-up (default 3)")->check(CLI::Range(1, 1000));
  benchCmd->add_option("--resolution", bench->resolution, "image size W H, overriding the scenes'")->expected(2)->check(CLI::Range(1, MAX_IMAGE_SIZE));
  benchCmd->add_option("--check-spp", bench->checkSpp, "samples per pixel of the correctness check (default 64)")->check(CLI::Range(1, 1 << 20));
  benchCmd->add_option("--plant-bias", bench->plantedBias, "debug: plant this bias in the variants' check renders")->check(CLI::Range(0.0, 100.0));
  benchCmd->add_option("--device", bench->device, "Vulkan device: index or part of the name");
  benchCmd->add_option("--out", bench->jsonPath, "write the results as JSON");
  benchCmd->add_option("--csv", bench->csvPath, "write the results as CSV");
  benchCmd->add_flag("--validation", bench->validation, "enable Vulkan validation; any message is a failure");
  CLI::Option* raycastFlag = benchCmd->add_flag("--raycast", bench->raycast,
                     "trace fixed ray sets (camera rays, then one bounce and one shadow ray from each hit) instead of rendering; "
                     "compared with Embree when built in");
  CLI::Option* buildFlag = benchCmd->add_flag(
      "--build", bench->build, "time BVH builds (the renderer's 8-wide tree, and the binary layout) instead of rendering; compared with Embree when built in");
  buildFlag->excludes(raycastFlag);
  CLI::Option* simtFlag = benchCmd->add_flag(
      "--simt", bench->simt,
      "replay the --raycast ray sets through a SIMT model of the walks (warps in lockstep, memory sectors, an L1) instead of timing; "
      "prints SIMD efficiency, sectors per warp iteration and a GPU's predicted rates");
  simtFlag->excludes(raycastFlag)->excludes(buildFlag);
  benchCmd->add_option("--warps", bench->warpWidths, "--simt: warp widths (default 32,64; 8: lavapipe's SIMD groups on AVX2)")
      ->delimiter(',')
      ->check(CLI::IsMember({8, 16, 32, 64}));
  benchCmd->add_option("--gpu-model", bench->gpuModel, "--simt: the GPU the prediction models (default h200)");
  benchCmd->add_option("--reorder", bench->reorders, "--simt: also model the bounce and shadow rays sorted by direction octant (octant) or octant and origin Morton code (morton)")
      ->delimiter(',')
      ->check(CLI::IsMember({"octant", "morton"}));
  benchCmd->add_option("--node-stride", bench->nodeStrideBytes,
                       "--simt: also model each variant with its wide nodes, or binary pairs of sibling nodes, this many bytes apart (128: one a cache line), a layout not built")
      ->check(CLI::Range(16u, 4096u));
  benchCmd->add_option("--measured", bench->measuredPath, "--simt: a GPU's bench --raycast --out JSON, printed beside the prediction");

  return {benchCmd, [bench] {
            if (bench->scenes.empty()) bench->scenes.push_back("scenes/cornell-box.json");
            if (bench->variants.empty() && bench->simt) bench->variants = simt_variants();
            if (bench->variants.empty())
              for (const KernelVariant& v : kernel_variants()) bench->variants.push_back(v.name);
            for (const std::string* path : {&bench->jsonPath, &bench->csvPath})
              if (!path->empty()) require_output_directory(*path);
            if (bench->build) return run_build_bench(*bench);
            if (bench->simt) return run_simt_bench(*bench);
            return bench->raycast ? run_raycast_bench(*bench) : run_bench(*bench);
          }};
}

}  // namespace wp::cli
