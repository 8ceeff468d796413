#include "bench/bench.h"

#include <nlohmann/json.hpp>

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

#include "bench/embree_baseline.h"
#include "bvh/wide_bvh.h"
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

Scene with_resolution(Scene scene, const BenchOptions& o) {
  if (!o.resolution.empty()) {
    scene.camera.width = o.resolution[0];
    scene.camera.height = o.resolution[1];
  }
  return scene;
}

std::string format_number(double x, int decimals) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, x);
  return buf;
}

nlohmann::json to_json(const Spread& s) {
  return {{"median", s.median}, {"min", s.min}, {"max", s.max}};
}

// A CSV field (RFC 4180): quoted, its quotes doubled, where it holds a
// comma, a quote or a line break (a scene's path may).
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

// Writes the results as JSON to `path`.
void write_json(const std::string& path, const nlohmann::json& j) {
  std::ofstream out(path);
  out << j.dump(2) << "\n";
  if (!out) throw InputError(path + ": cannot write the results");
}

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

// A variant's times include work redone one ray per invocation: say so
// under its row.
void print_one_ray_note(const std::string& variant, uint64_t reruns) {
  std::printf("  (%s: %llu dispatch(es) redone one ray per invocation, a ray having outrun its share of the loop budget;\n"
              "   its times are partly those of one ray per invocation)\n",
              variant.c_str(), (unsigned long long)reruns);
}

struct SceneResult {
  std::string scene;
  size_t primitives = 0;
  int width = 0, height = 0, spp = 0, maxBounces = 0;
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
    ImageStats reference = render_cpu(compile_scene(small, reference_options(ref)), 0, quiet);

