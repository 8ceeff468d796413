#include "bvh/bvh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <tuple>

#ifdef __SSE2__
#include <emmintrin.h>
#define WP_BVH_SSE 1
#endif

#include "util/huge_pages.h"

namespace wp {

namespace {

constexpr int kBins = 32;
constexpr uint32_t kParallelThreshold = 1u << 14;  // subtrees / ranges below this stay on one thread
constexpr float kTraversalCost = 1.0f;
constexpr float kIntersectCost = 1.0f;

// Four floats with the few operations the builder needs: SSE on x86-64, plain
// arrays elsewhere. Lane 3 is unused.
#ifdef WP_BVH_SSE
struct F4 {
  __m128 v;
  static F4 load(const float* p) { return {_mm_loadu_ps(p)}; }
  static F4 splat(float x) { return {_mm_set1_ps(x)}; }
  void store(float* p) const { _mm_storeu_ps(p, v); }
  friend F4 min(F4 a, F4 b) { return {_mm_min_ps(a.v, b.v)}; }
  friend F4 max(F4 a, F4 b) { return {_mm_max_ps(a.v, b.v)}; }
  friend F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
  friend F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend F4 operator*(F4 a, F4 b) { return {_mm_mul_ps(a.v, b.v)}; }
  // a where m, else b.
  static F4 select(bool m, F4 a, F4 b) {
    const __m128 mask = _mm_castsi128_ps(_mm_set1_epi32(-int(m)));
    return {_mm_or_ps(_mm_and_ps(mask, a.v), _mm_andnot_ps(mask, b.v))};
  }
  // Bin indices: x clamped below to 0 (NaN too), truncated.
  void bins(int out[4]) const {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(_mm_max_ps(v, _mm_setzero_ps())));
  }
};
#else
struct F4 {
  float v[4];
  static F4 load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
  static F4 splat(float x) { return {{x, x, x, x}}; }
  void store(float* p) const { std::memcpy(p, v, sizeof(v)); }
  template <typename Op>
  static F4 each(F4 a, F4 b, Op op) { return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}}; }
  friend F4 min(F4 a, F4 b) { return each(a, b, [](float x, float y) { return std::min(x, y); }); }
  friend F4 max(F4 a, F4 b) { return each(a, b, [](float x, float y) { return std::max(x, y); }); }
  friend F4 operator+(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x + y; }); }
  friend F4 operator-(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x - y; }); }
  friend F4 operator*(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x * y; }); }
  static F4 select(bool m, F4 a, F4 b) { return m ? a : b; }
  void bins(int out[4]) const {
    for (int k = 0; k < 4; ++k) out[k] = int(v[k] > 0.0f ? v[k] : 0.0f);
  }
};
#endif

// A primitive's bounds and id, 32 bytes; the builder partitions an array of
// these in place, so every pass over a node's primitives reads memory in order.
struct alignas(16) PrimRef {
  float lo[3];
  uint32_t id;
  float hi[3];
  uint32_t pad;
  F4 lo4() const { return F4::load(lo); }
  F4 hi4() const { return F4::load(hi); }
  F4 centroid2() const { return lo4() + hi4(); }  // twice the centroid: binning only needs its order
};

// Bounds as two F4, empty when lo > hi.
struct Box4 {
  F4 lo = F4::splat(3.0e38f);
  F4 hi = F4::splat(-3.0e38f);
  void grow(F4 l, F4 h) {
    lo = min(lo, l);
    hi = max(hi, h);
  }
  void grow(const Box4& b) { grow(b.lo, b.hi); }
  Aabb aabb() const {
    float l[4], h[4];
    lo.store(l);
    hi.store(h);
    Aabb a;
    a.lo = glm::vec3(l[0], l[1], l[2]);
    a.hi = glm::vec3(h[0], h[1], h[2]);
    return a;
  }
  float half_area() const {
    float d[4];
    (hi - lo).store(d);
    return d[0] > 0.0f ? d[0] * d[1] + d[1] * d[2] + d[2] * d[0] : 0.0f;  // empty: lo > hi
  }
};

