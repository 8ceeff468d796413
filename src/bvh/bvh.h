// bvh.h — binary BVH over primitive bounds, built on the host with binned SAH
// (or the clustered SAH build, or the darts "middle" / "equal" splits), in
// parallel, directly into the flat node array the kernels and the CPU
// reference traverse (shader::BvhNode).
// wide_bvh.h collapses it into the 8-wide layout.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <vector>

#include "scene/scene.h"
#include "shader/types.h"

namespace wp {

struct Aabb {
  glm::vec3 lo{3.0e38f};
  glm::vec3 hi{-3.0e38f};
  void grow(const Aabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  void grow(glm::vec3 p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return lo.x > hi.x; }
  float half_area() const {
    if (empty()) return 0.0f;
    glm::vec3 d = hi - lo;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
};

struct BvhInput {
  std::vector<Aabb> bounds;  // one per primitive
  // Per primitive, the sides it emits light towards (empty: none emits): bit
  // 2a where its front faces -a, bit 2a + 1 where it faces +a (every bit for
  // spheres), 0 where it does not emit. The binary build ignores it; the wide
  // collapse keeps flat emitters on grids that fit them, since shadow rays
  // aimed at one end just in front of it (wide_bvh.cpp).
  std::vector<uint8_t> emits;
};

struct Bvh {
  std::vector<shader::BvhNode> nodes;  // node 0 is the root
  // Leaf order: primitive ids as given to build_bvh, leaf after leaf; a leaf's
  // leftFirst indexes this array (and the primitive records, which
  // compile_scene lays out in this order).
  std::vector<uint32_t> order;
  int depth = 0;
  double sahCost = 0.0;  // expected cost per ray, traversal = 1, intersection = 1
  double buildSeconds = 0.0;
};

// From this many primitives on, SplitMethod::Auto takes the clustered SAH
// build instead of binned SAH. Below it the binned trees take the camera rays
// through fewer steps (+3.4 % for the clustered tree of 300 thousand
// triangles, +1.3 % at 1 million); from about 3 million on the clustered
// trees take as few or fewer (-3.4 % at 10 million) and build 1.2-1.4x
// faster (docs/benchmarks.md, "The clustered build by default for large
// scenes").
constexpr size_t kClusteredSahFromPrimitives = 2'000'000;

// The split method a build of `primitives` primitives with `settings` uses:
// settings.split, with Auto resolved by size.
SplitMethod split_for(const AcceleratorSettings& settings, size_t primitives);

// A split method's name for people: "binned SAH", "clustered SAH", ...
const char* split_method_name(SplitMethod m);

Bvh build_bvh(const BvhInput& input, const AcceleratorSettings& settings);

// The same tree where the builder leaves it, before build_bvh lays it out
// depth-first into Bvh::nodes: the root in slot 0 and each interior node's
// children in two adjacent slots, but slots that no node points to are
// unused (and uninitialized). The wide layout is collapsed straight from it
// (build_wide_bvh), which spares the copy: a fifth of the build at 10M
// triangles.
struct BvhSlots {
  const shader::BvhNode* nodes = nullptr;
  size_t slotCount = 0;
  const uint32_t* order = nullptr;  // as Bvh::order
  size_t primitiveCount = 0;
  int depth = 0;
  double sahCost = 0.0;  // as Bvh::sahCost, summed in another order
};

// Builds the tree and calls `use` with it while the builder's arrays live.
void build_bvh_slots(const BvhInput& input, const AcceleratorSettings& settings,
                     const std::function<void(const BvhSlots&)>& use);

// A node's box.
inline Aabb node_box(const shader::BvhNode& n) {
  Aabb b;
  b.lo = n.bmin;
  b.hi = n.bmax;
  return b;
}

}  // namespace wp
