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
};

// The binary tree's leaves must hold at most WIDE_MAX_LEAF_SIZE primitives.
// `emits` is BvhInput::emits for the primitives the tree was built over.
WideBvh collapse_to_wide(const Bvh& binary, const std::vector<uint8_t>& emits = {});

// build_bvh and collapse_to_wide in one, collapsing the binary tree from the
// builder's own arrays (BvhSlots) instead of a laid-out copy. The same wide
// tree.
WideBvh build_wide_bvh(const BvhInput& input, const AcceleratorSettings& settings);

// The box a wide node's slot decodes to (origin + q * 2^(e-127) per plane),
// for the tests; empty slots decode to whatever their bytes say.
Aabb wide_child_box(const shader::WideNode& node, int slot);

}  // namespace wp