// Per axis and bin: bounds and count of the primitives whose centroid falls
// in it. Only the first `used` bins of each axis are initialized and read: a
// node of a few primitives gets as few bins, so small nodes (most of the tree)
// cost little besides their primitives.
struct Bins {
  int used;
  Box4 box[3][kBins];
  uint32_t count[3][kBins];
  explicit Bins(int n = kBins) : used(n) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < used; ++b) {
        box[a][b] = Box4();
        count[a][b] = 0;
      }
  }
  void join(const Bins& o) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < used; ++b) {
        box[a][b].grow(o.box[a][b]);
        count[a][b] += o.count[a][b];
      }
  }
};

// Bins for a node of `count` primitives: one per primitive up to kBins.
int bins_for(uint32_t count) {
  return int(std::clamp<uint32_t>(count, 4, kBins));
}

// How a node's centroids map to bins: bin = (centroid2 - origin) * scale,
// clamped to the last bin.
struct Binning {
  F4 origin, scale, last;
  float scaleOf[3];
  Binning(const Box4& centroids, int bins) {
    origin = centroids.lo;
    last = F4::splat(float(bins - 1));
    float lo[4], hi[4], s[4] = {0, 0, 0, 0};
    centroids.lo.store(lo);
    centroids.hi.store(hi);
    for (int a = 0; a < 3; ++a) {
      float extent = hi[a] - lo[a];
      // Slightly under bins / extent so the largest centroid lands in the last bin.
      s[a] = extent > 0.0f ? float(bins) * (1.0f - 1e-6f) / extent : 0.0f;
      scaleOf[a] = s[a];
    }
    scale = F4::load(s);
  }
  void of(const PrimRef& r, int out[4]) const { min((r.centroid2() - origin) * scale, last).bins(out); }
  // Lane `a` of of(): the same operations in the same order, so the same bin.
  int on_axis(const PrimRef& r, int a, float o, float lastBin) const {
    float t = ((r.lo[a] + r.hi[a]) - o) * scaleOf[a];
    t = t < lastBin ? t : lastBin;
    return int(t > 0.0f ? t : 0.0f);
  }
};

// A float's bits as an unsigned integer that sorts in the float's order,
// -0 before +0 and NaNs at the ends: a total order, so that sorting by
// centroid stays well defined however wrong the bounds.
uint32_t sort_key(float x) {
  uint32_t u;
  std::memcpy(&u, &x, sizeof(u));
  return u ^ (uint32_t(int32_t(u) >> 31) | 0x80000000u);
}

// A node's share of its tree's SAH cost: its area relative to the root's,
// times the cost of visiting it (interior) or testing its primitives (leaf).
double sah_term(const shader::BvhNode& n, double rootArea) {
  const double rel = double(node_box(n).half_area()) / rootArea;
  return n.count == 0 ? kTraversalCost * rel : kIntersectCost * rel * double(n.count);
}

int largest_axis(glm::vec3 extent) {
  return extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
}

// A node to build: its primitives [begin, end) in reference array `buf` (0
// or 1, see Builder), with their bounds and the bounds of their centroids
// (doubled, as PrimRef::centroid2).
struct Task {
  uint32_t node, begin, end;
  int depth;
  int buf;
  Box4 bounds, centroids;
};

