#include "bvh/wide_bvh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>

#include <tbb/task_group.h>

#include "util/error.h"
#include "util/huge_pages.h"

namespace wp {

namespace {

using shader::BvhNode;
using shader::WideNode;

bool is_leaf(const BvhNode& n) {
  return n.count != 0;
}

// Slot of each child. Slot s stands for the octant with sign bits s (bit a
// set: towards -a); the child lying furthest towards an octant, seen from the
// node's centre, takes that octant's slot, greedily, best pair first: of the
// children and slots still free, the pair of highest score, the lower child
// and then the lower slot on ties. The walk visits slots in an order its
// ray's octant gives (see WideNode).
//
// Each (child, slot) pair is one key that orders pairs so: the score's bits
// made monotonic, then the child's and the slot's indices reversed. Keys are
// doubles (exact below 2^53) for two reasons: a taken child or slot is masked
// by a product with 0, without branches, and the compiler keeps floating-point
// maxima in the independent chains written below. Integer maxima it chained
// into one run of 64 dependent steps per pick, and the branchy search before
// (each child's best free slot, kept current) mispredicted: either way the
// slots took half of the collapse's time.
void assign_slots(const Aabb* boxes, int n, int slotOf[8]) {
  Aabb all;
  for (int i = 0; i < n; ++i) all.grow(boxes[i]);
  const glm::vec3 centre = 0.5f * (all.lo + all.hi);
  double key[64];  // 0 for the pairs of absent children
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 offset = c < n ? 0.5f * (boxes[c].lo + boxes[c].hi) - centre : glm::vec3(0.0f);
    for (int s = 0; s < 8; ++s) {
      // + 0: -0 becomes +0, equal to it as a score.
      const float score = ((s & 1) ? -offset.x : offset.x) + ((s & 2) ? -offset.y : offset.y) + ((s & 4) ? -offset.z : offset.z) + 0.0f;
      uint32_t bits;
      std::memcpy(&bits, &score, sizeof bits);
      bits ^= uint32_t(int32_t(bits) >> 31) | 0x80000000u;  // ordered as unsigned integers
      key[c * 8 + s] = c < n ? double((uint64_t(bits) << 6) | uint64_t((7 - c) << 3) | uint64_t(7 - s)) : 0.0;
    }
  }
  auto larger = [](double a, double b) { return a > b ? a : b; };
  double childFree[8], slotFree[8];
  for (int i = 0; i < 8; ++i) {
    childFree[i] = 1.0;
    slotFree[i] = 1.0;
  }
  for (int k = 0; k < n; ++k) {
    double row[8];  // per child, its best pair with a free slot
    for (int c = 0; c < 8; ++c) {
      const double* r = key + 8 * c;
      row[c] = childFree[c] * larger(larger(larger(r[0] * slotFree[0], r[1] * slotFree[1]), larger(r[2] * slotFree[2], r[3] * slotFree[3])),
                                     larger(larger(r[4] * slotFree[4], r[5] * slotFree[5]), larger(r[6] * slotFree[6], r[7] * slotFree[7])));
    }
    const uint64_t m = uint64_t(larger(larger(larger(row[0], row[1]), larger(row[2], row[3])), larger(larger(row[4], row[5]), larger(row[6], row[7]))));
    const int c = 7 - int((m >> 3) & 7u), s = 7 - int(m & 7u);
    slotOf[c] = s;
    childFree[c] = 0.0;
    slotFree[s] = 0.0;
  }
}

// 2^e as a double, for e within the range of normal doubles.
double power_of_two(int e) {
  const uint64_t bits = uint64_t(e + 1023) << 52;
  double p;
  std::memcpy(&p, &bits, sizeof p);
  return p;
}

// The power-of-two cell size per axis (as the biased exponent stored in the
// node) such that 255 cells span [lo, hi].
uint32_t cell_exponent(float lo, float hi) {
  double extent = double(hi) - double(lo);
  int e = -126;
  if (extent > 0.0) {
    // ceil(log2(extent / 255)) from the bits of the double (always normal:
    // extent is at least the least float).
    uint64_t bits;
    const double ratio = extent / 255.0;
    std::memcpy(&bits, &ratio, sizeof bits);
    const int exponent = int((bits >> 52) & 0x7ffu) - 1023;
    e = std::max(-126, (bits & ((uint64_t(1) << 52) - 1)) != 0 ? exponent + 1 : exponent);
    while (255.0 * power_of_two(e) < extent) ++e;  // the division may round down
  }
  return uint32_t(std::min(e, 127) + 127);
}

float cell_size(uint32_t biasedExponent) {
  const uint32_t bits = biasedExponent << 23;
  float cell;
  std::memcpy(&cell, &bits, sizeof cell);
  return cell;
}

// Quantized planes of [lo, hi] on the grid origin + q * cell, rounded
// outwards and checked in float as the decoding computes them. `inverseCell`
// is 1 / cell, exact since cell is a power of two. Floor and ceiling are
// taken after clamping to [0, 255], where they are integer conversions
// rather than calls into libm. A NaN plane (bounds that are not finite, which
// the builder tolerates) widens to the grid's end: converting NaN to an
// integer is undefined.
std::pair<uint32_t, uint32_t> quantize(float lo, float hi, float origin, float cell, double inverseCell) {
  const double rawLo = (double(lo) - double(origin)) * inverseCell, rawHi = (double(hi) - double(origin)) * inverseCell;
  const double below = rawLo > 0.0 ? std::min(rawLo, 255.0) : 0.0;
  const double above = rawHi < 255.0 ? std::max(rawHi, 0.0) : 255.0;
  int qlo = int(below);
  int qhi = int(above);
  if (double(qhi) < above) ++qhi;
  while (qlo > 0 && origin + float(qlo) * cell > lo) --qlo;
  while (qhi < 255 && origin + float(qhi) * cell < hi) ++qhi;
  return {uint32_t(qlo), uint32_t(qhi)};
}

// Where shadow rays end. Next-event estimation aims shadow rays at points on
// emitters and ends them in front of the surface (offset_ray: at least 2^-16
// of the point's coordinates away). A flat emitter leaf whose plane falls
// between two planes of a wide node's grid is widened by part of a cell on
// each side, and where that moves its front plane past the rays' ends, every
// shadow ray aimed at it enters its box and tests its primitives. On the
// Cornell box, whose light sits just under the ceiling, the root's grid
// (4-unit cells) took in the light and the ceiling, and shadow rays took 6.3
// walk steps instead of 3.1 (docs/benchmarks.md).
struct EmitterLeaves {
  const uint32_t* order = nullptr;  // the binary tree's leaf order
  const uint8_t* emits = nullptr;   // BvhInput::emits, or null: none emits

