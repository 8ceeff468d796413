// `wavepath bench --raycast`: fixed ray sets traced by each variant, checked
// against the CPU traversal, next to Embree.
#include "bench/bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "bench/bench_support.h"
#include "bench/embree_baseline.h"
#include "bench/ray_sets.h"
#include "bvh/wide_bvh.h"
#include "cpu/reference.h"
#include "gpu/wavefront.h"
#include "render/compiled_scene.h"
#include "render/shader_cpp.h"
#include "scene/load_scene.h"
#include "stats/compare.h"
#include "util/error.h"

namespace wp {

using namespace bench;

namespace {

// A ray's result as the benchmark compares it: the closest hit's distance,
// or for shadow rays (any hit) 1 where the segment is blocked; WP_INF for a
// miss.
float hit_distance(const shader::Hit& h, bool anyHit) {
  if (h.prim == WP_INVALID) return WP_INF;
  return anyHit ? 1.0f : h.t;
}

// Results by the CPU traversal (proven equal to brute force by the BVH
// tests): the reference the GPU's hits are checked against.
std::vector<float> cpu_hits(shader::SceneView& view, const std::vector<shader::ShadowRay>& rays, bool anyHit) {
  std::vector<float> t(rays.size(), WP_INF);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      shader::Hit h;
      view.trace_ray(rays[i].origin, rays[i].dir, rays[i].tmax, anyHit, h);
      t[i] = hit_distance(h, anyHit);
    }
  });
  return t;
}

// Mean iterations of the CPU traversal's walk per ray through cs's tree: the
// loop the kernels run (scene.glsl), so a measure of the tree's quality for
// these rays that, unlike a time, is the same in every run.
double walk_steps_per_ray(const CompiledScene& cs, const std::vector<shader::ShadowRay>& rays, bool anyHit) {
  const shader::SceneView view = cs.view();
  const uint64_t total = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, rays.size(), 1024), uint64_t(0),
      [&](const tbb::blocked_range<size_t>& r, uint64_t acc) {
        shader::SceneView counting = view;
        uint64_t steps = 0;
        counting.stepsTaken = &steps;
        for (size_t i = r.begin(); i != r.end(); ++i) {
          shader::Hit h;
          counting.trace_ray(rays[i].origin, rays[i].dir, rays[i].tmax, anyHit, h);
        }
        return acc + steps;
      },
      std::plus<uint64_t>());
  return rays.empty() ? 0.0 : double(total) / double(rays.size());
}

// Rays whose distances differ between two traversals beyond rounding: a
// few ulps of t, and (for hits inside instances, found with the origin taken
// into the instance's space) a few ulps of the origin's largest coordinate,
// however short t is.
size_t mismatches(const std::vector<float>& a, const std::vector<float>& b, const std::vector<shader::ShadowRay>& rays) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    bool hitA = a[i] != WP_INF, hitB = b[i] != WP_INF;
    const glm::vec3 o = glm::abs(rays[i].origin);
    const float tolerance = 1e-4f * b[i] + 1e-6f + 2e-6f * std::max({o.x, o.y, o.z}) / glm::length(rays[i].dir);
    if (hitA != hitB || (hitA && std::fabs(a[i] - b[i]) > tolerance)) ++n;
  }
  return n;
}

}  // namespace

