// `wavepath bench`: kernel variants on full renders, each checked against
// the CPU reference before it is timed.
#include "bench/bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "bench/bench_support.h"
#include "bench/embree_baseline.h"
#include "bvh/wide_bvh.h"
#include "cpu/reference.h"
#include "gpu/wavefront.h"
#include "render/compiled_scene.h"
#include "scene/load_scene.h"
#include "stats/compare.h"
#include "util/error.h"

namespace wp {

using namespace bench;

namespace {

// What one variant's scene compiles to: its BVH layout decides these.
struct BvhFigures {
  double buildSeconds = 0.0, sahCost = 0.0, bytesPerPrimitive = 0.0;
  int depth = 0;
};

BvhFigures bvh_figures(const CompiledScene& cs, size_t primitives) {
  return BvhFigures{cs.bvhBuildSeconds, cs.bvh_sah_cost(), primitives ? double(cs.gpu_bytes()) / double(primitives) : 0.0,
                    cs.bvhDepth};
}

struct VariantResult {
  std::string variant;
  BvhFigures bvh;
  bool checked = false;
  std::string check;  // the comparison summary
  Spread seconds;
  Spread samplesPerSecond;
  Spread stageSeconds[StageTimes::kStages];
  uint64_t closestHitRays = 0, shadowRays = 0;  // per render
  Spread closestHitRaysPerSecond, shadowRaysPerSecond;  // in extend / connect; 0 for the megakernel
  // Warm-up and timed renders redone one ray per invocation, the renderer
  // keeping one from then on (WavefrontRenderer::one_ray_reruns): not 0
  // means the times are not those of the variant's own kernels.
  uint64_t oneRayReruns = 0;
};

struct SceneResult {
  std::string scene;
  size_t primitives = 0;
  int width = 0, height = 0, spp = 0, maxBounces = 0;
  std::vector<VariantResult> variants;
};

// A timed renderer: a kernel variant, in RGB or (a name ending in
// ":spectral") in the spectral mode, so that one run times both modes
// interleaved (the spectral mode's cost, docs/benchmarks.md).
struct BenchVariant {
  const KernelVariant* kernel;
  bool spectral;
  std::string label;
};

BenchVariant bench_variant(const std::string& name) {
  const size_t colon = name.find(':');
  if (colon != std::string::npos && name.substr(colon) != ":spectral")
    throw InputError("--variants: \"" + name + "\": a variant may end in :spectral, nothing else");
  return BenchVariant{&kernel_variant(name.substr(0, colon)), colon != std::string::npos, name};
}

}  // namespace

int run_bench(const BenchOptions& o) {
  std::vector<BenchVariant> variants;
  for (const std::string& name : o.variants) variants.push_back(bench_variant(name));
  std::vector<Scene> scenes;
  for (const std::string& path : o.scenes) scenes.push_back(load_scene(path));  // all input errors before any work

  VulkanContext ctx(o.device, o.validation || VulkanContext::validation_requested_by_environment());
  Progress quiet("", 0, false);
  std::vector<SceneResult> results;
  bool allChecked = true;
  for (size_t si = 0; si < scenes.size(); ++si) {
    Scene scene = with_resolution(scenes[si], o);
    RenderOptions timed;
    timed.spp = o.spp;
    SceneResult sr;
    sr.scene = o.scenes[si];
    sr.primitives = scene.triangles.size() + scene.spheres.size();

    // The reference image for the correctness checks: small, many samples.
    Scene small = scene;
    small.camera.width = small.camera.height = o.checkSize;
    RenderOptions ref;
    ref.spp = o.checkSpp;
    ref.seed = 1;
    // One reference a colour mode, rendered where a variant needs it.
    std::map<bool, ImageStats> references;
    auto reference_of = [&](bool spectral) -> const ImageStats& {
      if (!references.count(spectral)) {
        RenderOptions r = ref;
        r.spectral = spectral;
        references.emplace(spectral, render_cpu(compile_scene(small, reference_options(r)), 0, quiet));
      }
      return references.at(spectral);
    };

    // Check every variant first; keep a renderer (scene uploaded, pipelines
    // built, warmed up) for each that agrees.
    struct Timed {
      size_t result;  // index into sr.variants
      std::unique_ptr<CompiledScene> scene;
      std::unique_ptr<WavefrontRenderer> renderer;
      std::vector<double> seconds, rates, stages[StageTimes::kStages], closestRates, shadowRates;
    };
    std::vector<Timed> timedVariants;
    for (const BenchVariant& bv : variants) {
      const KernelVariant* v = bv.kernel;
      VariantResult vr;
      vr.variant = bv.label;
      RenderOptions mode = timed;
      mode.spectral = bv.spectral;
      auto cs = std::make_unique<CompiledScene>(compile_scene(scene, variant_options(mode, v->name)));
      vr.bvh = bvh_figures(*cs, sr.primitives);
      sr.width = cs->width;
      sr.height = cs->height;
      sr.spp = cs->spp;
      sr.maxBounces = int(cs->params.image.z);
      RenderOptions check = ref;
      check.seed = 2;
      check.spectral = bv.spectral;
      {
        WavefrontRenderer checker(ctx, compile_scene(small, variant_options(check, v->name)), v->settings);
        ImageStats checked = checker.render(quiet);
        if (o.plantedBias != 1.0f) plant_bias(checked, o.plantedBias);
        CompareResult c = compare_images(checked, reference_of(bv.spectral));
        vr.checked = c.passed();
        vr.check = c.summary();
      }
      sr.variants.push_back(vr);
      if (!vr.checked) {
        allChecked = false;
        std::fprintf(stderr, "wavepath: %s on %s disagrees with the CPU reference; not timed:\n  %s\n", bv.label.c_str(),
                     sr.scene.c_str(), vr.check.c_str());
        continue;
      }
      auto renderer = std::make_unique<WavefrontRenderer>(ctx, *cs, v->settings);
      renderer->render(quiet);  // warm-up: pipeline JIT, caches
      timedVariants.push_back(Timed{sr.variants.size() - 1, std::move(cs), std::move(renderer), {}, {}, {}, {}, {}});
    }
    // Timed renders, the variants interleaved within each repeat, so that a
    // change in the machine's speed during the run affects all of them alike.
    for (int r = 0; r < o.repeats; ++r) {
      for (Timed& t : timedVariants) {
        auto t0 = std::chrono::steady_clock::now();
        t.renderer->render(quiet);
        double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        t.seconds.push_back(sec);
        t.rates.push_back(double(t.scene->width) * t.scene->height * t.scene->spp / sec);
        const StageTimes& st = t.renderer->stage_times();
        for (int k = 0; k < StageTimes::kStages; ++k) t.stages[k].push_back(st.seconds[k]);
        t.closestRates.push_back(st.closest_hit_rays_per_second());
        t.shadowRates.push_back(st.shadow_rays_per_second());
        sr.variants[t.result].closestHitRays = st.closestHitRays;
        sr.variants[t.result].shadowRays = st.shadowRays;
      }
    }
    for (Timed& t : timedVariants) {
      VariantResult& vr = sr.variants[t.result];
      vr.seconds = spread(t.seconds);
      vr.samplesPerSecond = spread(t.rates);
      for (int k = 0; k < StageTimes::kStages; ++k) vr.stageSeconds[k] = spread(t.stages[k]);
      vr.closestHitRaysPerSecond = spread(t.closestRates);
      vr.shadowRaysPerSecond = spread(t.shadowRates);
      vr.oneRayReruns = t.renderer->one_ray_reruns();
    }
    results.push_back(sr);
  }
  if (ctx.validation_messages() > 0) throw RenderError(std::to_string(ctx.validation_messages()) + " Vulkan validation message(s)");

  // The table.
  std::printf("device: %s (%s)\n", ctx.info().name.c_str(), ctx.info().driver.c_str());
  for (const SceneResult& sr : results) {
    std::printf("\n%s: %zu primitives, %dx%d, %d spp, %d bounces\n", sr.scene.c_str(), sr.primitives, sr.width, sr.height,
                sr.spp, sr.maxBounces);
    std::printf("  %-14s %-6s %9s %17s %9s %9s %9s %9s %10s %10s %9s %7s %6s\n", "variant", "check", "time s", "Msamples/s",
                "extend s", "sort s", "shade s", "connect s", "CH Mrays/s", "SH Mrays/s", "BVH s", "SAH", "B/prim");
    for (const VariantResult& v : sr.variants) {
      if (!v.checked) {
        std::printf("  %-14s %-6s (disagrees with the CPU reference: not timed)\n", v.variant.c_str(), "FAIL");
        continue;
      }
      // Ray rates need the stage that traced them: "-" for the megakernel.
      auto rate = [](const Spread& s) { return s.median > 0.0 ? format_number(s.median * 1e-6, 2) : std::string("-"); };
      std::printf("  %-14s %-6s %9.3f %6.3f (%.3f-%.3f) %9.3f %9.3f %9.3f %9.3f %10s %10s %9.3f %7.2f %6.1f\n", v.variant.c_str(), "pass",
                  v.seconds.median, v.samplesPerSecond.median * 1e-6, v.samplesPerSecond.min * 1e-6,
                  v.samplesPerSecond.max * 1e-6, v.stageSeconds[StageTimes::kExtend].median,
                  v.stageSeconds[StageTimes::kSort].median, v.stageSeconds[StageTimes::kShade].median,
                  v.stageSeconds[StageTimes::kConnect].median, rate(v.closestHitRaysPerSecond).c_str(),
                  rate(v.shadowRaysPerSecond).c_str(), v.bvh.buildSeconds, v.bvh.sahCost, v.bvh.bytesPerPrimitive);
      if (v.oneRayReruns > 0) print_one_ray_note(v.variant, v.oneRayReruns);
    }
  }

  {
    nlohmann::json j;
    j["device"] = {{"name", ctx.info().name}, {"driver", ctx.info().driver}, {"type", ctx.info().type}};
    j["settings"] = {{"spp", o.spp}, {"repeats", o.repeats}, {"check_size", o.checkSize}, {"check_spp", o.checkSpp}};
    for (const SceneResult& sr : results) {
      nlohmann::json js = {{"scene", sr.scene}, {"primitives", sr.primitives}, {"width", sr.width},
                           {"height", sr.height}, {"spp", sr.spp},               {"max_bounces", sr.maxBounces}};
      for (const VariantResult& v : sr.variants) {
        nlohmann::json jv = {{"variant", v.variant},
                             {"check_passed", v.checked},
                             {"check", v.check},
                             {"bvh_build_seconds", v.bvh.buildSeconds},
                             {"bvh_depth", v.bvh.depth},
                             {"sah_cost", v.bvh.sahCost},
                             {"gpu_bytes_per_primitive", v.bvh.bytesPerPrimitive}};
        if (v.checked) {
          jv["seconds"] = to_json(v.seconds);
          jv["samples_per_second"] = to_json(v.samplesPerSecond);
          for (int k = 0; k < StageTimes::kStages; ++k) jv["stage_seconds"][StageTimes::kNames[k]] = to_json(v.stageSeconds[k]);
          jv["closest_hit_rays"] = v.closestHitRays;
          jv["shadow_rays"] = v.shadowRays;
          jv["one_ray_reruns"] = v.oneRayReruns;
          // Per second of the tracing stage's GPU time; null for the megakernel.
          auto rate = [](const Spread& s) {
            return s.median > 0.0 ? to_json(Spread{s.median * 1e-6, s.min * 1e-6, s.max * 1e-6}) : nlohmann::json();
          };
          jv["closest_hit_mrays_per_second"] = rate(v.closestHitRaysPerSecond);
          jv["shadow_mrays_per_second"] = rate(v.shadowRaysPerSecond);
        }
        js["variants"].push_back(jv);
      }
      j["scenes"].push_back(js);
    }
    if (!o.jsonPath.empty()) write_json(o.jsonPath, j);
    if (o.results) *o.results = j.dump();
  }
  if (!o.csvPath.empty()) {
    std::ofstream out(o.csvPath);
    out << "scene,variant,check_passed,seconds_median,seconds_min,seconds_max,samples_per_second_median";
    for (const char* name : StageTimes::kNames) out << "," << name << "_seconds_median";
    out << ",closest_hit_rays,shadow_rays,closest_hit_mrays_per_second_median,shadow_mrays_per_second_median";
    out << ",bvh_build_seconds,sah_cost,gpu_bytes_per_primitive\n";
    for (const SceneResult& sr : results) {
      for (const VariantResult& v : sr.variants) {
        out << csv_field(sr.scene) << "," << csv_field(v.variant) << "," << (v.checked ? 1 : 0) << "," << v.seconds.median << "," << v.seconds.min
            << "," << v.seconds.max << "," << v.samplesPerSecond.median;
        for (const Spread& s : v.stageSeconds) out << "," << s.median;
        out << "," << v.closestHitRays << "," << v.shadowRays << "," << v.closestHitRaysPerSecond.median * 1e-6 << ","
            << v.shadowRaysPerSecond.median * 1e-6;
        out << "," << v.bvh.buildSeconds << "," << v.bvh.sahCost << "," << v.bvh.bytesPerPrimitive << "\n";
      }
    }
    if (!out) throw InputError(o.csvPath + ": cannot write the results");
  }
  return allChecked ? 0 : 1;
}


}  // namespace wp