  // The sides the primitives order[first, first + count) emit towards
  // (BvhInput::emits' bits).
  uint32_t sides(uint32_t first, uint32_t count) const {
    uint32_t s = 0;
    for (uint32_t k = 0; k < count; ++k) s |= emits[order[first + k]];
    return s;
  }

  // Whether the grid of a wide node over `grid` moves a front plane of
  // `leaf` (emitting towards `sides`) past where shadow rays end, on an axis
  // where the leaf is thinner than a cell.
  static bool grid_widens(const Aabb& leaf, uint32_t sides, const Aabb& grid) {
    for (int a = 0; a < 3; ++a) {
      const float cell = cell_size(cell_exponent(grid.lo[a], grid.hi[a]));
      if (leaf.hi[a] - leaf.lo[a] >= cell) continue;
      const auto [qlo, qhi] = quantize(leaf.lo[a], leaf.hi[a], grid.lo[a], cell, 1.0 / double(cell));
      const float below = leaf.lo[a] - (grid.lo[a] + float(qlo) * cell);
      const float above = (grid.lo[a] + float(qhi) * cell) - leaf.hi[a];
      // Half the least distance offset_ray puts between a ray's end and the surface.
      const float end = 0.5f * std::max(std::ldexp(std::max(std::fabs(leaf.lo[a]), std::fabs(leaf.hi[a])), -16), 1.0f / 65536.0f);
      if (((sides >> (2 * a)) & 1u && below > end) || ((sides >> (2 * a + 1)) & 1u && above > end)) return true;
    }
    return false;
  }