// Top-down binned SAH. The primitive references live in two arrays: a node's
// split copies its references from its array into the other one (left
// children from the front, right ones from the back), so each partition is a
// branch-free stream, and a large node's partition runs in parallel by
// chunks. Leaves write their primitive ids straight into the tree's order.
class Builder {
 public:
  Builder(const BvhInput& in, const AcceleratorSettings& s)
      : settings_(s),
        n_(in.bounds.size()),
        refs0_(n_),
        refs1_(n_),
        nodes_(2 * n_ + max_chains(n_) * kNodeBlock) {
    refs_[0] = refs0_.get();
    refs_[1] = refs1_.get();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n_, 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const Aabb& b = in.bounds[i];
        refs_[0][i] = PrimRef{{b.lo.x, b.lo.y, b.lo.z}, uint32_t(i), {b.hi.x, b.hi.y, b.hi.z}, 0u};
      }
    });
  }

  // An empty scene's tree: an interior root with an empty box, which every
  // ray misses before any child is read.
  static shader::BvhNode empty_root() {
    shader::BvhNode root{};
    root.bmin = Aabb().lo;
    root.bmax = Aabb().hi;
    return root;
  }

  Bvh build() {
    Bvh bvh;
    if (n_ == 0) {
      bvh.nodes.push_back(empty_root());
      return bvh;
    }
    reserve_huge(bvh.order, n_);
    bvh.order.resize(n_);
    build_tree(bvh.order.data());
    compact_nodes(bvh);
    return bvh;
  }

  void build_slots(const std::function<void(const BvhSlots&)>& use) {
    if (n_ == 0) {
      const shader::BvhNode root = empty_root();
      use(BvhSlots{&root, 1, nullptr, 0, 0, 0.0});
      return;
    }
    WorkArray<uint32_t> order(n_);
    build_tree(order.get());
    const double rootArea = std::max(double(node_box(nodes_[0]).half_area()), 1e-30);
    const Measure m = measure(0, 0, rootArea);
    use(BvhSlots{nodes_.get(), nodeCount_.load(), order.get(), n_, m.depth, m.sahCost});
  }

 private:
  static constexpr uint32_t kChunk = 1u << 13;  // primitives per chunk of a parallel pass
  static uint32_t chunks_of(const Task& t) { return (t.end - t.begin + kChunk - 1) / kChunk; }
  // The primitives [begin, end) of task t's chunk c.
  static std::pair<uint32_t, uint32_t> chunk(const Task& t, uint32_t c) {
    const uint32_t begin = t.begin + c * kChunk;
    return {begin, std::min(t.end, begin + kChunk)};
  }

  // Node slots are handed out in blocks, one block at a time to each chain of
  // build_node calls (the root's, and each spawned task's), so threads do not
  // contend for a shared counter at every node. Every chain leaves at most
  // one partly used block: nodes_ has room for 2n nodes and one block more
  // per chain. The unused slots are dropped by compact_nodes.
  static constexpr uint32_t kNodeBlock = 32;
  // Chains: the root's, and one per node of at least kParallelThreshold
  // primitives that is split. Such nodes at one depth are disjoint, so there
  // are at most n / kParallelThreshold per depth, and BVH_MAX_DEPTH depths.
  static size_t max_chains(size_t n) { return 1 + size_t(BVH_MAX_DEPTH + 1) * (n / kParallelThreshold + 1); }
  struct NodeBlock {
    uint32_t next = 0, end = 0;
  };
  // Builds the tree into nodes_, writing the leaves' primitive ids to `order`.
  void build_tree(uint32_t* order) {
    order_ = order;
    Task root{0, 0, uint32_t(n_), 0, 0, {}, {}};
    bounds_of(root);
    nodeCount_ = 1;
    tbb::task_group tasks;
    NodeBlock block;
    build_node(root, tasks, block);
    tasks.wait();
  }

  // SAH cost and depth of the subtree at slot i (at depth `depth`), straight
  // from the slots; the top levels' subtrees in parallel, their sums joined in
  // a fixed order so that the result does not depend on the threads.
  struct Measure {
    double sahCost;
    int depth;
  };
  Measure measure(uint32_t i, int depth, double rootArea) const {
    const shader::BvhNode& n = nodes_[i];
    if (n.count != 0) return {sah_term(n, rootArea), depth};
    Measure l, r;
    auto left = [&] { l = measure(n.leftFirst, depth + 1, rootArea); };
    auto right = [&] { r = measure(n.leftFirst + 1, depth + 1, rootArea); };
    if (depth < 6) {
      tbb::parallel_invoke(left, right);
    } else {
      left();
      right();
    }
    return {sah_term(n, rootArea) + l.sahCost + r.sahCost, std::max(l.depth, r.depth)};
  }

  // Two adjacent node slots, for a node's children.
  uint32_t allocate_pair(NodeBlock& block) {
    if (block.next == block.end) {
      block.next = nodeCount_.fetch_add(kNodeBlock, std::memory_order_relaxed);
      block.end = block.next + kNodeBlock;
    }
    uint32_t at = block.next;
    block.next += 2;
    return at;
  }

  // The tree's nodes in depth-first order (siblings still adjacent), without
  // the unused slots; also measures its depth.
  void compact_nodes(Bvh& bvh) const {
    reserve_huge(bvh.nodes, std::min<size_t>(nodeCount_.load(), 2 * n_));
    bvh.nodes.push_back(nodes_[0]);
    struct Visit {
      uint32_t from, to;
      int depth;
    };
    std::vector<Visit> stack{{0, 0, 0}};
    int depth = 0;
    while (!stack.empty()) {
      Visit v = stack.back();
      stack.pop_back();
      const shader::BvhNode& n = nodes_[v.from];
      if (n.count != 0) {
        depth = std::max(depth, v.depth);
        continue;
      }
      const uint32_t at = uint32_t(bvh.nodes.size());
      bvh.nodes.push_back(nodes_[n.leftFirst]);
      bvh.nodes.push_back(nodes_[n.leftFirst + 1]);
      bvh.nodes[v.to].leftFirst = at;
      stack.push_back({n.leftFirst + 1, at + 1, v.depth + 1});
      stack.push_back({n.leftFirst, at, v.depth + 1});
    }
    bvh.depth = depth;
  }

  // Bounds and centroid bounds of a task's primitives, in parallel when large.
  void bounds_of(Task& t) const {
    struct Acc {
      Box4 b, c;
      void join(const Acc& o) {
        b.grow(o.b);
        c.grow(o.c);
      }
    };
    const PrimRef* refs = refs_[t.buf];
    auto body = [refs](const tbb::blocked_range<uint32_t>& r, Acc acc) {
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        F4 c = refs[i].centroid2();
        acc.b.grow(refs[i].lo4(), refs[i].hi4());
        acc.c.grow(c, c);
      }
      return acc;
    };
    Acc acc = t.end - t.begin < kParallelThreshold
                  ? body(tbb::blocked_range<uint32_t>(t.begin, t.end), Acc{})
                  : tbb::parallel_reduce(tbb::blocked_range<uint32_t>(t.begin, t.end, kChunk), Acc{}, body,
                                         [](Acc a, const Acc& b) {
                                           a.join(b);
                                           return a;
                                         });
    t.bounds = acc.b;
    t.centroids = acc.c;
  }

  static void bin_range(const PrimRef* refs, uint32_t begin, uint32_t end, const Binning& binning, Bins& acc) {
    for (uint32_t i = begin; i < end; ++i) {
      const PrimRef& p = refs[i];
      int b[4];
      binning.of(p, b);
      F4 lo = p.lo4(), hi = p.hi4();
      for (int a = 0; a < 3; ++a) {
        acc.box[a][b[a]].grow(lo, hi);
        acc.count[a][b[a]]++;
      }
    }
  }

  // Copies src[begin, end) into dst: those satisfying `left` upwards from
  // `leftAt`, the others downwards from `rightEnd`, without branches on the
  // outcome (half of them would be mispredicted); grows both sides' centroid
  // bounds. Returns how many went left.
  template <typename Left>
  static uint32_t partition_range(const PrimRef* src, PrimRef* dst, uint32_t begin, uint32_t end, uint32_t leftAt,
                                  uint32_t rightEnd, Left left, Box4& leftCentroids, Box4& rightCentroids) {
    F4 lLo = leftCentroids.lo, lHi = leftCentroids.hi, rLo = rightCentroids.lo, rHi = rightCentroids.hi;
    const F4 big = F4::splat(3.0e38f), small = F4::splat(-3.0e38f);
    uint32_t l = leftAt, r = rightEnd;
    for (uint32_t i = begin; i < end; ++i) {
      const PrimRef& p = src[i];
      const bool isLeft = left(p);
      dst[isLeft ? l : r - 1] = p;
      l += isLeft;
      r -= !isLeft;
      F4 c = p.centroid2();
      lLo = min(lLo, F4::select(isLeft, c, big));
      lHi = max(lHi, F4::select(isLeft, c, small));
      rLo = min(rLo, F4::select(isLeft, big, c));
      rHi = max(rHi, F4::select(isLeft, small, c));
    }
    leftCentroids = Box4{lLo, lHi};
    rightCentroids = Box4{rLo, rHi};
    return l - leftAt;
  }

  // Splits task t's primitives by `left` into the other array: fills in the
  // children's ranges, arrays and centroid bounds. Large tasks run by chunks
  // in parallel; `leftOfChunk`, when given, already holds how many of each
  // chunk's primitives go left.
  template <typename Left>
  void split_by(const Task& t, Task& l, Task& r, Left left, std::vector<uint32_t>* leftOfChunk = nullptr) {
    const PrimRef* src = refs_[t.buf];
    PrimRef* dst = refs_[t.buf ^ 1];
    l.buf = r.buf = t.buf ^ 1;
    l.begin = t.begin;
    r.end = t.end;
    const uint32_t count = t.end - t.begin;
    if (count < kParallelThreshold) {
      l.end = r.begin = t.begin + partition_range(src, dst, t.begin, t.end, t.begin, t.end, left, l.centroids, r.centroids);
      return;
    }
    const uint32_t chunks = chunks_of(t);
    std::vector<uint32_t> counted;
    if (!leftOfChunk) {
      counted.resize(chunks);
      tbb::parallel_for(uint32_t(0), chunks, [&](uint32_t c) {
        auto [b, e] = chunk(t, c);
        uint32_t n = 0;
        for (uint32_t i = b; i < e; ++i) n += left(src[i]);
        counted[c] = n;
      });
      leftOfChunk = &counted;
    }
    // Chunk c's left primitives go after those of the chunks before it; its
    // right ones below those of the chunks before it.
    std::vector<uint32_t> leftAt(chunks), rightEnd(chunks);
    uint32_t lsum = 0, rsum = 0;
    for (uint32_t c = 0; c < chunks; ++c) {
      auto [b, e] = chunk(t, c);
      const uint32_t n = e - b;
      leftAt[c] = t.begin + lsum;
      rightEnd[c] = t.end - rsum;
      lsum += (*leftOfChunk)[c];
      rsum += n - (*leftOfChunk)[c];
    }
    std::vector<Box4> lc(chunks), rc(chunks);
    tbb::parallel_for(uint32_t(0), chunks, [&](uint32_t c) {
      auto [b, e] = chunk(t, c);
      partition_range(src, dst, b, e, leftAt[c], rightEnd[c], left, lc[c], rc[c]);
    });
    for (uint32_t c = 0; c < chunks; ++c) {
      l.centroids.grow(lc[c]);
      r.centroids.grow(rc[c]);
    }
    l.end = r.begin = t.begin + lsum;
  }

  // The median split on `axis` (nth_element on centroids, in the task's own
  // array), with both halves' bounds computed afterwards.
  void median_split(const Task& t, Task& l, Task& r, int axis) {
    PrimRef* refs = refs_[t.buf];
    uint32_t mid = t.begin + (t.end - t.begin) / 2;
    std::nth_element(refs + t.begin, refs + mid, refs + t.end, [axis](const PrimRef& a, const PrimRef& b) {
      return sort_key(a.lo[axis] + a.hi[axis]) < sort_key(b.lo[axis] + b.hi[axis]);
    });
    l.buf = r.buf = t.buf;
    l.begin = t.begin;
    l.end = r.begin = mid;
    r.end = t.end;
    bounds_of(l);
    bounds_of(r);
  }

  void make_leaf(const Task& t) {
    shader::BvhNode& n = nodes_[t.node];
    n.leftFirst = t.begin;
    n.count = t.end - t.begin;
    const PrimRef* refs = refs_[t.buf];
    for (uint32_t i = t.begin; i < t.end; ++i) order_[i] = refs[i].id;
  }

  void build_node(Task t, tbb::task_group& tasks, NodeBlock& block) {
    Aabb box = t.bounds.aabb();
    nodes_[t.node].bmin = box.lo;
    nodes_[t.node].bmax = box.hi;
    const uint32_t count = t.end - t.begin;
    const uint32_t maxLeaf = uint32_t(settings_.maxLeafSize);
    if (count == 1) return make_leaf(t);

    Aabb cb = t.centroids.aabb();
    glm::vec3 extent = cb.hi - cb.lo;
    int axis = largest_axis(extent);
    Task l{0, 0, 0, t.depth + 1, t.buf, {}, {}}, r = l;
    // Near the depth limit only halving splits are allowed: 32 of them separate
    // any number of primitives a 32-bit index can hold, so the tree (and the
    // kernels' traversal stack) never exceeds BVH_MAX_DEPTH.
    bool forceMedian = t.depth >= BVH_MAX_DEPTH - 33;
    if (extent[axis] <= 0.0f) {
      // Identical centroids: any halving will do.
      if (count <= maxLeaf) return make_leaf(t);
      median_split(t, l, r, axis);
    } else if (forceMedian || settings_.split == SplitMethod::Equal) {
      if (count <= maxLeaf) return make_leaf(t);
      median_split(t, l, r, axis);
    } else if (settings_.split == SplitMethod::Middle) {
      if (count <= maxLeaf) return make_leaf(t);
      float m = 0.5f * (cb.lo[axis] + cb.hi[axis]);  // the middle of the (doubled) centroids
      split_by(t, l, r, [axis, m](const PrimRef& p) { return p.lo[axis] + p.hi[axis] < m; });
      if (l.end == t.begin || l.end == t.end) {
        Task moved = t;  // the references are in the other array now
        moved.buf ^= 1;
        median_split(moved, l, r, axis);
      } else {
        bounds_of(l);
        bounds_of(r);
      }
    } else if (!(count <= kSweepMax ? sweep_split(t, l, r) : sah_split(t, l, r))) {
      return make_leaf(t);
    }

    uint32_t left = allocate_pair(block);
    nodes_[t.node].leftFirst = left;
    nodes_[t.node].count = 0;
    l.node = left;
    r.node = left + 1;
    if (count >= kParallelThreshold) {
      tasks.run([this, l, &tasks] {
        NodeBlock own;
        build_node(l, tasks, own);
      });
    } else {
      build_node(l, tasks, block);
    }
    build_node(r, tasks, block);
  }

  // Whether task t should be a leaf rather than split at `splitArea` (the
  // children's areas weighted by their primitive counts): a leaf must be
  // allowed (at most maxLeafSize primitives) and no dearer than the split.
  bool leaf_is_better(const Task& t, float splitArea) const {
    const uint32_t count = t.end - t.begin;
    const float splitCost = kTraversalCost + kIntersectCost * splitArea / std::max(t.bounds.half_area(), 1e-30f);
    return count <= uint32_t(settings_.maxLeafSize) && splitCost >= kIntersectCost * float(count);
  }

  // Nodes of at most kSweepMax primitives, most of the tree's nodes, take the
  // exact SAH split instead of binning: per axis, the primitives sorted by
  // centroid and every split of that order swept. Binning such a node cost
  // 100-150 cycles per primitive, mostly fixed costs of the bins; this costs
  // less and finds the best split binning only approximates.
  static constexpr uint32_t kSweepMax = 16;

  bool sweep_split(const Task& t, Task& l, Task& r) {
    const uint32_t count = t.end - t.begin;
    const PrimRef* src = refs_[t.buf] + t.begin;
    uint8_t order[3][kSweepMax];
    float best = WP_INF;
    int bestAxis = -1;
    uint32_t bestLeftCount = 0;
    Box4 bestLeft, bestRight;
    for (int a = 0; a < 3; ++a) {
      uint32_t key[kSweepMax];
      uint8_t* o = order[a];
      for (uint32_t i = 0; i < count; ++i) key[i] = sort_key(src[i].lo[a] + src[i].hi[a] + 0.0f);  // + 0: -0 becomes +0
      // Sorted by centroid, ties in their order: each primitive's place is
      // the number before it, counted without branches (an insertion sort's
      // mispredicted comparisons cost more for these few).
      for (uint32_t i = 0; i < count; ++i) {
        uint32_t rank = 0;
        for (uint32_t j = 0; j < count; ++j) rank += uint32_t(key[j] < key[i]) + uint32_t((key[j] == key[i]) & (j < i));
        o[rank] = uint8_t(i);
      }
      Box4 right[kSweepMax];
      Box4 acc;
      for (uint32_t k = count - 1; k > 0; --k) {
        acc.grow(src[o[k]].lo4(), src[o[k]].hi4());
        right[k] = acc;
      }
      acc = Box4();
      for (uint32_t k = 1; k < count; ++k) {  // k primitives on the left
        acc.grow(src[o[k - 1]].lo4(), src[o[k - 1]].hi4());
        float cost = acc.half_area() * float(k) + right[k].half_area() * float(count - k);
        if (cost < best) {
          best = cost;
          bestAxis = a;
          bestLeftCount = k;
          bestLeft = acc;
          bestRight = right[k];
        }
      }
    }
    if (bestAxis < 0) {  // no split has a finite cost: the bounds are not finite
      if (count <= uint32_t(settings_.maxLeafSize)) return false;
      median_split(t, l, r, 0);
      return true;
    }
    if (leaf_is_better(t, best)) return false;
    // The children, in sorted order, into the other array.
    PrimRef* dst = refs_[t.buf ^ 1] + t.begin;
    for (uint32_t i = 0; i < count; ++i) {
      dst[i] = src[order[bestAxis][i]];
      F4 c = dst[i].centroid2();
      (i < bestLeftCount ? l : r).centroids.grow(c, c);
    }
    l.buf = r.buf = t.buf ^ 1;
    l.begin = t.begin;
    l.end = r.begin = t.begin + bestLeftCount;
    r.end = t.end;
    l.bounds = bestLeft;
    r.bounds = bestRight;
    return true;
  }

  // Binned SAH over all three axes. Fills the children and returns true, or
  // returns false when a leaf is cheaper (and allowed).
  bool sah_split(Task& t, Task& l, Task& r) {
    const uint32_t count = t.end - t.begin;
    const uint32_t maxLeaf = uint32_t(settings_.maxLeafSize);
    const int nb = bins_for(count);
    const PrimRef* src = refs_[t.buf];
    Binning binning(t.centroids, nb);
    Bins bins(nb);
    // A large node is binned by chunks in parallel; each chunk's bins are kept,
    // so its count of primitives going left is known without another pass.
    std::vector<Bins> chunkBins;
    if (count < kParallelThreshold) {
      bin_range(src, t.begin, t.end, binning, bins);
    } else {
      chunkBins.assign(chunks_of(t), Bins(nb));
      tbb::parallel_for(uint32_t(0), chunks_of(t), [&](uint32_t c) {
        auto [b, e] = chunk(t, c);
        bin_range(src, b, e, binning, chunkBins[c]);
      });
      for (const Bins& c : chunkBins) bins.join(c);
    }
    float best = WP_INF;
    int bestAxis = -1, bestBin = 0;
    Box4 bestLeft, bestRight;
    for (int a = 0; a < 3; ++a) {
      if (binning.scaleOf[a] <= 0.0f) continue;
      // Sweep from the right for suffix bounds, then from the left.
      Box4 right[kBins];
      float rightCost[kBins];
      Box4 acc;
      uint32_t n = 0;
      for (int b = nb - 1; b > 0; --b) {
        acc.grow(bins.box[a][b]);
        n += bins.count[a][b];
        right[b] = acc;
        rightCost[b] = acc.half_area() * float(n);
      }
      acc = Box4();
      n = 0;
      for (int b = 0; b < nb - 1; ++b) {
        acc.grow(bins.box[a][b]);
        n += bins.count[a][b];
        float cost = acc.half_area() * float(n) + rightCost[b + 1];
        if (n > 0 && n < count && cost < best) {
          best = cost;
          bestAxis = a;
          bestBin = b;
          bestLeft = acc;
          bestRight = right[b + 1];
        }
      }
    }
    if (bestAxis < 0 || leaf_is_better(t, best)) {
      if (count <= maxLeaf) return false;
      Aabb cb = t.centroids.aabb();
      median_split(t, l, r, largest_axis(cb.hi - cb.lo));
      return true;
    }
    std::vector<uint32_t> leftOfChunk(chunkBins.size());
    for (size_t c = 0; c < chunkBins.size(); ++c)
      for (int b = 0; b <= bestBin; ++b) leftOfChunk[c] += chunkBins[c].count[bestAxis][b];
    // The very computation that binned them, so each child's primitives are
    // exactly its bins' (whose bounds it takes).
    float o[4];
    binning.origin.store(o);
    const float origin = o[bestAxis], lastBin = float(nb - 1);
    split_by(
        t, l, r, [&](const PrimRef& p) { return binning.on_axis(p, bestAxis, origin, lastBin) <= bestBin; },
        chunkBins.empty() ? nullptr : &leftOfChunk);
    l.bounds = bestLeft;
    r.bounds = bestRight;
    return true;
  }

  AcceleratorSettings settings_;
  size_t n_;
  WorkArray<PrimRef> refs0_, refs1_;
  PrimRef* refs_[2];
  WorkArray<shader::BvhNode> nodes_;
  uint32_t* order_ = nullptr;
  std::atomic<uint32_t> nodeCount_{0};
};

