// `wavepath bench --simt`: the ray sets of `bench --raycast` replayed through
// the SIMT model of the walks (simt_model.h), per variant, ray set and warp
// width; with --measured, the model's order of the variants beside a GPU's.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>

#include "bench/bench.h"
#include "bench/bench_support.h"
#include "bench/ray_sets.h"
#include "bench/simt_model.h"
#include "cpu/reference.h"
#include "gpu/wavefront.h"
#include "scene/load_scene.h"
#include "util/error.h"

namespace wp {

using namespace bench;

namespace {

std::string file_name(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Measured Mrays/s by (scene file name, ray set, variant), from the JSON
// that `bench --raycast --out` writes.
using Measured = std::map<std::tuple<std::string, std::string, std::string>, double>;

Measured read_measured(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the measured results");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path + ": not JSON (" + std::string(e.what()) + ")");
  }
  if (!j.is_object() || !j.contains("raycast") || !j["raycast"].is_array())
    throw InputError(path + ": no \"raycast\" array: not the output of bench --raycast --out");
  Measured m;
  for (size_t i = 0; i < j["raycast"].size(); ++i) {
    const nlohmann::json& r = j["raycast"][i];
    const std::string where = path + ": /raycast/" + std::to_string(i);
    if (!r.is_object() || !r.contains("scene") || !r.contains("rays") || !r.contains("variant"))
      throw InputError(where + ": needs scene, rays and variant");
    if (!r.contains("mrays_per_second")) continue;  // a variant that failed its check was not timed
    if (!r["mrays_per_second"].is_number()) throw InputError(where + "/mrays_per_second: not a number");
    m[{file_name(r["scene"].get<std::string>()), r["rays"].get<std::string>(), r["variant"].get<std::string>()}] =
        r["mrays_per_second"].get<double>();
  }
  return m;
}

// Spreads the low 10 bits of x to every third bit.
uint32_t spread_bits(uint32_t x) {
  x &= 0x3ffu;
  x = (x | (x << 16)) & 0x030000ffu;
  x = (x | (x << 8)) & 0x0300f00fu;
  x = (x | (x << 4)) & 0x030c30c3u;
  return (x | (x << 2)) & 0x09249249u;
}

// The rays reordered as a sort before the tracing kernel would leave them:
// by the octant of their direction ("octant"), or by octant and then the
// Morton code of their origin in the origins' box ("morton"); stable, so
// rays of one key keep the kernels' order.
std::vector<shader::ShadowRay> reordered(const std::vector<shader::ShadowRay>& rays, const std::string& order) {
  glm::vec3 lo(WP_INF), hi(-WP_INF);
  for (const shader::ShadowRay& r : rays) {
    lo = glm::min(lo, r.origin);
    hi = glm::max(hi, r.origin);
  }
  const glm::vec3 scale = 1023.0f / glm::max(hi - lo, glm::vec3(1e-20f));
  std::vector<std::pair<uint64_t, uint32_t>> keys(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    const shader::ShadowRay& r = rays[i];
    uint64_t key = uint64_t((r.dir.x < 0.0f ? 1u : 0u) | (r.dir.y < 0.0f ? 2u : 0u) | (r.dir.z < 0.0f ? 4u : 0u)) << 30;
    if (order == "morton") {
      const glm::uvec3 q(glm::clamp((r.origin - lo) * scale, glm::vec3(0.0f), glm::vec3(1023.0f)));
      key |= (spread_bits(q.x) << 2) | (spread_bits(q.y) << 1) | spread_bits(q.z);
    }
    keys[i] = {key, uint32_t(i)};
  }
  std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<shader::ShadowRay> out(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) out[i] = rays[keys[i].second];
  return out;
}

// Variant names by falling rate.
std::string order_of(std::vector<std::pair<double, std::string>> rates) {
  std::sort(rates.begin(), rates.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string s;
  for (const auto& r : rates) s += (s.empty() ? "" : " > ") + r.second;
  return s;
}

nlohmann::json to_json(const SimtFigures& f) {
  return {{"rays", f.rays},
          {"warps", f.warps},
          {"iterations_per_warp", f.iterationsPerWarp},
          {"simd_efficiency", f.simdEfficiency},
          {"phase_efficiency", f.phaseEfficiency},
          {"steps_per_ray", f.stepsPerRay},
          {"node_visits_per_ray", f.nodeVisitsPerRay},
          {"instance_node_visits_per_ray", f.instanceNodeVisitsPerRay},
          {"node_sectors_per_iteration", f.nodeSectors},
          {"node_lines_per_iteration", f.nodeLines},
          {"prim_sectors_per_iteration", f.primSectors},
          {"prim_lines_per_iteration", f.primLines},
          {"stack_sectors_per_iteration", f.stackSectors},
          {"stack_lines_per_iteration", f.stackLines},
          {"other_sectors_per_iteration", f.otherSectors},
          {"bytes_per_ray", f.bytesPerRay},
          {"l1_hit_rate", f.l1HitRate},
          {"l2_bytes_per_ray", f.l2BytesPerRay},
          {"deepest_stack", f.deepestStack},
          {"bound_shares", {{"issue", f.issueShare}, {"l1", f.l1Share}, {"l2", f.l2Share}, {"latency", f.latencyShare}}},
          {"bound", f.bound},
          {"predicted_mrays_per_second", f.predictedRaysPerSecond * 1e-6},
          {"sm_balance", f.smBalance}};
}

}  // namespace

std::vector<std::string> simt_variants() {
  // gpu-memstack and gpu-oneray walk as gpu does on a GPU; the megakernels,
  // sorting and compaction change what is traced, not the walk.
  return {"gpu", "gpu-bvh2", "gpu-regstack", "gpu-multiray", "gpu-greedy", "gpu-clustered", "gpu-loads", "gpu-bvh2-loads", "gpu-bvh2-fused"};
}

int run_simt_bench(const BenchOptions& o) {
  const GpuModel& gpu = gpu_model(o.gpuModel);
  const Measured measured = o.measuredPath.empty() ? Measured{} : read_measured(o.measuredPath);
  nlohmann::json results = nlohmann::json::array();
  std::printf("SIMT model of the walks on %s (%d SMs at %.2f GHz, %d resident warps an SM); "
              "sectors and lines are per warp iteration, predictions for warps of 32\n",
              gpu.name.c_str(), gpu.sms, gpu.clockGHz, gpu.residentWarps);
  for (const std::string& path : o.scenes) {
    Scene scene = with_resolution(load_scene(path), o);
    const CompiledScene reference = compile_scene(scene, reference_options(RenderOptions{}));
    const RaySets sets = make_rays(reference);
    std::vector<CompiledScene> compiled;
    for (const std::string& v : o.variants) compiled.push_back(compile_scene(scene, variant_options(RenderOptions{}, v)));
    for (size_t vi = 0; vi < o.variants.size() && o.nodeStrideBytes != 0; ++vi) {
      const bool wide = simt_walk(o.variants[vi], compiled[vi]).wide;
      const size_t nodeBytes = wide ? sizeof(shader::WideNode) : 2 * sizeof(shader::BvhNode);
      if (o.nodeStrideBytes < nodeBytes || o.nodeStrideBytes % 16 != 0)
        throw InputError("--node-stride " + std::to_string(o.nodeStrideBytes) + ": a " + o.variants[vi] + (wide ? " node" : " pair of nodes") +
                         " takes " + std::to_string(nodeBytes) + " bytes, and strides are whole 16-byte texels");
    }
    std::printf("\n%s: %zu primary, %zu bounce and %zu shadow rays\n", path.c_str(), sets.primary.size(), sets.bounce.size(),
                sets.shadow.size());
    std::printf("  %-14s %-13s %4s %7s %6s %6s %6s %11s %11s %11s %7s %6s %5s %9s %-8s %9s\n", "rays", "variant", "warp", "it/warp",
                "SIMD", "phase", "steps", "node s/l", "prim s/l", "stack s/l", "B/ray", "L1 hit", "stack", "pred Mr/s", "bound",
                "measured");
    // The ray sets as the kernels take them, and the incoherent ones
    // reordered as each --reorder asks (a candidate modelled before it is
    // built: "bounce/morton" is the bounce rays sorted so).
    struct RaySet {
      std::string name;
      std::vector<shader::ShadowRay> rays;
      bool anyHit;
    };
    std::vector<RaySet> raySets{{"primary", sets.primary, false}, {"bounce", sets.bounce, false}, {"shadow", sets.shadow, true}};
    for (const std::string& order : o.reorders)
      for (size_t k : {size_t(1), size_t(2)}) raySets.push_back({raySets[k].name + "/" + order, reordered(raySets[k].rays, order), raySets[k].anyHit});
    for (const RaySet& set : raySets) {
      if (set.rays.empty()) continue;
      const bool anyHit = set.anyHit;
      std::vector<std::pair<double, std::string>> predicted, seen;
      std::string nodeVisits, balance;
      for (size_t row = 0; row < o.variants.size() * (o.nodeStrideBytes ? 2 : 1); ++row) {
        const size_t vi = row % o.variants.size();
        SimtWalk walk = simt_walk(o.variants[vi], compiled[vi]);
        if (row >= o.variants.size()) {  // --node-stride: the same walk over nodes laid out so
          walk.nodeStrideBytes = o.nodeStrideBytes;
          walk.variant += "/" + std::to_string(o.nodeStrideBytes) + "B";
        }
        for (int width : o.warpWidths) {
          const SimtFigures f = simulate_walks(compiled[vi], set.rays, anyHit, walk, gpu, width);
          const auto m = measured.find({file_name(path), set.name, walk.variant});
          const bool predicts = width == 32;
          char measuredText[32] = "-";
          if (m != measured.end() && predicts) std::snprintf(measuredText, sizeof measuredText, "%.0f", m->second);
          char pred[32] = "-";
          if (predicts) std::snprintf(pred, sizeof pred, "%.0f", f.predictedRaysPerSecond * 1e-6);
          std::printf("  %-14s %-13s %4d %7.1f %6.3f %6.3f %6.1f %5.1f/%-5.1f %5.1f/%-5.1f %5.1f/%-5.1f %7.0f %6.3f %5u %9s %-8s %9s\n",
                      set.name.c_str(), walk.variant.c_str(), width, f.iterationsPerWarp, f.simdEfficiency, f.phaseEfficiency,
                      f.stepsPerRay, f.nodeSectors, f.nodeLines, f.primSectors, f.primLines, f.stackSectors, f.stackLines,
                      f.bytesPerRay, f.l1HitRate, f.deepestStack, pred, predicts ? f.bound.c_str() : "-", measuredText);
          if (f.instanceNodeVisitsPerRay > 0.0 && width == o.warpWidths.front()) {
            char text[96];
            std::snprintf(text, sizeof text, "%s%s %.1f + %.1f", nodeVisits.empty() ? "" : ", ", walk.variant.c_str(),
                          f.nodeVisitsPerRay - f.instanceNodeVisitsPerRay, f.instanceNodeVisitsPerRay);
            nodeVisits += text;
          }
          if (predicts) {
            char text[64];
            std::snprintf(text, sizeof text, "%s%s %.3f", balance.empty() ? "" : ", ", walk.variant.c_str(), f.smBalance);
            balance += text;
          }
          nlohmann::json row = to_json(f);
          row["scene"] = path;
          row["rays_set"] = set.name;
          row["variant"] = walk.variant;
          row["warp_width"] = width;
          row["gpu_model"] = gpu.name;
          if (m != measured.end()) row["measured_mrays_per_second"] = m->second;
          results.push_back(row);
          if (predicts) {
            predicted.emplace_back(f.predictedRaysPerSecond, walk.variant);
            if (m != measured.end()) seen.emplace_back(m->second, walk.variant);
          }
        }
      }
      // In instanced scenes: where the node visits went, which bound the
      // steps from below (an iteration visits at most one node).
      if (!nodeVisits.empty()) std::printf("  %-7s node visits a ray, top level + instances' trees (warps of %d): %s\n", set.name.c_str(), o.warpWidths.front(), nodeVisits.c_str());
      // What dynamic fetch across SMs could gain at most is its inverse.
      std::printf("  %-7s SM balance (mean SM's time / slowest's): %s\n", set.name.c_str(), balance.c_str());
      if (predicted.size() > 1) std::printf("  %-7s predicted order: %s\n", set.name.c_str(), order_of(predicted).c_str());
      if (seen.size() > 1) std::printf("  %-7s measured order:  %s\n", set.name.c_str(), order_of(seen).c_str());
    }
  }
  const nlohmann::json document = {{"gpu_model", gpu.name}, {"simt", results}};
  if (!o.jsonPath.empty()) write_json(o.jsonPath, document);
  if (o.results) *o.results = document.dump();
  if (!o.csvPath.empty()) {
    std::ofstream out(o.csvPath);
    out << "scene,rays,variant,warp_width,iterations_per_warp,simd_efficiency,phase_efficiency,steps_per_ray,"
           "node_sectors,node_lines,prim_sectors,prim_lines,stack_sectors,stack_lines,bytes_per_ray,l1_hit_rate,"
           "l2_bytes_per_ray,deepest_stack,predicted_mrays_per_second,bound,measured_mrays_per_second\n";
    for (const nlohmann::json& r : results) {
      out << csv_field(r["scene"].get<std::string>()) << "," << r["rays_set"].get<std::string>() << ","
          << r["variant"].get<std::string>() << "," << r["warp_width"];
      for (const char* k : {"iterations_per_warp", "simd_efficiency", "phase_efficiency", "steps_per_ray",
                            "node_sectors_per_iteration", "node_lines_per_iteration", "prim_sectors_per_iteration",
                            "prim_lines_per_iteration", "stack_sectors_per_iteration", "stack_lines_per_iteration",
                            "bytes_per_ray", "l1_hit_rate", "l2_bytes_per_ray", "deepest_stack", "predicted_mrays_per_second"})
        out << "," << r[k];
      out << "," << r["bound"].get<std::string>() << ",";
      if (r.contains("measured_mrays_per_second")) out << r["measured_mrays_per_second"];
      out << "\n";
    }
    if (!out) throw InputError(o.csvPath + ": cannot write the results");
  }
  return 0;
}

}  // namespace wp
