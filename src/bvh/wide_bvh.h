// wide_bvh.h — the 8-wide compressed BVH (shader::WideNode), made by
// collapsing a binary BVH: each wide node takes up to eight descendants of a
// binary node, placed in slots by direction so that rays meet near children
// first, with child boxes quantized outwards to 8 bits per plane.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/bvh.h"

namespace wp {

struct WideBvh {
  std::vector<shader::WideNode> nodes;  // node 0 is the root
  // Leaf order: primitive ids as given to build_bvh, in the order the wide
  // nodes' primBase and offsets index them.
  std::vector<uint32_t> order;
  int depth = 0;          // wide nodes on the longest root-to-leaf path
  double sahCost = 0.0;  // of the binary tree it was collapsed from
  double collapseSeconds = 0.0;  // the collapse alone (build_wide_bvh: the rest is the binary tree's build)
};

// How a binary tree's nodes are picked as each wide node's children.
enum class WideCollapse {
  // The wide tree of least SAH cost, leaves included (Ylitie et al. 2017),
  // best from a binary tree split down to single primitives: it merges
  // subtrees of up to maxLeafSize primitives into leaves where that is
  // cheaper. The default.
  Sah,
  // Open the child of largest area until there are eight; the binary tree's
  // leaves stay the wide tree's (variant gpu-greedy).
  Greedy,
};

// The binary tree's leaves must hold at most WIDE_MAX_LEAF_SIZE primitives.
// `emits` is BvhInput::emits for the primitives the tree was built over. The
// SAH collapse merges leaves up to maxLeafSize (and WIDE_MAX_LEAF_SIZE)
// primitives.
WideBvh collapse_to_wide(const Bvh& binary, const std::vector<uint8_t>& emits = {}, WideCollapse how = WideCollapse::Sah,
                         int maxLeafSize = WIDE_MAX_LEAF_SIZE);

// The binary tree a collapse starts from, for a wide tree with `settings`:
// leaves of one primitive for the SAH collapse (which picks the leaves),
// else the scene's leaf size, at most WIDE_MAX_LEAF_SIZE.
AcceleratorSettings binary_settings_for_wide(const AcceleratorSettings& settings, WideCollapse how);

// build_bvh (with binary_settings_for_wide) and collapse_to_wide in one,
// collapsing the binary tree from the builder's own arrays (BvhSlots)
// instead of a laid-out copy. The same wide tree.
WideBvh build_wide_bvh(const BvhInput& input, const AcceleratorSettings& settings, WideCollapse how = WideCollapse::Sah);

// A wide tree's own SAH cost, from its quantized boxes: each node's area
// plus each leaf's area times its primitives, over the root's area (node and
// primitive both cost 1, as in the SAH collapse).
double wide_sah_cost(const std::vector<shader::WideNode>& nodes);

// The box a wide node's slot decodes to (origin + q * 2^(e-127) per plane),
// for the tests; empty slots decode to whatever their bytes say.
Aabb wide_child_box(const shader::WideNode& node, int slot);

}  // namespace wp