    // Check every variant first; keep a renderer (scene uploaded, pipelines
    // built, warmed up) for each that agrees.
    struct Timed {
      size_t result;  // index into sr.variants
      std::unique_ptr<CompiledScene> scene;
      std::unique_ptr<WavefrontRenderer> renderer;
      std::vector<double> seconds, rates, stages[StageTimes::kStages], closestRates, shadowRates;
    };
    std::vector<Timed> timedVariants;
    for (const KernelVariant* v : variants) {
      VariantResult vr;
      vr.variant = v->name;
      auto cs = std::make_unique<CompiledScene>(compile_scene(scene, variant_options(timed, v->name)));
      vr.bvh = bvh_figures(*cs, sr.primitives);
      sr.width = cs->width;
      sr.height = cs->height;
      sr.spp = cs->spp;
      sr.maxBounces = int(cs->params.image.z);
      RenderOptions check = ref;
      check.seed = 2;
      {
        WavefrontRenderer checker(ctx, compile_scene(small, variant_options(check, v->name)), v->settings);
        ImageStats checked = checker.render(quiet);
        if (o.plantedBias != 1.0f) plant_bias(checked, o.plantedBias);
        CompareResult c = compare_images(checked, reference);
        vr.checked = c.passed();
        vr.check = c.summary();
      }
      sr.variants.push_back(vr);
      if (!vr.checked) {
        allChecked = false;
        std::fprintf(stderr, "wavepath: %s on %s disagrees with the CPU reference; not timed:\n  %s\n", v->name.c_str(),
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

  if (!o.jsonPath.empty()) {
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
    write_json(o.jsonPath, j);
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

// Rays whose hit (or miss) differs from the reference by more than rounding.
size_t mismatches(const std::vector<float>& a, const std::vector<float>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    bool hitA = a[i] != WP_INF, hitB = b[i] != WP_INF;
    if (hitA != hitB || (hitA && std::fabs(a[i] - b[i]) > 1e-4f * b[i] + 1e-6f)) ++n;
  }
  return n;
}

struct RaySets {
  std::vector<shader::ShadowRay> primary, bounce, shadow;
  std::vector<float> primaryHits;  // the CPU traversal's distances: the primary rays' reference
};

// Camera rays through every pixel, then from every hit one cosine-distributed
// bounce and one shadow ray to a point that next-event estimation picks on
// an emitter (where it lies above the surface), leaving the surface as the
// path tracer would.
RaySets make_rays(shader::SceneView& view, const CompiledScene& cs) {
  RaySets sets;
  size_t pixels = size_t(cs.width) * size_t(cs.height);
  sets.primary.resize(pixels);
  for (size_t p = 0; p < pixels; ++p) {
    shader::PathState ps;
    view.path_begin(ps, uint32_t(p), 0);
    sets.primary[p] = shader::ShadowRay{ps.origin, WP_INF, ps.dir, uint32_t(p), glm::vec3(0.0f), 0u};
  }
  std::vector<shader::Hit> hits(pixels);
  tbb::parallel_for(size_t(0), pixels, [&](size_t p) {
    view.trace_ray(sets.primary[p].origin, sets.primary[p].dir, sets.primary[p].tmax, false, hits[p]);
  });
  sets.primaryHits.assign(pixels, WP_INF);
  for (size_t p = 0; p < pixels; ++p) {
    if (hits[p].prim == WP_INVALID) continue;
    sets.primaryHits[p] = hits[p].t;
    const shader::ShadowRay& r = sets.primary[p];
    shader::SceneView::SurfaceHit s = view.surface_at(r.origin, r.dir, hits[p]);
    glm::vec3 n = glm::dot(s.ng, r.dir) < 0.0f ? s.ng : -s.ng;
    uint32_t rng = view.rng_seed(uint32_t(p), 1u, 7u);
    glm::vec3 t, b;
    view.make_frame(n, t, b);
    glm::vec3 d = view.frame_to_world(view.square_to_cosine_hemisphere(glm::vec2(view.rng_next(rng), view.rng_next(rng))), t, b, n);
    sets.bounce.push_back(shader::ShadowRay{view.offset_ray(s.p, n), WP_INF, d, uint32_t(p), glm::vec3(0.0f), 0u});
    shader::SceneView::LightSample ls;
    const glm::vec3 uLight(view.rng_next(rng), view.rng_next(rng), view.rng_next(rng));
    if (view.sample_emitter(s.p, uLight, ls) && ls.pdf > 0.0f && glm::dot(ls.wi, n) > 0.0f) {
      shader::ShadowRay sr{};
      sr.path = uint32_t(p);
      view.aim_shadow_ray(s.p, n, ls, sr.origin, sr.dir, sr.tmax);
      sets.shadow.push_back(sr);
    }
  }
  return sets;
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
    RaySets sets = make_rays(view, cs);
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
    std::printf("\n%s: %zu primitives, %zu primary, %zu bounce and %zu shadow rays; BVH %.3f s%s\n", o.scenes[si].c_str(),
                scene.triangles.size() + scene.spheres.size(), sets.primary.size(), sets.bounce.size(), sets.shadow.size(),
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
        size_t bad = mismatches(t, reference);
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
          row["embree_mismatches"] = mismatches(embreeHits, reference);
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
  if (!o.jsonPath.empty()) {
    nlohmann::json j = {{"device", {{"name", ctx.info().name}, {"driver", ctx.info().driver}}},
                        {"embree", embree_available()}, {"repeats", o.repeats}, {"raycast", results}};
    write_json(o.jsonPath, j);
  }
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

namespace {

// One round of a scene's builds: the default layout as compile_scene makes
// it (the primitives' bounds, then the binary tree collapsed into the 8-wide
// layout from the builder's arrays), the binary layout alone (gpu-bvh2 and
// the CPU reference: the tree laid out depth-first), the 8-wide layout
// collapsed greedily (gpu-greedy), and, for binned-SAH scenes, the 8-wide
// layout from the clustered SAH build (gpu-clustered).
struct TimedBuild {
  double bounds = 0.0, wide = 0.0, binary = 0.0, greedy = 0.0, clustered = 0.0;
  double collapse = 0.0;  // the part of `wide` that collapsed the binary tree (the rest built it)
  bool hasClustered = false;  // the scene asks for binned SAH, so the clustered build was timed too
  WideBvh wideBvh, greedyBvh, clusteredBvh;
  Bvh bvh;
  double total() const { return bounds + wide; }
  double greedyTotal() const { return bounds + greedy; }
  double clusteredTotal() const { return bounds + clustered; }
};

TimedBuild time_build(const Scene& scene, const AcceleratorSettings& accel) {
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  TimedBuild b;
  auto t0 = Clock::now();
  BvhInput input = bvh_input(scene);
  auto t1 = Clock::now();
  b.wideBvh = build_wide_bvh(input, accel);
  auto t2 = Clock::now();
  b.bvh = build_bvh(input, accel);
  auto t3 = Clock::now();
  b.greedyBvh = build_wide_bvh(input, accel, WideCollapse::Greedy);
  auto t4 = Clock::now();
  b.bounds = seconds(t0, t1);
  b.wide = seconds(t1, t2);
  b.collapse = b.wideBvh.collapseSeconds;
  b.binary = seconds(t2, t3);
  b.greedy = seconds(t3, t4);
  if (accel.split == SplitMethod::Sah) {
    AcceleratorSettings clustered = accel;
    clustered.split = SplitMethod::ClusteredSah;
    b.clusteredBvh = build_wide_bvh(input, clustered);
    b.clustered = seconds(t4, Clock::now());
    b.hasClustered = true;
  }
  return b;
}

// Whether the trees' leaves hold every primitive exactly once.
bool places_every_primitive_once(const TimedBuild& b, size_t primitives) {
  std::vector<const std::vector<uint32_t>*> orders{&b.bvh.order, &b.wideBvh.order, &b.greedyBvh.order};
  if (b.hasClustered) orders.push_back(&b.clusteredBvh.order);
  for (const std::vector<uint32_t>* order : orders) {
    if (order->size() != primitives) return false;
    std::vector<bool> seen(primitives, false);
    for (uint32_t id : *order) {
      if (id >= primitives || seen[id]) return false;
      seen[id] = true;
    }
  }
  return true;
}

}  // namespace

int run_build_bench(const BenchOptions& o) {
  std::vector<Scene> scenes;
  for (const std::string& path : o.scenes) scenes.push_back(load_scene(path));
  const int threads = tbb::this_task_arena::max_concurrency();
  std::printf("BVH builds on %d threads: wavepath's (bounds, then the binary tree collapsed to 8-wide; the binary layout alone) "
              "against Embree's default build%s\n",
              threads, embree_available() ? "" : " (not built in)");
  nlohmann::json results = nlohmann::json::array();
  for (size_t si = 0; si < scenes.size(); ++si) {
    const Scene& scene = scenes[si];
    const size_t primitives = scene.triangles.size() + scene.spheres.size();
    // The settings compile_scene builds both layouts with, binned SAH where
    // the scene leaves the SAH build to its size: the clustered build is
    // timed beside it either way, and the renderer's choice marked.
    const SplitMethod rendererSplit = split_for(scene.accelerator, primitives);
    AcceleratorSettings accel = scene.accelerator;
    if (accel.split == SplitMethod::Auto) accel.split = SplitMethod::Sah;
    const bool clusteredIsRenderers = rendererSplit != accel.split;
    std::string embreeNote;
    bool embree = embree_available();
    if (embree && !scene.spheres.empty()) {
      embree = false;
      embreeNote = "the Embree baseline takes triangle scenes only";
    }
    // A warm-up round, then the timed ones, wavepath and Embree interleaved so
    // that a change in the machine's speed affects both alike.
    std::vector<double> total, bounds, wide, binaryTree, collapse, binary, greedy, clustered, embreeSeconds;
    TimedBuild last;
    for (int r = 0; r <= o.repeats; ++r) {
      last = time_build(scene, accel);
      double e = embree ? embree_build_seconds(scene) : 0.0;
      if (r == 0) continue;
      total.push_back(last.total());
      bounds.push_back(last.bounds);
      wide.push_back(last.wide);
      binaryTree.push_back(last.wide - last.collapse);
      collapse.push_back(last.collapse);
      binary.push_back(last.binary);
      greedy.push_back(last.greedyTotal());
      clustered.push_back(last.clusteredTotal());
      embreeSeconds.push_back(e);
    }
    if (!places_every_primitive_once(last, primitives))
      throw RenderError("internal error: the BVH of " + o.scenes[si] + " does not hold every primitive exactly once");
    const double rate = double(primitives) / std::max(spread(total).median, 1e-12);
    // The 8-wide trees' own SAH costs (the binary tree they are collapsed
    // from is split down to single primitives: its cost says little).
    const double wideSah = wide_sah_cost(last.wideBvh.nodes);
    const double greedySah = wide_sah_cost(last.greedyBvh.nodes);
    const double clusteredSah = last.hasClustered ? wide_sah_cost(last.clusteredBvh.nodes) : 0.0;
    std::printf("\n%s: %zu primitives, %s%s, leaves of at most %d (8-wide: %d); %zu binary and %zu wide nodes, "
                "SAH cost %.3f (binary layout), %.3f (8-wide)\n",
                o.scenes[si].c_str(), primitives, split_method_name(accel.split),
                clusteredIsRenderers ? " (the renderer's build for this size is the clustered one)" : "", accel.maxLeafSize,
                std::min(accel.maxLeafSize, WIDE_MAX_LEAF_SIZE), last.bvh.nodes.size(), last.wideBvh.nodes.size(),
                last.bvh.sahCost, wideSah);
    if (!embreeNote.empty()) std::printf("  Embree: %s\n", embreeNote.c_str());
    std::printf("  %-48s %10s %21s %10s\n", "build", "median s", "min - max s", "Mprims/s");
    auto row = [](const char* name, const Spread& s, double prims) {
      std::printf("  %-48s %10.4f %10.4f - %8.4f %10s\n", name, s.median, s.min, s.max,
                  prims > 0.0 ? format_number(prims / std::max(s.median, 1e-12) * 1e-6, 2).c_str() : "");
    };
    row(clusteredIsRenderers ? "wavepath, 8-wide" : "wavepath, 8-wide (the renderer's)", spread(total), double(primitives));
    row("  bounds", spread(bounds), 0.0);
    row("  binary tree collapsed to 8-wide", spread(wide), double(primitives));
    row("    binary tree to single primitives", spread(binaryTree), 0.0);
    row("    collapse", spread(collapse), 0.0);
    row("wavepath, binary layout alone", spread(binary), double(primitives));
    row("wavepath, 8-wide, greedy collapse", spread(greedy), double(primitives));
    const double greedyRate = double(primitives) / std::max(spread(greedy).median, 1e-12);
    std::printf("  greedy collapse: 8-wide SAH cost %.3f (SAH collapse %.3f), %.2fx the SAH collapse's rate\n",
                greedySah, wideSah, greedyRate / rate);
    const bool hasClustered = last.hasClustered;
    const double clusteredRate = hasClustered ? double(primitives) / std::max(spread(clustered).median, 1e-12) : 0.0;
    if (hasClustered) {
      row(clusteredIsRenderers ? "wavepath clustered SAH, 8-wide (the renderer's)" : "wavepath clustered SAH, 8-wide",
          spread(clustered), double(primitives));
      std::printf("  clustered SAH: 8-wide SAH cost %.3f (binned %.3f), %.2fx the binned build's rate\n",
                  clusteredSah, wideSah, clusteredRate / rate);
    }
    nlohmann::json j = {{"scene", o.scenes[si]},
                        {"primitives", primitives},
                        {"split", split_method_name(accel.split)},
                        {"renderer_split", split_method_name(rendererSplit)},
                        {"max_leaf_size", accel.maxLeafSize},
                        {"binary_nodes", last.bvh.nodes.size()},
                        {"wide_nodes", last.wideBvh.nodes.size()},
                        {"sah_cost", last.bvh.sahCost},
                        {"wide_sah_cost", wideSah},
                        {"seconds", to_json(spread(total))},
                        {"bounds_seconds", to_json(spread(bounds))},
                        {"wide_seconds", to_json(spread(wide))},
                        {"wide_binary_tree_seconds", to_json(spread(binaryTree))},
                        {"wide_collapse_seconds", to_json(spread(collapse))},
                        {"binary_seconds", to_json(spread(binary))},
                        {"greedy_seconds", to_json(spread(greedy))},
                        {"greedy_mprims_per_second", greedyRate * 1e-6},
                        {"greedy_sah_cost", greedySah},
                        {"mprims_per_second", rate * 1e-6}};
    if (hasClustered) {
      j["clustered_seconds"] = to_json(spread(clustered));
      j["clustered_mprims_per_second"] = clusteredRate * 1e-6;
      j["clustered_sah_cost"] = clusteredSah;  // 8-wide
    }
    if (embree) {
      const double embreeRate = double(scene.triangles.size()) / std::max(spread(embreeSeconds).median, 1e-12);
      row("Embree", spread(embreeSeconds), double(primitives));
      std::printf("  ratio %s / Embree: %.3f", clusteredIsRenderers ? "binned SAH" : "wavepath", rate / embreeRate);
      if (hasClustered) std::printf("; clustered SAH / Embree: %.3f", clusteredRate / embreeRate);
      std::printf("\n");
      j["embree_seconds"] = to_json(spread(embreeSeconds));
      j["embree_mprims_per_second"] = embreeRate * 1e-6;
      j["ratio_to_embree"] = rate / embreeRate;
      if (hasClustered) j["clustered_ratio_to_embree"] = clusteredRate / embreeRate;
    }
    results.push_back(j);
  }
  if (!o.jsonPath.empty()) {
    nlohmann::json j = {{"threads", threads}, {"embree", embree_available()}, {"repeats", o.repeats}, {"build", results}};
    write_json(o.jsonPath, j);
  }
  if (!o.csvPath.empty()) {
    std::ofstream out(o.csvPath);
    out << "scene,primitives,sah_cost,wide_sah_cost,seconds,wide_seconds,binary_seconds,mprims_per_second,greedy_seconds,"
           "greedy_mprims_per_second,greedy_sah_cost,clustered_seconds,clustered_mprims_per_second,clustered_sah_cost,"
           "embree_seconds,embree_mprims_per_second,ratio_to_embree,wide_binary_tree_seconds,wide_collapse_seconds\n";
    for (const nlohmann::json& r : results) {
      out << csv_field(r["scene"].get<std::string>()) << "," << r["primitives"] << "," << r["sah_cost"] << "," << r["wide_sah_cost"] << ","
          << r["seconds"]["median"] << "," << r["wide_seconds"]["median"] << "," << r["binary_seconds"]["median"] << ","
          << r["mprims_per_second"] << "," << r["greedy_seconds"]["median"] << "," << r["greedy_mprims_per_second"] << ","
          << r["greedy_sah_cost"];
      if (r.contains("clustered_seconds"))
        out << "," << r["clustered_seconds"]["median"] << "," << r["clustered_mprims_per_second"] << "," << r["clustered_sah_cost"];
      else
        out << ",,,";
      if (r.contains("embree_seconds"))
        out << "," << r["embree_seconds"]["median"] << "," << r["embree_mprims_per_second"] << "," << r["ratio_to_embree"];
      else
        out << ",,,";
      out << "," << r["wide_binary_tree_seconds"]["median"] << "," << r["wide_collapse_seconds"]["median"] << "\n";
    }
    if (!out) throw InputError(o.csvPath + ": cannot write the results");
  }
  return 0;
}

}  // namespace wp