int run_raycast_bench(const BenchOptions& o) {
  std::vector<const KernelVariant*> variants;
  for (const std::string& name : o.variants) variants.push_back(&kernel_variant(name));
  std::vector<Scene> scenes;
  for (const std::string& path : o.scenes) scenes.push_back(load_scene(path));

  VulkanContext ctx(o.device, o.validation || VulkanContext::validation_requested_by_environment());
  nlohmann::json results = nlohmann::json::array();
  bool allChecked = true;
  std::printf("device: %s (%s); Embree baseline: %s\n", ctx.info().name.c_str(), ctx.info().driver.c_str(),
              embree_available() ? "yes, all cores" : "not built in");
  for (size_t si = 0; si < scenes.size(); ++si) {
    Scene scene = with_resolution(scenes[si], o);
    // Rays and reference hits come from the CPU reference's tree: faster on a
    // CPU, and a different tree from the ones the variants trace.
    CompiledScene cs = compile_scene(scene, reference_options(RenderOptions{}));
    shader::SceneView view = cs.view();
    RaySets sets = make_rays(cs);
    std::vector<CompiledScene> variantScenes;  // each variant traces its own BVH layout
    for (const KernelVariant* v : variants) variantScenes.push_back(compile_scene(scene, variant_options(RenderOptions{}, v->name)));
    std::unique_ptr<EmbreeScene> embree;
    std::string embreeNote;
    if (embree_available()) {
      try {
        embree = std::make_unique<EmbreeScene>(scene);
      } catch (const RenderError& e) {
        embreeNote = e.what();
      }
    }
    const std::string placed = cs.instancing.instances == 0 ? std::string()
                               : " and " + std::to_string(cs.instancing.instances) + " instances placing " +
                                     std::to_string(cs.instancing.instancedTriangles) + " triangles";
    std::printf("\n%s: %zu primitives%s, %zu primary, %zu bounce and %zu shadow rays; BVH %.3f s%s\n", o.scenes[si].c_str(),
                scene.triangles.size() + scene.spheres.size(), placed.c_str(), sets.primary.size(), sets.bounce.size(), sets.shadow.size(),
                cs.bvhBuildSeconds,
                embree ? (", Embree build " + std::to_string(embree->build_seconds()) + " s").c_str() : "");
    if (!embreeNote.empty()) std::printf("  Embree: %s\n", embreeNote.c_str());
    std::printf("  %-8s %-14s %12s %14s %8s %13s %11s\n", "rays", "variant", "Mrays/s", "Embree Mrays/s", "ratio",
                "per repeat", "walk steps");
    using RaySet = std::pair<const char*, const std::vector<shader::ShadowRay>*>;
    for (const RaySet& set : {RaySet{"primary", &sets.primary}, RaySet{"bounce", &sets.bounce}, RaySet{"shadow", &sets.shadow}}) {
      // Named variables, not a structured binding: the lambdas below capture
      // them, which C++17 allows only for variables (GCC accepts it, Clang not).
      const char* setName = set.first;
      const std::vector<shader::ShadowRay>* rays = set.second;
      if (rays->empty()) continue;
      const bool anyHit = rays == &sets.shadow;  // shadow rays ask whether the segment is blocked
      std::vector<float> reference = rays == &sets.primary ? sets.primaryHits : cpu_hits(view, *rays, anyHit);
      // Check each variant's hits (the first cast is also its warm-up); keep
      // a renderer for each that agrees.
      struct Timed {
        size_t variant;
        std::unique_ptr<WavefrontRenderer> renderer;
        nlohmann::json row;
        std::vector<double> seconds;
      };
      std::vector<Timed> timedVariants;
      // Camera rays, and the shadow rays from their hits (in image order),
      // are passed as coherent; bounce rays are not (cast_rays).
      const bool coherent = rays != &sets.bounce;
      auto cast = [&](WavefrontRenderer& r, uint64_t* truncated, double* kernel) {
        return anyHit ? r.cast_shadow_rays(*rays, truncated, kernel, coherent) : r.cast_rays(*rays, truncated, kernel, coherent);
      };
      for (size_t vi = 0; vi < variants.size(); ++vi) {
        const KernelVariant* v = variants[vi];
        auto renderer = std::make_unique<WavefrontRenderer>(ctx, variantScenes[vi], v->settings);
        uint64_t truncated = 0;
        std::vector<shader::Hit> hits = cast(*renderer, &truncated, nullptr);
        std::vector<float> t(hits.size());
        for (size_t i = 0; i < hits.size(); ++i) t[i] = hit_distance(hits[i], anyHit);
        size_t bad = mismatches(t, reference, *rays);
        nlohmann::json row = {{"scene", o.scenes[si]}, {"rays", setName}, {"count", rays->size()}, {"variant", v->name},
                              {"mismatches", bad}, {"truncated", truncated}};
        // Rounding may flip a hit on an edge now and then; more is a bug.
        if (truncated > 0 || double(bad) > 1e-4 * double(rays->size())) {
          allChecked = false;
          row["check_passed"] = false;
          std::printf("  %-8s %-14s disagrees with the CPU traversal on %zu rays: not timed\n", setName, v->name.c_str(), bad);
          results.push_back(row);
          continue;
        }
        timedVariants.push_back(Timed{vi, std::move(renderer), row, {}});
      }
      // Embree and the variants interleaved within each repeat, so that a
      // change in the machine's speed during the run affects all of them alike.
      std::vector<double> embreeSeconds;
      std::vector<float> embreeHits;
      auto embree_trace = [&] {
        if (!anyHit) return embree->trace(*rays, &embreeHits);
        std::vector<uint8_t> blocked;
        const double seconds = embree->occluded(*rays, &blocked);
        embreeHits.resize(blocked.size());
        for (size_t i = 0; i < blocked.size(); ++i) embreeHits[i] = blocked[i] ? 1.0f : WP_INF;
        return seconds;
      };
      if (embree) embree_trace();  // warm-up
      // A GPU raises its clocks only after some work: each variant casts for
      // a while before it is timed, or the first ones are timed at idle
      // clocks (camera rays on the H200 measured 1.4 and 4.9 G/s in two
      // calls). lavapipe runs at the CPU's pace from the start.
      if (ctx.info().type != "cpu")
        for (Timed& t : timedVariants) {
          const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
          while (std::chrono::steady_clock::now() < until) cast(*t.renderer, nullptr, nullptr);
        }
      for (int r = 0; r < o.repeats; ++r) {
        if (embree) embreeSeconds.push_back(embree_trace());
        for (Timed& t : timedVariants) {
          double kernel = 0.0;
          cast(*t.renderer, nullptr, &kernel);
          t.seconds.push_back(kernel);
        }
      }
      const double embreeRate = embree ? double(rays->size()) / spread(embreeSeconds).median : 0.0;
      for (Timed& t : timedVariants) {
        const KernelVariant* v = variants[t.variant];
        double rate = double(rays->size()) / std::max(spread(t.seconds).median, 1e-12);
        nlohmann::json& row = t.row;
        row["check_passed"] = true;
        row["kernel_seconds"] = to_json(spread(t.seconds));
        row["mrays_per_second"] = rate * 1e-6;
        const double steps = walk_steps_per_ray(variantScenes[t.variant], *rays, anyHit);
        row["cpu_walk_steps_per_ray"] = steps;
        row["one_ray_reruns"] = t.renderer->one_ray_reruns();
        if (embree) {
          // Each repeat's ratio, from the Embree run beside it: on a machine
          // whose speed drifts, their spread shows how far the headline
          // ratio (of the medians) can be trusted.
          std::vector<double> paired(t.seconds.size());
          for (size_t r = 0; r < paired.size(); ++r) paired[r] = embreeSeconds[r] / std::max(t.seconds[r], 1e-12);
          const Spread pairedSpread = spread(paired);
          row["embree_mrays_per_second"] = embreeRate * 1e-6;
          row["ratio_to_embree"] = rate / embreeRate;
          row["ratio_to_embree_per_repeat"] = to_json(pairedSpread);
          row["embree_mismatches"] = mismatches(embreeHits, reference, *rays);
          char range[32];
          std::snprintf(range, sizeof range, "%.3f-%.3f", pairedSpread.min, pairedSpread.max);
          std::printf("  %-8s %-14s %12.2f %14.2f %8.3f %13s %11.2f\n", setName, v->name.c_str(), rate * 1e-6, embreeRate * 1e-6,
                      rate / embreeRate, range, steps);
        } else {
          std::printf("  %-8s %-14s %12.2f %14s %8s %13s %11.2f\n", setName, v->name.c_str(), rate * 1e-6, "-", "-", "-", steps);
        }
        if (t.renderer->one_ray_reruns() > 0) print_one_ray_note(v->name, t.renderer->one_ray_reruns());
        results.push_back(row);
      }
    }
  }
  if (ctx.validation_messages() > 0) throw RenderError(std::to_string(ctx.validation_messages()) + " Vulkan validation message(s)");
  const nlohmann::json j = {{"device", {{"name", ctx.info().name}, {"driver", ctx.info().driver}}},
                            {"embree", embree_available()}, {"repeats", o.repeats}, {"raycast", results}};
  if (!o.jsonPath.empty()) write_json(o.jsonPath, j);
  if (o.results) *o.results = j.dump();
  if (!o.csvPath.empty()) {
    std::ofstream out(o.csvPath);
    out << "scene,rays,count,variant,check_passed,mismatches,truncated,mrays_per_second,embree_mrays_per_second,ratio_to_embree,"
           "ratio_per_repeat_min,ratio_per_repeat_median,ratio_per_repeat_max,cpu_walk_steps_per_ray\n";
    // A variant that failed its check, or a run without Embree, leaves its
    // figures empty.
    auto field = [&out](const nlohmann::json& v) {
      out << ",";
      if (!v.is_null()) out << v;
    };
    const nlohmann::json none;
    for (const nlohmann::json& r : results) {
      out << csv_field(r["scene"].get<std::string>()) << "," << csv_field(r["rays"].get<std::string>()) << "," << r["count"] << ","
          << csv_field(r["variant"].get<std::string>()) << "," << (r["check_passed"].get<bool>() ? 1 : 0) << "," << r["mismatches"] << ","
          << r["truncated"];
      for (const char* key : {"mrays_per_second", "embree_mrays_per_second", "ratio_to_embree"}) field(r.value(key, none));
      const nlohmann::json paired = r.value("ratio_to_embree_per_repeat", none);
      for (const char* key : {"min", "median", "max"}) field(paired.is_null() ? none : paired[key]);
      field(r.value("cpu_walk_steps_per_ray", none));
      out << "\n";
    }
    if (!out) throw InputError(o.csvPath + ": cannot write the results");
  }
  return allChecked ? 0 : 1;
}

}  // namespace wp
