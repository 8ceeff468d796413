// `wavepath bench --build`: BVH builds timed against Embree's.
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
  const nlohmann::json document = {{"threads", threads}, {"embree", embree_available()}, {"repeats", o.repeats}, {"build", results}};
  if (!o.jsonPath.empty()) write_json(o.jsonPath, document);
  if (o.results) *o.results = document.dump();
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