  // Whether opening binary node `node` (a child of a wide node over `grid`)
  // would move an emitter leaf from the grid of its own box, which fits it,
  // to `grid`, which widens it. leaf_of(c, first, count) says whether child c
  // becomes (or may become) a leaf, of the primitives order[first, first + count).
  template <typename LeafOf>
  bool opening_widens(const BvhNode* nodes, const BvhNode& node, const Aabb& grid, LeafOf leaf_of) const {
    if (!emits) return false;
    for (uint32_t k = 0; k < 2; ++k) {
      uint32_t first = 0, count = 0;
      if (!leaf_of(node.leftFirst + k, first, count)) continue;
      const uint32_t s = sides(first, count);
      const Aabb box = node_box(nodes[node.leftFirst + k]);
      if (s != 0 && grid_widens(box, s, grid) && !grid_widens(box, s, node_box(node))) return true;
    }
    return false;
  }
};

// The greedy collapse (WideCollapse::Greedy): up to eight descendants of
// binary node `root`, the children of one wide node: starting from root's two
// children, the interior one of largest surface area is replaced by its two
// children until there are eight or none is interior, except where that would
// widen an emitter leaf (above). A root that is itself a leaf becomes a wide
// node's only child.
int collapse_children(const BvhNode* nodes, uint32_t root, const EmitterLeaves& emitters, uint32_t out[8]) {
  const BvhNode& r = nodes[root];
  if (is_leaf(r)) {
    out[0] = root;
    return 1;
  }
  const Aabb grid = node_box(r);  // the wide node's box: its children's union
  int n = 2;
  out[0] = r.leftFirst;
  out[1] = r.leftFirst + 1;
  uint32_t kept = 0;  // bit i: out[i] stays closed
  while (n < 8) {
    int best = -1;
    float bestArea = -1.0f;
    for (int i = 0; i < n; ++i) {
      const BvhNode& c = nodes[out[i]];
      float area = node_box(c).half_area();
      if (!is_leaf(c) && ((kept >> i) & 1u) == 0u && area > bestArea) {
        bestArea = area;
        best = i;
      }
    }
    if (best < 0) break;
    auto binary_leaf = [nodes](uint32_t c, uint32_t& first, uint32_t& count) {
      first = nodes[c].leftFirst;
      count = nodes[c].count;
      return is_leaf(nodes[c]);
    };
    if (emitters.opening_widens(nodes, nodes[out[best]], grid, binary_leaf)) {
      kept |= 1u << best;
      continue;
    }
    uint32_t expanded = out[best];
    out[best] = nodes[expanded].leftFirst;
    out[n++] = nodes[expanded].leftFirst + 1;
  }
  return n;
}

// A wide node's child: a binary node that becomes a wide node of its own
// (interior), or a leaf of the primitives order[first, first + count).
struct WideChild {
  uint32_t node;
  bool interior;
  uint32_t first, count;
};

void set_byte(uint32_t& word, int index, uint32_t value) {
  word |= (value & 0xffu) << (8 * index);
}

uint32_t get_byte(uint32_t word, int index) {
  return (word >> (8 * index)) & 0xffu;
}

// The words of WideNode holding plane (axis, upper) of slots 0-3 and 4-7.
uint32_t* plane_words(WideNode& n, int axis, bool upper) {
  uint32_t* q[6] = {&n.qlo.x, &n.qlo.z, &n.qloZqhiX.x, &n.qloZqhiX.z, &n.qhi.x, &n.qhi.z};
  return q[axis + (upper ? 3 : 0)];
}

const uint32_t* plane_words(const WideNode& n, int axis, bool upper) {
  return plane_words(const_cast<WideNode&>(n), axis, upper);
}

}  // namespace

