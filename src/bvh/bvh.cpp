#include "bvh/bvh.h"

#include <algorithm>
#include <chrono>

#include "bvh/builder.h"

namespace wp {

using build::Builder;

namespace {

// The SAH cost of a binary tree (its nodes' areas relative to the root's).
double sah_cost(const std::vector<shader::BvhNode>& nodes) {
  double rootArea = std::max(double(node_box(nodes[0]).half_area()), 1e-30);
  double cost = 0.0;
  for (const shader::BvhNode& n : nodes) cost += build::sah_term(n, rootArea);
  return cost;
}

}  // namespace

SplitMethod split_for(const AcceleratorSettings& settings, size_t primitives) {
  if (settings.split != SplitMethod::Auto) return settings.split;
  return primitives >= kClusteredSahFromPrimitives ? SplitMethod::ClusteredSah : SplitMethod::Sah;
}

const char* split_method_name(SplitMethod m) {
  switch (m) {
    case SplitMethod::Sah: return "binned SAH";
    case SplitMethod::ClusteredSah: return "clustered SAH";
    case SplitMethod::Middle: return "middle split";
    case SplitMethod::Equal: return "equal counts";
    case SplitMethod::Auto: return "SAH, binned or clustered by size";
  }
  return "?";
}

void build_bvh_slots(const BvhInput& input, const AcceleratorSettings& settings,
                     const std::function<void(const BvhSlots&)>& use) {
  Builder(input, settings).build_slots(use);
}

Bvh build_bvh(const BvhInput& input, const AcceleratorSettings& settings) {
  auto start = std::chrono::steady_clock::now();
  Bvh bvh = Builder(input, settings).build();
  bvh.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!input.bounds.empty()) bvh.sahCost = sah_cost(bvh.nodes);
  return bvh;
}

}  // namespace wp
