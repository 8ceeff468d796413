// `wavepath compare`: two renders of a scene (or two stored EXRs) and the
// statistical verdict on whether they estimate the same image.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/render_args.h"
#include "report/html_report.h"
#include "stats/compare.h"
#include "stats/reference_diff.h"
#include "util/error.h"

namespace wp::cli {

namespace {

struct CompareArgs {
  RenderArgs render;  // scene, spp, bounces, seed, device, threads, quiet, validation
  std::vector<std::string> images;
  std::string a = "gpu";
  std::string b = "cpu";
  std::string report;
  float plantBias = 1.0f;
  std::vector<uint32_t> plantRegion;
  std::string layer = "color";  // which layer to compare (AOVs: layers.glsl)
  CompareSettings settings;
  // --reference REF IMAGE: measured against a reference without variance.
  std::vector<std::string> reference;
  std::vector<double> tolerance{0.02, 0.1};
  std::string curve = "srgb";
  std::vector<int> excludeRows{0, 0};
  std::vector<int> mask;
};

// How far IMAGE is from REF; exit 0 when within both tolerances (the mean
// error and the median block error), 1 when beyond.
int run_reference(const CompareArgs& c) {
  const EightBitCurve curve = c.curve == "cs184" ? EightBitCurve::Cs184 : EightBitCurve::Srgb;
  const LinearImage ref = load_image_as_radiance(c.reference[0], curve), image = load_image_as_radiance(c.reference[1], curve);
  ReferenceDiffSettings s;
  s.excludeTop = c.excludeRows[0];
  s.excludeBottom = c.excludeRows[1];
  if (!c.mask.empty()) s.mask = glm::ivec4(c.mask[0], c.mask[1], c.mask[2], c.mask[3]);
  const std::optional<ImageFormat> format = image_format_of(c.reference[0]);
  const bool eightBit = format && *format != ImageFormat::Hdr && *format != ImageFormat::Pfm && *format != ImageFormat::Exr;
  if (eightBit) s.clipped = clip_radiance(curve);
  const ReferenceDiff d = diff_against_reference(image, ref, s);
  const bool within = d.meanError <= c.tolerance[0] && d.blockMedian <= c.tolerance[1];
  std::printf("%s: %s (tolerances: mean %.2f%%, median block %.2f%%)\n", within ? "WITHIN" : "BEYOND", d.summary().c_str(),
              100.0 * c.tolerance[0], 100.0 * c.tolerance[1]);
  return within ? 0 : 1;
}

// Renders the scene twice with independent seeds (or reads two EXR renders) and
// decides whether both estimate the same image. Exit 0: agree, 1: differ.
int run_compare(const CompareArgs& c) {
  ImageStats a, b;
  ReportLabels labels;
  if (!c.images.empty()) {
    a = read_exr(c.images[0]);
    b = read_exr(c.images[1]);
    labels = ReportLabels{c.images[0] + " vs " + c.images[1], c.images[0], c.images[1]};
  } else {
    for (const std::string& r : {c.a, c.b})
      if (r != "cpu") kernel_variant(r);  // fails early, naming the known variants
    Scene scene = load_scene_with_overrides(c.render);
    RenderOptions oa = options_from(c.render, c.render.seed), ob = options_from(c.render, c.render.seed + 1);
    std::string whereA, whereB;
    a = render_on(c.a, compile_scene(scene, variant_options(oa, c.a)), c.render, &whereA);
    if (c.plantBias != 1.0f) {
      const std::vector<uint32_t>& r = c.plantRegion;
      plant_bias(a, c.plantBias, r.empty() ? glm::uvec4(0u, 0u, ~0u, ~0u) : glm::uvec4(r[0], r[1], r[2], r[3]));
    }
    b = render_on(c.b, compile_scene(scene, variant_options(ob, c.b)), c.render, &whereB);
    auto label = [&](const std::string& r, const std::string& where, uint32_t seed, bool planted) {
      std::string l = r + " (" + where + "), seed " + std::to_string(seed);
      if (planted) {
        char factor[32];
        std::snprintf(factor, sizeof(factor), "%g", double(c.plantBias));
        l += std::string(", planted bias x") + factor;
      }
      return l;
    };
    labels = ReportLabels{c.render.scene, label(c.a, whereA, c.render.seed, c.plantBias != 1.0f),
                          label(c.b, whereB, c.render.seed + 1, false)};
  }
  if (c.layer != "color") {
    for (const auto& [image, name] : {std::pair<ImageStats*, std::string>{&a, "A"}, {&b, "B"}})
      if (!image->layer(c.layer)) throw InputError("image " + name + " has no \"" + c.layer + "\" layer (render it with --aov " + c.layer + ")");
    a = layer_as_color(a, c.layer);
    b = layer_as_color(b, c.layer);
  }
  CompareResult result = compare_images(a, b, c.settings);
  std::printf("%s\n", result.summary().c_str());
  if (!c.report.empty()) {
    write_html_report(c.report, a, b, result, labels);
    std::printf("report: %s/index.html\n", c.report.c_str());
  }
  return result.passed() ? 0 : 1;
}

}  // namespace

Command add_compare(CLI::App& app) {
  auto cmp = std::make_shared<CompareArgs>();
  CLI::App* compare = app.add_subcommand(
      "compare", "render a scene twice with independent seeds (default: GPU against the CPU reference), or read two EXR "
                 "renders, and decide statistically whether they estimate the same image. Exit 0: agree, 1: differ");
  compare->add_option("scene", cmp->render.scene, "scene file (darts JSON, glTF 2.0)");
  compare->add_option("--images", cmp->images, "compare two stored renders (EXR written by wavepath render) instead")->expected(2);
  compare->add_option("--a", cmp->a, "renderer of image A: cpu or a kernel variant such as gpu, gpu-mega (default gpu)");
  compare->add_option("--b", cmp->b, "renderer of image B: cpu or a kernel variant (default cpu)");
  compare->add_option("--spp", cmp->render.spp, "samples per pixel of each render")->check(CLI::Range(1, MAX_SAMPLES_PER_PIXEL));
  compare->add_option("--max-bounces", cmp->render.maxBounces, "maximum scattering events per path")->check(CLI::Range(0, 1024));
  compare->add_option("--integrator", cmp->render.integrator, "integrator, overriding the scene's (darts name)");
  compare->add_option("--seed", cmp->render.seed, "seed of A; B uses seed + 1 (default 1)")->default_val(1);
  compare->add_option("--resolution", cmp->render.resolution, "image size W H, overriding the scene's")->expected(2)->check(CLI::Range(1, MAX_IMAGE_SIZE));
  compare->add_option("--report", cmp->report, "write an HTML report to this directory");
  compare->add_option("--layer", cmp->layer, "the layer to compare: color (default) or an AOV layer, " + aov_layer_names() +
                                                 " (rendered with --aov)");
  compare->add_option("--aov", cmp->render.aovs, "AOV layers to render (with a scene): " + aov_layer_names())->delimiter(',');
  compare->add_option("--device", cmp->render.device, "Vulkan device: index or part of the name");
  compare->add_option("--threads", cmp->render.threads, "CPU threads for the CPU reference")->check(CLI::Range(0, 1024));
  compare->add_option("--plant-bias", cmp->plantBias, "debug: multiply A's radiance by this factor, to see what the test detects")
      ->check(CLI::Range(0.0, 100.0));
  compare->add_option("--plant-region", cmp->plantRegion, "debug: only inside pixels X0 Y0 X1 Y1 (exclusive ends)")->expected(4);
  compare->add_option("--alpha", cmp->settings.alpha,
                      "family-wise significance level of each test (default 0.01); checks of many images divide it among them")
      ->check(CLI::Range(1e-12, 0.5));
  compare->add_option("--reference", cmp->reference,
                      "REF IMAGE: measure IMAGE (a PNG, EXR, ...) against a reference image without variance (a course's "
                      "*-ref.png) instead; exit 0 when within --tolerance")
      ->expected(2);
  compare->add_option("--tolerance", cmp->tolerance,
                      "with --reference: the largest relative error of the whole mean and the largest median error of 16x16 "
                      "block means (default 0.02 0.1)")
      ->expected(2)
      ->check(CLI::Range(0.0, 1e6));
  compare->add_option("--curve", cmp->curve, "with --reference: how 8-bit images encode radiance, srgb (default) or cs184")
      ->check(CLI::IsMember({"srgb", "cs184"}));
  compare->add_option("--exclude-rows", cmp->excludeRows, "with --reference: leave out TOP and BOTTOM rows")->expected(2)->check(CLI::Range(0, MAX_IMAGE_SIZE));
  compare->add_option("--mask", cmp->mask, "with --reference: leave out pixels X0 Y0 X1 Y1 (exclusive ends; a watermark)")
      ->expected(4)
      ->check(CLI::Range(0, MAX_IMAGE_SIZE));
  compare->add_flag("-q,--quiet", cmp->render.quiet, "no progress line");
  compare->add_flag("--validation", cmp->render.validation, "enable Vulkan validation; any message is a failure");
  return {compare, [cmp] {
            const int modes = !cmp->render.scene.empty() + !cmp->images.empty() + !cmp->reference.empty();
            if (modes != 1) throw InputError("compare needs one of: a scene file, --images A.exr B.exr, --reference REF IMAGE");
            return cmp->reference.empty() ? run_compare(*cmp) : run_reference(*cmp);
          }};
}

}  // namespace wp::cli
