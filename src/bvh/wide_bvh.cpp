#include "bvh/wide_bvh.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "util/error.h"

namespace wp {

namespace {

using shader::BvhNode;
using shader::WideNode;

Aabb box_of(const BvhNode& n) {
  Aabb b;
  b.lo = n.bmin;
  b.hi = n.bmax;
  return b;
}

bool is_leaf(const BvhNode& n) {
  return n.count != 0;
}

// Up to eight descendants of binary node `root`, the children of one wide
// node: starting from root's two children, the interior one of largest
// surface area is replaced by its two children until there are eight or none
// is interior. A root that is itself a leaf becomes a wide node's only child.
int collapse_children(const std::vector<BvhNode>& nodes, uint32_t root, uint32_t out[8]) {
  const BvhNode& r = nodes[root];
  if (is_leaf(r)) {
    out[0] = root;
    return 1;
  }
  int n = 2;
  out[0] = r.leftFirst;
  out[1] = r.leftFirst + 1;
  while (n < 8) {
    int best = -1;
    float bestArea = -1.0f;
    for (int i = 0; i < n; ++i) {
      const BvhNode& c = nodes[out[i]];
      float area = box_of(c).half_area();
      if (!is_leaf(c) && area > bestArea) {
        bestArea = area;
        best = i;
      }
    }
    if (best < 0) break;
    uint32_t expanded = out[best];
    out[best] = nodes[expanded].leftFirst;
    out[n++] = nodes[expanded].leftFirst + 1;
  }
  return n;
}

// Slot of each child. Slot s stands for the octant with sign bits s (bit a
// set: towards -a); the child lying furthest towards an octant, seen from the
// node's centre, takes that octant's slot, greedily, best pair first. The
// walk visits slots in an order its ray's octant gives (see WideNode).
void assign_slots(const Aabb* boxes, int n, int slotOf[8]) {
  Aabb all;
  for (int i = 0; i < n; ++i) all.grow(boxes[i]);
  glm::vec3 centre = 0.5f * (all.lo + all.hi);
  float score[8][8];
  for (int c = 0; c < n; ++c) {
    glm::vec3 offset = 0.5f * (boxes[c].lo + boxes[c].hi) - centre;
    for (int s = 0; s < 8; ++s) {
      glm::vec3 dir((s & 1) ? -1.0f : 1.0f, (s & 2) ? -1.0f : 1.0f, (s & 4) ? -1.0f : 1.0f);
      score[c][s] = glm::dot(offset, dir);
    }
  }
  bool childDone[8] = {}, slotTaken[8] = {};
  for (int k = 0; k < n; ++k) {
    int bestC = -1, bestS = -1;
    for (int c = 0; c < n; ++c)
      for (int s = 0; s < 8; ++s)
        if (!childDone[c] && !slotTaken[s] && (bestC < 0 || score[c][s] > score[bestC][bestS])) {
          bestC = c;
          bestS = s;
        }
    childDone[bestC] = slotTaken[bestS] = true;
    slotOf[bestC] = bestS;
  }
}

// The power-of-two cell size per axis (as the biased exponent stored in the
// node) such that 255 cells span [lo, hi].
uint32_t cell_exponent(float lo, float hi) {
  double extent = double(hi) - double(lo);
  int e = -126;
  if (extent > 0.0) {
    e = std::max(-126, int(std::ceil(std::log2(extent / 255.0))));
    while (std::ldexp(255.0, e) < extent) ++e;  // log2 may round down
  }
  return uint32_t(std::min(e, 127) + 127);
}

float cell_size(uint32_t biasedExponent) {
  return std::ldexp(1.0f, int(biasedExponent) - 127);
}

// Quantized planes of [lo, hi] on the grid origin + q * cell, rounded
// outwards and checked in float as the decoding computes them.
std::pair<uint32_t, uint32_t> quantize(float lo, float hi, float origin, float cell) {
  int qlo = std::clamp(int(std::floor((double(lo) - double(origin)) / double(cell))), 0, 255);
  int qhi = std::clamp(int(std::ceil((double(hi) - double(origin)) / double(cell))), 0, 255);
  while (qlo > 0 && origin + float(qlo) * cell > lo) --qlo;
  while (qhi < 255 && origin + float(qhi) * cell < hi) ++qhi;
  return {uint32_t(qlo), uint32_t(qhi)};
}

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

WideBvh collapse_to_wide(const Bvh& binary) {
  WideBvh out;
  out.nodes.resize(1);
  out.depth = 1;
  if (binary.order.empty()) return out;  // a root without children: every ray misses
  out.order.reserve(binary.order.size());
  // Depth first, with an explicit stack: (wide node to fill, binary node it
  // stands for, its depth). A node's interior children are allocated together,
  // so they are consecutive as the layout requires.
  std::vector<std::tuple<uint32_t, uint32_t, int>> todo{{0u, 0u, 1}};
  while (!todo.empty()) {
    auto [wideIndex, binaryIndex, depth] = todo.back();
    todo.pop_back();
    out.depth = std::max(out.depth, depth);
    uint32_t kids[8];
    int n = collapse_children(binary.nodes, binaryIndex, kids);
    Aabb boxes[8], all;
    for (int i = 0; i < n; ++i) {
      boxes[i] = box_of(binary.nodes[kids[i]]);
      all.grow(boxes[i]);
    }
    int slotOf[8];
    assign_slots(boxes, n, slotOf);
    int childInSlot[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
    for (int i = 0; i < n; ++i) childInSlot[slotOf[i]] = i;

    WideNode node{};
    node.origin = all.lo;
    uint32_t cells[3];
    for (int a = 0; a < 3; ++a) {
      cells[a] = cell_exponent(all.lo[a], all.hi[a]);
      set_byte(node.exyzImask, a, cells[a]);
    }
    node.childBase = uint32_t(out.nodes.size());
    node.primBase = uint32_t(out.order.size());
    uint32_t imask = 0, interior = 0, offset = 0;
    for (int s = 0; s < 8; ++s) {
      int i = childInSlot[s];
      if (i < 0) continue;  // empty slot: meta 0, no bits
      for (int a = 0; a < 3; ++a) {
        auto [qlo, qhi] = quantize(boxes[i].lo[a], boxes[i].hi[a], node.origin[a], cell_size(cells[a]));
        set_byte(plane_words(node, a, false)[s / 4], s % 4, qlo);
        set_byte(plane_words(node, a, true)[s / 4], s % 4, qhi);
      }
      const BvhNode& child = binary.nodes[kids[i]];
      uint32_t meta;
      if (!is_leaf(child)) {
        imask |= 1u << s;
        meta = (1u << 5) | (24u + uint32_t(s));
        todo.emplace_back(node.childBase + interior, kids[i], depth + 1);
        ++interior;
      } else {
        uint32_t count = child.count;
        if (count > WIDE_MAX_LEAF_SIZE) throw RenderError("internal error: a BVH leaf holds more primitives than a wide node's slot");
        meta = (((1u << count) - 1u) << 5) | offset;
        out.order.insert(out.order.end(), binary.order.begin() + child.leftFirst, binary.order.begin() + child.leftFirst + count);
        offset += count;
      }
      set_byte(s < 4 ? node.meta0123 : node.meta4567, s % 4, meta);
    }
    set_byte(node.exyzImask, 3, imask);
    out.nodes.resize(out.nodes.size() + interior);
    out.nodes[wideIndex] = node;
  }
  return out;
}

}  // namespace wp
