#include "bench/bench.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

#include "cpu/reference.h"
#include "gpu/wavefront.h"
#include "render/compiled_scene.h"
#include "scene/load_scene.h"
#include "stats/compare.h"
#include "util/error.h"

namespace wp {

namespace {

struct Spread {
  double median = 0.0, min = 0.0, max = 0.0;
};

Spread spread(std::vector<double> v) {
  Spread s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  s.min = v.front();
  s.max = v.back();
  return s;
}

nlohmann::json to_json(const Spread& s) {
  return {{"median", s.median}, {"min", s.min}, {"max", s.max}};
}

struct VariantResult {
  std::string variant;
  bool checked = false;
  std::string check;  // the comparison summary
  Spread seconds;
  Spread samplesPerSecond;
  Spread stageSeconds[StageTimes::kStages];
};

struct SceneResult {
  std::string scene;
  size_t primitives = 0;
  int width = 0, height = 0, spp = 0, maxBounces = 0;
  double bvhBuildSeconds = 0.0, sahCost = 0.0, bytesPerPrimitive = 0.0;
  std::vector<VariantResult> variants;
};

}  // namespace

int run_bench(const BenchOptions& o) {
  std::vector<const KernelVariant*> variants;
  for (const std::string& name : o.variants) variants.push_back(&kernel_variant(name));
  std::vector<Scene> scenes;
  for (const std::string& path : o.scenes) scenes.push_back(load_scene(path));  // all input errors before any work

  VulkanContext ctx(o.device, o.validation || VulkanContext::validation_requested_by_environment());
  Progress quiet("", 0, false);
  std::vector<SceneResult> results;
  bool allChecked = true;
  for (size_t si = 0; si < scenes.size(); ++si) {
    Scene scene = scenes[si];
    if (!o.resolution.empty()) {
      scene.camera.width = o.resolution[0];
      scene.camera.height = o.resolution[1];
    }
    RenderOptions timed;
    timed.spp = o.spp;
    CompiledScene cs = compile_scene(scene, timed);
    SceneResult sr;
    sr.scene = o.scenes[si];
    sr.primitives = scene.triangles.size() + scene.spheres.size();
    sr.width = cs.width;
    sr.height = cs.height;
    sr.spp = cs.spp;
    sr.maxBounces = int(cs.params.image.z);
    sr.bvhBuildSeconds = cs.bvhBuildSeconds;
    sr.sahCost = cs.bvhSahCost;
    sr.bytesPerPrimitive = sr.primitives ? double(cs.gpu_bytes()) / double(sr.primitives) : 0.0;

    // The reference image for the correctness checks: small, many samples.
    Scene small = scene;
    small.camera.width = small.camera.height = o.checkSize;
    RenderOptions ref;
    ref.spp = o.checkSpp;
    ref.seed = 1;
    ImageStats reference = render_cpu(compile_scene(small, ref), 0, quiet);

    for (const KernelVariant* v : variants) {
      VariantResult vr;
      vr.variant = v->name;
      RenderOptions check = ref;
      check.seed = 2;
      check.plantedBias = o.plantedBias;
      {
        WavefrontRenderer checker(ctx, compile_scene(small, check), v->settings);
        CompareResult c = compare_images(checker.render(quiet), reference);
        vr.checked = c.passed();
        vr.check = c.summary();
      }
      if (!vr.checked) {
        allChecked = false;
        std::fprintf(stderr, "wavepath: %s on %s disagrees with the CPU reference; not timed:\n  %s\n", v->name.c_str(),
                     sr.scene.c_str(), vr.check.c_str());
        sr.variants.push_back(vr);
        continue;
      }
      WavefrontRenderer renderer(ctx, cs, v->settings);
      renderer.render(quiet);  // warm-up: pipeline JIT, caches
      std::vector<double> seconds, rates, stages[StageTimes::kStages];
      for (int r = 0; r < o.repeats; ++r) {
        auto t0 = std::chrono::steady_clock::now();
        renderer.render(quiet);
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        seconds.push_back(s);
        rates.push_back(double(cs.width) * cs.height * cs.spp / s);
        for (int k = 0; k < StageTimes::kStages; ++k) stages[k].push_back(renderer.stage_times().seconds[k]);
      }
      vr.seconds = spread(seconds);
      vr.samplesPerSecond = spread(rates);
      for (int k = 0; k < StageTimes::kStages; ++k) vr.stageSeconds[k] = spread(stages[k]);
      sr.variants.push_back(vr);
    }
    results.push_back(sr);
  }
  if (ctx.validation_messages() > 0) throw RenderError(std::to_string(ctx.validation_messages()) + " Vulkan validation message(s)");

  // The table.
  std::printf("device: %s (%s)\n", ctx.info().name.c_str(), ctx.info().driver.c_str());
  for (const SceneResult& sr : results) {
    std::printf("\n%s: %zu primitives, %dx%d, %d spp, %d bounces; BVH %.3f s, SAH cost %.2f, %.1f bytes/primitive\n",
                sr.scene.c_str(), sr.primitives, sr.width, sr.height, sr.spp, sr.maxBounces, sr.bvhBuildSeconds, sr.sahCost,
                sr.bytesPerPrimitive);
    std::printf("  %-10s %-6s %9s %17s %9s %9s %9s\n", "variant", "check", "time s", "Msamples/s", "extend s", "shade s",
                "connect s");
    for (const VariantResult& v : sr.variants) {
      if (!v.checked) {
        std::printf("  %-10s %-6s (disagrees with the CPU reference: not timed)\n", v.variant.c_str(), "FAIL");
        continue;
      }
      std::printf("  %-10s %-6s %9.3f %6.3f (%.3f-%.3f) %9.3f %9.3f %9.3f\n", v.variant.c_str(), "pass", v.seconds.median,
                  v.samplesPerSecond.median * 1e-6, v.samplesPerSecond.min * 1e-6, v.samplesPerSecond.max * 1e-6,
                  v.stageSeconds[2].median, v.stageSeconds[3].median, v.stageSeconds[4].median);
    }
  }

  if (!o.jsonPath.empty()) {
    nlohmann::json j;
    j["device"] = {{"name", ctx.info().name}, {"driver", ctx.info().driver}, {"type", ctx.info().type}};
    j["settings"] = {{"spp", o.spp}, {"repeats", o.repeats}, {"check_size", o.checkSize}, {"check_spp", o.checkSpp}};
    for (const SceneResult& sr : results) {
      nlohmann::json js = {{"scene", sr.scene},           {"primitives", sr.primitives},
                           {"width", sr.width},           {"height", sr.height},
                           {"spp", sr.spp},               {"max_bounces", sr.maxBounces},
                           {"bvh_build_seconds", sr.bvhBuildSeconds}, {"sah_cost", sr.sahCost},
                           {"gpu_bytes_per_primitive", sr.bytesPerPrimitive}};
      for (const VariantResult& v : sr.variants) {
        nlohmann::json jv = {{"variant", v.variant}, {"check_passed", v.checked}, {"check", v.check}};
        if (v.checked) {
          jv["seconds"] = to_json(v.seconds);
          jv["samples_per_second"] = to_json(v.samplesPerSecond);
          for (int k = 0; k < StageTimes::kStages; ++k) jv["stage_seconds"][StageTimes::kNames[k]] = to_json(v.stageSeconds[k]);
        }
        js["variants"].push_back(jv);
      }
      j["scenes"].push_back(js);
    }
    std::ofstream out(o.jsonPath);
    out << j.dump(2) << "\n";
    if (!out) throw InputError(o.jsonPath + ": cannot write the results");
  }
  if (!o.csvPath.empty()) {
    std::ofstream out(o.csvPath);
    out << "scene,variant,check_passed,seconds_median,seconds_min,seconds_max,samples_per_second_median";
    for (const char* name : StageTimes::kNames) out << "," << name << "_seconds_median";
    out << ",bvh_build_seconds,sah_cost,gpu_bytes_per_primitive\n";
    for (const SceneResult& sr : results) {
      for (const VariantResult& v : sr.variants) {
        out << sr.scene << "," << v.variant << "," << (v.checked ? 1 : 0) << "," << v.seconds.median << "," << v.seconds.min
            << "," << v.seconds.max << "," << v.samplesPerSecond.median;
        for (const Spread& s : v.stageSeconds) out << "," << s.median;
        out << "," << sr.bvhBuildSeconds << "," << sr.sahCost << "," << sr.bytesPerPrimitive << "\n";
      }
    }
    if (!out) throw InputError(o.csvPath + ": cannot write the results");
  }
  return allChecked ? 0 : 1;
}

}  // namespace wp