Aabb wide_child_box(const WideNode& node, int slot) {
  Aabb b;
  for (int a = 0; a < 3; ++a) {
    float cell = cell_size(get_byte(node.exyzImask, a));
    b.lo[a] = node.origin[a] + float(get_byte(plane_words(node, a, false)[slot / 4], slot % 4)) * cell;
    b.hi[a] = node.origin[a] + float(get_byte(plane_words(node, a, true)[slot / 4], slot % 4)) * cell;
  }
  return b;
}

namespace {

// Collapses in two parallel passes over the wide tree: the first measures
// each wide subtree (nodes, primitives, height), so that the second can give
// every subtree its own block of nodes and of primitive order and write the
// subtrees independently. A node's interior children are consecutive (the
// layout requires it); each one's descendants follow in a block of their own.
class Collapser {
 public:
  // A binary tree's nodes (slotCount slots; those no node points to are not
  // read) and leaf order, and BvhInput::emits (or null). The SAH collapse
  // merges subtrees of at most maxLeafSize primitives into leaves.
  Collapser(const BvhNode* nodes, size_t slotCount, const uint32_t* order, const uint8_t* emits, WideCollapse how,
            uint32_t maxLeafSize)
      : nodes_(nodes),
        order_(order),
        emitters_{order, emits},
        how_(how),
        maxLeafSize_(std::min<uint32_t>(maxLeafSize, WIDE_MAX_LEAF_SIZE)),
        subtree_(slotCount),
        links_(how == WideCollapse::Sah ? slotCount : 0) {
    // Primitives are fewer than slots, so both fit below kLeafLink.
    if (slotCount >= kLeafLink) throw RenderError("internal error: too many BVH nodes for the collapse");
  }

  WideBvh run() {
    WideBvh out;
    if (how_ == WideCollapse::Sah) solve(0, 0);
    out.depth = measure(0, 0);
    reserve_huge(out.nodes, subtree_[0].nodes);
    out.nodes.resize(subtree_[0].nodes);
    reserve_huge(out.order, subtree_[0].prims);
    out.order.resize(subtree_[0].prims);
    out_ = &out;
    emit(0, 0, 1, 0, 0);
    return out;
  }

 private:
  // Wide levels whose subtrees are handled as separate tasks: up to 8^4.
  static constexpr int kParallelDepth = 4;

  // A wide node's interior children (indices into its kids), in the order of
  // their node indices.
  struct Interior {
    int child[8];
    int count = 0;
    void add(int i) { child[count++] = i; }
    const int* begin() const { return child; }
    const int* end() const { return child + count; }
  };

  // Runs f(i) for each interior child i, as tasks near the root.
  template <typename F>
  static void for_children(int depth, const Interior& interior, F f) {
    if (depth >= kParallelDepth) {
      for (int i : interior) f(i);
      return;
    }
    tbb::task_group tasks;
    for (int i : interior) tasks.run([&f, i] { f(i); });
    tasks.wait();
  }

  // Sizes of the wide subtree rooted at the wide node that stands for binary
  // node b; returns its height in wide nodes.
  int measure(uint32_t b, int depth) {
    WideChild child[8];
    uint32_t kids[8];
    const int n = children_of(b, child);
    Interior interior;
    uint32_t wide = 1, prims = 0;
    for (int i = 0; i < n; ++i) {
      kids[i] = child[i].node;
      if (child[i].interior) {
        interior.add(i);
      } else if (child[i].count > WIDE_MAX_LEAF_SIZE) {
        throw RenderError("internal error: a BVH leaf holds more primitives than a wide node's slot");
      } else {
        prims += child[i].count;
      }
    }
    int heights[8] = {};
    for_children(depth, interior, [&](int i) { heights[i] = measure(kids[i], depth + 1); });
    int height = 1;
    for (int i : interior) {
      wide += subtree_[kids[i]].nodes;
      prims += subtree_[kids[i]].prims;
      height = std::max(height, 1 + heights[i]);
    }
    subtree_[b] = SubtreeSize{wide, prims};
    return height;
  }