double sah_cost(const std::vector<shader::BvhNode>& nodes) {
  double rootArea = std::max(double(node_box(nodes[0]).half_area()), 1e-30);
  double cost = 0.0;
  for (const shader::BvhNode& n : nodes) cost += sah_term(n, rootArea);
  return cost;
}

Aabb union_of(const Aabb& a, const Aabb& b) {
  Aabb u = a;
  u.grow(b);
  return u;
}

// One rotation pass over the subtree at `node` (depth `depth`), children
// first; height[i] is the height of the subtree in slot i (a leaf: 0), kept
// current as subtrees move. Counts the rotations made.
void rotate_subtree(std::vector<shader::BvhNode>& nodes, std::vector<int>& height, uint32_t node, int depth,
                    uint64_t& rotations) {
  if (nodes[node].count != 0) {
    height[node] = 0;
    return;
  }
  const uint32_t l = nodes[node].leftFirst, r = l + 1;
  rotate_subtree(nodes, height, l, depth + 1, rotations);
  rotate_subtree(nodes, height, r, depth + 1, rotations);
  // Candidates: swap child `a` with a child `g` of its sibling `b`; b's box
  // becomes the union of `a` and g's sibling `keep`.
  struct Candidate {
    uint32_t a, b, g, keep;
    float gain;
  } best{0, 0, 0, 0, 0.0f};
  for (auto [a, b] : {std::pair<uint32_t, uint32_t>{l, r}, {r, l}}) {
    const shader::BvhNode& sib = nodes[b];
    if (sib.count != 0) continue;
    // `a` moves one level down: its subtree must still fit under BVH_MAX_DEPTH.
    if (depth + 2 + height[a] > BVH_MAX_DEPTH) continue;
    float before = node_box(sib).half_area();
    for (uint32_t g : {sib.leftFirst, sib.leftFirst + 1}) {
      uint32_t keep = g == sib.leftFirst ? sib.leftFirst + 1 : sib.leftFirst;
      float gain = before - union_of(node_box(nodes[a]), node_box(nodes[keep])).half_area();
      if (gain > best.gain) best = Candidate{a, b, g, keep, gain};
    }
  }
  // Tiny gains are rounding; they would make passes swap back and forth.
  if (best.gain > 1e-6f * node_box(nodes[node]).half_area()) {
    std::swap(nodes[best.a], nodes[best.g]);
    std::swap(height[best.a], height[best.g]);
    Aabb box = union_of(node_box(nodes[best.g]), node_box(nodes[best.keep]));
    nodes[best.b].bmin = box.lo;
    nodes[best.b].bmax = box.hi;
    height[best.b] = 1 + std::max(height[best.g], height[best.keep]);
    ++rotations;
  }
  height[node] = 1 + std::max(height[l], height[r]);
}

}  // namespace

void rotate_bvh(Bvh& bvh, int maxPasses) {
  if (bvh.order.empty()) return;
  auto start = std::chrono::steady_clock::now();
  std::vector<int> height(bvh.nodes.size(), 0);
  for (int pass = 0; pass < maxPasses; ++pass) {
    uint64_t rotations = 0;
    rotate_subtree(bvh.nodes, height, 0, 0, rotations);
    if (rotations == 0) break;
  }
  bvh.depth = height[0];
  bvh.sahCost = sah_cost(bvh.nodes);
  bvh.buildSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
