#include "bvh/bvh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <tuple>

#ifdef __SSE2__
#include <emmintrin.h>
#define WP_BVH_SSE 1
#endif

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

// A node to build: its primitives [begin, end) with their bounds and the
// bounds of their centroids (doubled, as PrimRef::centroid2).
struct Task {
  uint32_t node, begin, end;
  int depth;
  Box4 bounds, centroids;
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

int largest_axis(glm::vec3 extent) {
  return extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
}

class Builder {
 public:
  Builder(const BvhInput& in, const AcceleratorSettings& s) : settings_(s) {
    size_t n = in.bounds.size();
    refs_.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const Aabb& b = in.bounds[i];
        refs_[i] = PrimRef{{b.lo.x, b.lo.y, b.lo.z}, uint32_t(i), {b.hi.x, b.hi.y, b.hi.z}, 0u};
      }
    });
    // A binary tree over n primitives has at most 2n - 1 nodes. Left
    // uninitialized: every node is written before it is read, and only the
    // pages of nodes the tree uses are ever touched.
    nodes_.reset(new shader::BvhNode[std::max<size_t>(1, 2 * n)]);
  }

  Bvh build() {
    Bvh bvh;
    if (refs_.empty()) {
      // An empty scene: an interior root with an empty box, which every ray
      // misses before any child is read.
      shader::BvhNode root{};
      root.bmin = Aabb().lo;
      root.bmax = Aabb().hi;
      bvh.nodes.push_back(root);
      return bvh;
    }
    Task root{0, 0, uint32_t(refs_.size()), 0, {}, {}};
    bounds_of(root);
    nodeCount_ = 1;
    tbb::task_group tasks;
    build_node(root, tasks);
    tasks.wait();
    bvh.nodes.assign(nodes_.get(), nodes_.get() + nodeCount_.load());
    bvh.order.resize(refs_.size());
    tbb::parallel_for(size_t(0), refs_.size(), [&](size_t i) { bvh.order[i] = refs_[i].id; });
    bvh.depth = maxDepth_.load();
    return bvh;
  }

 private:
  // Bounds and centroid bounds of a task's primitives, in parallel when large.
  void bounds_of(Task& t) const {
    struct Acc {
      Box4 b, c;
      void join(const Acc& o) {
        b.grow(o.b);
        c.grow(o.c);
      }
    };
    auto body = [&](const tbb::blocked_range<uint32_t>& r, Acc acc) {
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        const PrimRef& p = refs_[i];
        F4 c = p.centroid2();
        acc.b.grow(p.lo4(), p.hi4());
        acc.c.grow(c, c);
      }
      return acc;
    };
    Acc acc = t.end - t.begin < kParallelThreshold
                  ? body(tbb::blocked_range<uint32_t>(t.begin, t.end), Acc{})
                  : tbb::parallel_reduce(tbb::blocked_range<uint32_t>(t.begin, t.end, 1 << 13), Acc{}, body,
                                         [](Acc a, const Acc& b) {
                                           a.join(b);
                                           return a;
                                         });
    t.bounds = acc.b;
    t.centroids = acc.c;
  }

  void bin_range(uint32_t begin, uint32_t end, const Binning& binning, Bins& acc) const {
    for (uint32_t i = begin; i < end; ++i) {
      const PrimRef& p = refs_[i];
      int b[4];
      binning.of(p, b);
      F4 lo = p.lo4(), hi = p.hi4();
      for (int a = 0; a < 3; ++a) {
        acc.box[a][b[a]].grow(lo, hi);
        acc.count[a][b[a]]++;
      }
    }
  }

  void bin(const Task& t, const Binning& binning, Bins& bins) const {
    if (t.end - t.begin < kParallelThreshold) return bin_range(t.begin, t.end, binning, bins);
    bins = tbb::parallel_reduce(
        tbb::blocked_range<uint32_t>(t.begin, t.end, 1 << 13), Bins(bins.used),
        [&](const tbb::blocked_range<uint32_t>& r, Bins acc) {
          bin_range(r.begin(), r.end(), binning, acc);
          return acc;
        },
        [](Bins a, const Bins& b) {
          a.join(b);
          return a;
        });
  }

  // Partitions the task's primitives so that those satisfying `left` come
  // first, filling in both halves' centroid bounds; returns the split.
  template <typename Left>
  uint32_t partition(const Task& t, Left left, Box4& leftCentroids, Box4& rightCentroids) {
    PrimRef* refs = refs_.data();  // locals, so the loop keeps them in registers
    F4 lLo = leftCentroids.lo, lHi = leftCentroids.hi, rLo = rightCentroids.lo, rHi = rightCentroids.hi;
    uint32_t i = t.begin, j = t.end;
    while (true) {
      while (i < j && left(refs[i])) {
        F4 c = refs[i].centroid2();
        lLo = min(lLo, c);
        lHi = max(lHi, c);
        ++i;
      }
      while (i < j && !left(refs[j - 1])) {
        F4 c = refs[j - 1].centroid2();
        rLo = min(rLo, c);
        rHi = max(rHi, c);
        --j;
      }
      if (i >= j) break;
      std::swap(refs[i], refs[j - 1]);
    }
    leftCentroids = Box4{lLo, lHi};
    rightCentroids = Box4{rLo, rHi};
    return i;
  }

  // The median split on `axis` (nth_element on centroids), with both halves'
  // bounds computed afterwards.
  uint32_t median_split(Task& t, Task& l, Task& r, int axis) {
    uint32_t mid = t.begin + (t.end - t.begin) / 2;
    std::nth_element(refs_.begin() + t.begin, refs_.begin() + mid, refs_.begin() + t.end,
                     [axis](const PrimRef& a, const PrimRef& b) { return a.lo[axis] + a.hi[axis] < b.lo[axis] + b.hi[axis]; });
    l.begin = t.begin;
    l.end = r.begin = mid;
    r.end = t.end;
    bounds_of(l);
    bounds_of(r);
    return mid;
  }

  void make_leaf(const Task& t) {
    shader::BvhNode& n = nodes_[t.node];
    n.leftFirst = t.begin;
    n.count = t.end - t.begin;
    int d = maxDepth_.load();
    while (t.depth > d && !maxDepth_.compare_exchange_weak(d, t.depth)) {
    }
  }

  void build_node(Task t, tbb::task_group& tasks) {
    Aabb box = t.bounds.aabb();
    nodes_[t.node].bmin = box.lo;
    nodes_[t.node].bmax = box.hi;
    const uint32_t count = t.end - t.begin;
    const uint32_t maxLeaf = uint32_t(settings_.maxLeafSize);
    if (count == 1) return make_leaf(t);

    Aabb cb = t.centroids.aabb();
    glm::vec3 extent = cb.hi - cb.lo;
    int axis = largest_axis(extent);
    Task l{0, 0, 0, t.depth + 1, {}, {}}, r = l;
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
      l.begin = t.begin;
      r.end = t.end;
      l.end = r.begin = partition(t, [&](const PrimRef& p) { return p.lo[axis] + p.hi[axis] < m; }, l.centroids, r.centroids);
      if (l.end == t.begin || l.end == t.end) {
        median_split(t, l, r, axis);
      } else {
        bounds_of(l);
        bounds_of(r);
      }
    } else if (!sah_split(t, l, r)) {
      return make_leaf(t);
    }

    uint32_t left = nodeCount_.fetch_add(2);
    nodes_[t.node].leftFirst = left;
    nodes_[t.node].count = 0;
    l.node = left;
    r.node = left + 1;
    if (count >= kParallelThreshold) {
      tasks.run([this, l, &tasks] { build_node(l, tasks); });
      build_node(r, tasks);
    } else {
      build_node(l, tasks);
      build_node(r, tasks);
    }
  }

  // Binned SAH over all three axes. Fills the children and returns true, or
  // returns false when a leaf is cheaper (and allowed).
  bool sah_split(Task& t, Task& l, Task& r) {
    const uint32_t count = t.end - t.begin;
    const uint32_t maxLeaf = uint32_t(settings_.maxLeafSize);
    const int nb = bins_for(count);
    Binning binning(t.centroids, nb);
    Bins bins(nb);
    bin(t, binning, bins);
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
    float splitCost = kTraversalCost + kIntersectCost * best / std::max(t.bounds.half_area(), 1e-30f);
    float leafCost = kIntersectCost * float(count);
    if (bestAxis < 0 || (splitCost >= leafCost && count <= maxLeaf)) {
      if (count <= maxLeaf) return false;
      Aabb cb = t.centroids.aabb();
      median_split(t, l, r, largest_axis(cb.hi - cb.lo));
      return true;
    }
    l.begin = t.begin;
    r.end = t.end;
    // The very computation that binned them, so each child's primitives are
    // exactly its bins' (whose bounds it takes).
    float o[4];
    binning.origin.store(o);
    const float origin = o[bestAxis], lastBin = float(nb - 1);
    l.end = r.begin = partition(
        t, [&](const PrimRef& p) { return binning.on_axis(p, bestAxis, origin, lastBin) <= bestBin; }, l.centroids,
        r.centroids);
    l.bounds = bestLeft;
    r.bounds = bestRight;
    return true;
  }

  AcceleratorSettings settings_;
  std::vector<PrimRef> refs_;
  std::unique_ptr<shader::BvhNode[]> nodes_;
  std::atomic<uint32_t> nodeCount_{0};
  std::atomic<int> maxDepth_{0};
};

double sah_cost(const std::vector<shader::BvhNode>& nodes) {
  Aabb root;
  root.lo = nodes[0].bmin;
  root.hi = nodes[0].bmax;
  double rootArea = std::max(double(root.half_area()), 1e-30);
  double cost = 0.0;
  for (const shader::BvhNode& n : nodes) {
    Aabb b;
    b.lo = n.bmin;
    b.hi = n.bmax;
    double rel = b.half_area() / rootArea;
    cost += n.count == 0 ? kTraversalCost * rel : kIntersectCost * rel * double(n.count);
  }
  return cost;
}

Aabb node_box(const shader::BvhNode& n) {
  Aabb b;
  b.lo = n.bmin;
  b.hi = n.bmax;
  return b;
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

Bvh build_bvh(const BvhInput& input, const AcceleratorSettings& settings) {
  auto start = std::chrono::steady_clock::now();
  Bvh bvh = Builder(input, settings).build();
  bvh.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!input.bounds.empty()) bvh.sahCost = sah_cost(bvh.nodes);
  return bvh;
}

}  // namespace wp