  // Writes the wide node `wideIndex` for binary node b: its interior children
  // go to nodes [childBase, ...), its leaf children's primitives to order
  // [primBase, ...); then the children's subtrees, each in its own block.
  void emit(uint32_t wideIndex, uint32_t b, uint32_t childBase, uint32_t primBase, int depth) {
    WideChild child[8];
    uint32_t kids[8];
    const int n = children_of(b, child);
    for (int i = 0; i < n; ++i) kids[i] = child[i].node;
    Aabb boxes[8], all;
    for (int i = 0; i < n; ++i) {
      boxes[i] = node_box(nodes_[kids[i]]);
      all.grow(boxes[i]);
    }
    int slotOf[8];
    assign_slots(boxes, n, slotOf);
    int childInSlot[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
    for (int i = 0; i < n; ++i) childInSlot[slotOf[i]] = i;

    WideNode node{};
    node.origin = all.lo;
    float cell[3];
    double inverseCell[3];
    for (int a = 0; a < 3; ++a) {
      const uint32_t e = cell_exponent(all.lo[a], all.hi[a]);
      set_byte(node.exyzImask, a, e);
      cell[a] = cell_size(e);
      inverseCell[a] = 1.0 / double(cell[a]);
    }
    node.childBase = childBase;
    node.primBase = primBase;
    Interior interior;
    uint32_t imask = 0, offset = 0;
    for (int s = 0; s < 8; ++s) {
      int i = childInSlot[s];
      if (i < 0) continue;  // empty slot: meta 0, no bits
      for (int a = 0; a < 3; ++a) {
        auto [qlo, qhi] = quantize(boxes[i].lo[a], boxes[i].hi[a], node.origin[a], cell[a], inverseCell[a]);
        set_byte(plane_words(node, a, false)[s / 4], s % 4, qlo);
        set_byte(plane_words(node, a, true)[s / 4], s % 4, qhi);
      }
      const WideChild& c = child[i];
      uint32_t meta;
      if (c.interior) {
        imask |= 1u << s;
        meta = (1u << 5) | (24u + uint32_t(s));
        interior.add(i);
      } else {
        meta = (((1u << c.count) - 1u) << 5) | offset;
        std::copy(order_ + c.first, order_ + c.first + c.count, out_->order.begin() + primBase + offset);
        offset += c.count;
      }
      set_byte(s < 4 ? node.meta0123 : node.meta4567, s % 4, meta);
    }
    set_byte(node.exyzImask, 3, imask);
    out_->nodes[wideIndex] = node;

    // Each interior child's node index, and where its descendants and its
    // primitives go.
    uint32_t indexOf[8], nodeAt[8], primAt[8];
    uint32_t nextNode = childBase + uint32_t(interior.count), nextPrim = primBase + offset;
    for (int k = 0; k < interior.count; ++k) {
      const int i = interior.child[k];
      indexOf[i] = childBase + uint32_t(k);
      nodeAt[i] = nextNode;
      primAt[i] = nextPrim;
      nextNode += subtree_[kids[i]].nodes - 1;
      nextPrim += subtree_[kids[i]].prims;
    }
    for_children(depth, interior, [&](int i) { emit(indexOf[i], kids[i], nodeAt[i], primAt[i], depth + 1); });
  }

  // The SAH collapse (Ylitie, Karras and Laine 2017, "Efficient incoherent
  // ray traversal on GPUs through compressed wide BVHs"): the wide tree of
  // least SAH cost that the binary tree's nodes can form, by dynamic
  // programming over it. cost(n, j) is the least cost of binary node n's
  // subtree as a forest of at most j roots, each a leaf (a subtree of at most
  // maxLeafSize primitives, merged) or a wide node (kNodeCost times its area,
  // plus its children as a forest of at most 8). Unlike the greedy collapse,
  // it weighs leaves against nodes: from a binary tree split down to single
  // primitives it picks the leaves too. Walk steps per ray barely moved with
  // the ratio of the two costs (0.5 to 2; docs/benchmarks.md).
  static constexpr float kNodeCost = 1.0f;
  static constexpr float kPrimCost = 1.0f;

  // cost(n, j) is kept for j up to 7 only: a node shares its wide node's
  // eight slots with at least its sibling's subtree.
  static constexpr int kMaxRoots = 7;

  // What solve decided for binary node n, packed into its plan word so that the
  // passes after it read one word per node instead of its children's costs:
  // bits 0-3 the primitives of a subtree that may become one leaf (0: it
  // may not), bit 4 whether that leaf is cheaper than a wide node, bits 5-7
  // how many roots the left child takes in a forest of 8 (a wide node's
  // children), and for a forest of at most j = 2..7 roots, four bits from
  // bit 8 + 4 (j - 2): whether n stays whole, and the left child's roots.
  static constexpr uint32_t kMergeWins = 1u << 4;
  static_assert(WIDE_MAX_LEAF_SIZE < 16, "a plan holds a leaf's primitive count in four bits");
  static uint32_t mergeable_of(uint32_t plan) { return plan & 15u; }
  uint32_t mergeable(uint32_t n) const { return mergeable_of(links_[n].plan); }
  static int forest_shift(int j) { return 8 + 4 * (j - 2); }
  int left_roots_of_eight(uint32_t n) const { return int((links_[n].plan >> 5) & 7u); }

  // Per binary node, its plan and where it leads, 8 bytes: the passes after
  // solve walk these instead of the 32-byte nodes, a quarter of the memory.
  // `link` is an interior node's first child, or a leaf's first primitive
  // with kLeafLink set; a leaf's plan holds its primitive count in bits 8-11.
  struct Link {
    uint32_t link, plan;
  };
  static constexpr uint32_t kLeafLink = 1u << 31;
  bool is_leaf_link(uint32_t n) const { return (links_[n].link & kLeafLink) != 0; }
  WideChild leaf_child(uint32_t n) const { return WideChild{n, false, links_[n].link & ~kLeafLink, (links_[n].plan >> 8) & 15u}; }
  // Interior node n as one leaf of its subtree's primitives (count 0 where it may not be one).
  WideChild merged_leaf(uint32_t n) const { return WideChild{n, false, first_prim(n), mergeable(n)}; }

  // What solve returns for a subtree: cost(n, 1..7), n's plan and its first
  // primitive in the order. Only the parent reads a node's costs, so they
  // pass up the recursion instead of through an array (7 floats per node:
  // 56 MB of fresh memory at 1M triangles).
  struct Solved {
    float cost[kMaxRoots];
    uint32_t plan;
    uint32_t first;
  };

  // Solves n's subtree and fills the plan of each of its nodes. A subtree
  // may become one leaf when it has at most maxLeafSize primitives,
  // contiguous in the order (tree rotations can interleave them).
  Solved solve(uint32_t n, int depth) {
    const BvhNode& node = nodes_[n];
    const float area = node_box(node).half_area();
    Solved out;
    if (is_leaf(node)) {
      if (node.count > WIDE_MAX_LEAF_SIZE) throw RenderError("internal error: a BVH leaf holds more primitives than a wide node's slot");
      out.plan = node.count <= maxLeafSize_ ? node.count : 0u;
      links_[n] = Link{node.leftFirst | kLeafLink, out.plan | node.count << 8};
      out.first = node.leftFirst;
      std::fill(out.cost, out.cost + kMaxRoots, kPrimCost * area * float(node.count));
      return out;
    }
    const uint32_t l = node.leftFirst, r = l + 1;
    Solved left, right;
    if (depth < kParallelSolveDepth) {
      tbb::task_group tasks;
      tasks.run([&] { left = solve(l, depth + 1); });
      right = solve(r, depth + 1);
      tasks.wait();
    } else {
      left = solve(l, depth + 1);
      right = solve(r, depth + 1);
    }
    // split[j]: the least cost of the two children as a forest of at most j
    // roots (the first split on ties), and the left child's roots in it.
    float split[9];
    uint32_t leftRoots[9];
#pragma GCC unroll 7
    for (int j = 2; j <= 8; ++j) {
      split[j] = std::numeric_limits<float>::infinity();
      leftRoots[j] = 1;
#pragma GCC unroll 7
      for (int k = 1; k < j; ++k) {
        const float sum = left.cost[k - 1] + right.cost[j - k - 1];
        const bool better = sum < split[j];
        leftRoots[j] = better ? uint32_t(k) : leftRoots[j];
        split[j] = better ? sum : split[j];
      }
    }
    const uint32_t mergeLeft = mergeable_of(left.plan), mergeRight = mergeable_of(right.plan);
    const uint32_t prims = mergeLeft + mergeRight;
    const bool contiguous = mergeLeft != 0 && mergeRight != 0 && right.first == left.first + mergeLeft;
    uint32_t plan = contiguous && prims <= maxLeafSize_ ? prims : 0u;
    const float asNode = kNodeCost * area + split[8];
    float single = asNode;
    if (plan != 0) {
      const float asLeaf = kPrimCost * area * float(prims);
      single = std::min(single, asLeaf);
      if (asLeaf <= asNode) plan |= kMergeWins;
    }
    plan |= leftRoots[8] << 5;
    out.cost[0] = single;
#pragma GCC unroll 6
    for (int j = 2; j <= kMaxRoots; ++j) {
      out.cost[j - 1] = std::min(single, split[j]);
      plan |= ((single <= split[j] ? 1u : 0u) | leftRoots[j] << 1) << forest_shift(j);
    }
    out.plan = plan;
    links_[n] = Link{l, plan};
    out.first = left.first;
    return out;
  }
  static constexpr int kParallelSolveDepth = 8;

  // The first primitive (in the order) of a subtree that may become one leaf.
  uint32_t first_prim(uint32_t n) const {
    while (!is_leaf_link(n)) n = links_[n].link;
    return links_[n].link & ~kLeafLink;
  }

  // Appends to `out` the roots of n's subtree as the forest of at most j
  // roots that cost(n, j) found, inside a wide node over `grid`. A node the
  // forest would open stays whole where opening it would widen an emitter
  // leaf (EmitterLeaves), as in the greedy collapse.
  void forest(uint32_t n, int j, const Aabb& grid, WideChild* out, int& count) const {
    if (is_leaf_link(n)) {
      out[count++] = leaf_child(n);
      return;
    }
    // A child of a subtree that the SAH may merge into a leaf counts as one.
    auto may_be_leaf = [this](uint32_t c, uint32_t& first, uint32_t& count) {
      const WideChild leaf = is_leaf_link(c) ? leaf_child(c) : merged_leaf(c);
      first = leaf.first;
      count = leaf.count;
      return count != 0;
    };
    const Link link = links_[n];
    const uint32_t decision = j == 1 ? 1u : link.plan >> forest_shift(j);
    const bool whole = (decision & 1u) != 0;
    const int leftRoots = int((decision >> 1) & 7u);
    // Kept whole for an emitter, it becomes a wide node over its own box.
    const bool forEmitter = !whole && emitters_.opening_widens(nodes_, nodes_[n], grid, may_be_leaf);
    if (whole || forEmitter) {
      const bool merged = !forEmitter && (link.plan & kMergeWins) != 0;
      out[count++] = merged ? merged_leaf(n) : WideChild{n, true, 0, 0};
      return;
    }
    forest(link.link, leftRoots, grid, out, count);
    forest(link.link + 1, j - leftRoots, grid, out, count);
  }

  // The children of the wide node that stands for binary node b.
  int children_of(uint32_t b, WideChild out[8]) const {
    int count = 0;
    if (how_ == WideCollapse::Sah && !is_leaf_link(b)) {
      const int leftRoots = left_roots_of_eight(b);
      // The node's box only matters to emitters (measure reads no node).
      const Aabb grid = emitters_.emits ? node_box(nodes_[b]) : Aabb();
      forest(links_[b].link, leftRoots, grid, out, count);
      forest(links_[b].link + 1, 8 - leftRoots, grid, out, count);
      return count;
    }
    uint32_t kids[8];
    count = collapse_children(nodes_, b, emitters_, kids);
    for (int i = 0; i < count; ++i) {
      const BvhNode& c = nodes_[kids[i]];
      out[i] = is_leaf(c) ? WideChild{kids[i], false, c.leftFirst, c.count} : WideChild{kids[i], true, 0, 0};
    }
    return count;
  }

  const BvhNode* nodes_;
  const uint32_t* order_;
  EmitterLeaves emitters_;
  WideCollapse how_;
  uint32_t maxLeafSize_;
  // Per binary node that becomes a wide node, the size of its wide subtree
  // (the two words side by side: emit reads both, at a cache miss).
  struct SubtreeSize {
    uint32_t nodes, prims;
  };
  WorkArray<SubtreeSize> subtree_;
  WorkArray<Link> links_;                      // per binary node: what solve decided, and its links (the SAH collapse)
  WideBvh* out_ = nullptr;
};

}  // namespace

namespace {

WideBvh collapse(const BvhNode* nodes, size_t slotCount, const uint32_t* order, size_t primitives, const std::vector<uint8_t>& emits,
                 double sahCost, WideCollapse how, int maxLeafSize) {
  if (!emits.empty() && emits.size() != primitives) throw RenderError("internal error: emitter flags for a different set of primitives");
  const auto start = std::chrono::steady_clock::now();
  WideBvh out;
  if (primitives == 0) {
    out.nodes.resize(1);  // a root without children: every ray misses
    out.depth = 1;
  } else {
    out = Collapser(nodes, slotCount, order, emits.empty() ? nullptr : emits.data(), how, uint32_t(std::max(maxLeafSize, 1))).run();
  }
  out.sahCost = sahCost;
  out.collapseSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

WideBvh collapse_to_wide(const Bvh& binary, const std::vector<uint8_t>& emits, WideCollapse how, int maxLeafSize) {
  return collapse(binary.nodes.data(), binary.nodes.size(), binary.order.data(), binary.order.size(), emits, binary.sahCost,
                  how, maxLeafSize);
}

AcceleratorSettings binary_settings_for_wide(const AcceleratorSettings& settings, WideCollapse how) {
  AcceleratorSettings binary = settings;
  binary.maxLeafSize = how == WideCollapse::Sah ? 1 : std::min(settings.maxLeafSize, WIDE_MAX_LEAF_SIZE);
  return binary;
}

WideBvh build_wide_bvh(const BvhInput& input, const AcceleratorSettings& settings, WideCollapse how) {
  WideBvh out;
  build_bvh_slots(input, binary_settings_for_wide(settings, how), [&](const BvhSlots& tree) {
    out = collapse(tree.nodes, tree.slotCount, tree.order, tree.primitiveCount, input.emits, tree.sahCost, how,
                   settings.maxLeafSize);
  });
  return out;
}

double wide_sah_cost(const std::vector<WideNode>& nodes) {
  // A node's area (its box is the union of its children's, the root's too)
  // and its leaves' areas times their primitives, each child decoded once.
  auto node_terms = [](const WideNode& n, double& area, double& leaves) {
    Aabb all;
    leaves = 0.0;
    for (int slot = 0; slot < 8; ++slot) {
      const uint32_t meta = get_byte(slot < 4 ? n.meta0123 : n.meta4567, slot % 4);
      if (meta == 0) continue;  // empty
      const Aabb box = wide_child_box(n, slot);
      all.grow(box);
      if (((n.exyzImask >> (24 + slot)) & 1u) == 0u) leaves += double(box.half_area()) * double(__builtin_popcount(meta >> 5));
    }
    area = all.empty() ? 0.0 : double(all.half_area());
  };
  double rootArea, rootLeaves;
  node_terms(nodes[0], rootArea, rootLeaves);
  rootArea = std::max(rootArea, 1e-30);
  double cost = 0.0;
  for (const WideNode& n : nodes) {
    double area, leaves;
    node_terms(n, area, leaves);
    cost += (area + leaves) / rootArea;
  }
  return cost;
}

}  // namespace wp
