// `wavepath convergence`: RMSE against a high-sample reference per sample
// count, for the independent and the CMJ sampler.
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/render_args.h"
#include "cpu/reference.h"
#include "util/error.h"
#include "util/progress.h"

namespace wp::cli {

namespace {

// Convergence of the camera samplers: RMSE against a high-sample reference
// at 1, 2, 4, ... samples per pixel, for the independent and the CMJ sampler.
// Renders with the CPU reference (the kernels' own code, and faster than
// lavapipe); one CSV row per sampler and sample count.
struct ConvergenceArgs {
  RenderArgs render;
  int maxSpp = 256;
  int referenceSpp = 4096;
  std::string csv;
};

int run_convergence(const ConvergenceArgs& c) {
  if (!c.csv.empty()) require_output_directory(c.csv);
  Scene scene = load_scene_with_overrides(c.render);
  Progress quiet("", 0, false);
  RenderOptions ro = options_from(c.render, 1000);
  ro.spp = c.referenceSpp;
  ro.sampler = SamplerKind::Independent;
  ImageStats reference = render_cpu(compile_scene(scene, reference_options(ro)), c.render.threads, quiet);
  std::string rows = "sampler,spp,rmse\n";
  std::printf("%-12s %6s %12s\n", "sampler", "spp", "RMSE");
  for (SamplerKind sampler : {SamplerKind::Independent, SamplerKind::Cmj}) {
    const char* name = sampler == SamplerKind::Cmj ? "cmj" : "independent";
    for (int spp = 1; spp <= c.maxSpp; spp *= 2) {
      RenderOptions o = options_from(c.render, 1);
      o.spp = spp;
      o.sampler = sampler;
      ImageStats img = render_cpu(compile_scene(scene, reference_options(o)), c.render.threads, quiet);
      double se = 0.0;
      for (size_t p = 0; p < img.pixels(); ++p) {
        glm::dvec3 d = img.mean(p) - reference.mean(p);
        se += glm::dot(d, d);
      }
      double rmse = std::sqrt(se / (3.0 * double(img.pixels())));
      std::printf("%-12s %6d %12.6g\n", name, spp, rmse);
      rows += std::string(name) + "," + std::to_string(spp) + "," + std::to_string(rmse) + "\n";
    }
  }
  if (!c.csv.empty()) {
    FILE* f = std::fopen(c.csv.c_str(), "w");
    if (!f || std::fputs(rows.c_str(), f) < 0 || std::fclose(f) != 0) throw InputError(c.csv + ": cannot write");
  }
  return 0;
}

}  // namespace

Command add_convergence(CLI::App& app) {
  auto conv = std::make_shared<ConvergenceArgs>();
  CLI::App* convergence = app.add_subcommand(
      "convergence", "RMSE against a high-sample reference at 1, 2, 4, ... spp, independent vs cmj sampler (CPU reference)");
  convergence->add_option("scene", conv->render.scene, "scene file (darts JSON, glTF 2.0)")->required();
  convergence->add_option("--max-spp", conv->maxSpp, "largest sample count (default 256)")->check(CLI::Range(1, 1 << 16));
  convergence->add_option("--reference-spp", conv->referenceSpp, "samples of the reference (default 4096)")->check(CLI::Range(1, 1 << 20));
  convergence->add_option("--integrator", conv->render.integrator, "integrator, overriding the scene's (darts name)");
  convergence->add_option("--max-bounces", conv->render.maxBounces, "maximum scattering events per path")->check(CLI::Range(0, 1024));
  convergence->add_option("-r,--resolution", conv->render.resolution, "image size W H, overriding the scene's")->expected(2)->check(CLI::Range(1, MAX_IMAGE_SIZE));
  convergence->add_option("--csv", conv->csv, "write sampler,spp,rmse rows (scripts/plot_convergence.py draws them)");
  convergence->add_option("-t,--threads", conv->render.threads, "CPU threads (default: all cores)")->check(CLI::Range(0, 1024));

  return {convergence, [conv] { return run_convergence(*conv); }};
}

}  // namespace wp::cli
