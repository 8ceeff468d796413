#include "bvh/bvh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
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
constexpr uint32_t kChunk = 1u << 13;               // primitives per chunk of a parallel pass
// The SAH's costs: a node visit and a primitive test cost alike, as in one
// iteration of the kernels' walks, which do one of each.
constexpr float kTraversalCost = 1.0f;
constexpr float kIntersectCost = 1.0f;
// When choosing between a leaf and a split, a primitive test costs a little
// more: smaller leaves cut the wide walk's iterations per ray by 1.5-3 % on the
// benchmark scenes (docs/benchmarks.md) and keep GPU memory within 64 bytes
// per triangle (63.5; 1.5 would cost 65.4).
constexpr float kLeafIntersectCost = 1.25f;

static_assert(offsetof(shader::BvhNode, leftFirst) == 12 && offsetof(shader::BvhNode, bmax) == 16 &&
                  offsetof(shader::BvhNode, count) == 28,
              "Box4::store_box writes a node's bounds as two 16-byte halves");
static_assert(sizeof(Aabb) == 24 && offsetof(Aabb, hi) == 12, "F4::load reads an Aabb as six packed floats");

// Four floats with the few operations the builder needs: SSE on x86-64, plain
// arrays elsewhere. Lane 3 is unused.
#ifdef WP_BVH_SSE
struct F4 {
  __m128 v;
  static F4 load(const float* p) { return {_mm_loadu_ps(p)}; }
  static F4 splat(float x) { return {_mm_set1_ps(x)}; }
  // An Aabb's corners in two loads that stay inside its 24 bytes.
  static void load(const Aabb& b, F4& lo, F4& hi) {
    lo.v = _mm_loadu_ps(&b.lo.x);                      // lo.x lo.y lo.z hi.x
    const __m128 t = _mm_loadu_ps(&b.lo.z);            // lo.z hi.x hi.y hi.z
    hi.v = _mm_shuffle_ps(t, t, _MM_SHUFFLE(3, 3, 2, 1));
  }
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
  static void load(const Aabb& b, F4& lo, F4& hi) {
    lo = {{b.lo.x, b.lo.y, b.lo.z, 0.0f}};
    hi = {{b.hi.x, b.hi.y, b.hi.z, 0.0f}};
  }
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
  // Writes the box to a node's bmin and bmax in two 16-byte stores, which
  // clobber leftFirst and count: the caller writes those afterwards. (Going
  // through an Aabb, the compiler's 8-byte copies straddled its 16-byte
  // stores, which the core cannot forward: a stall at every node.)
  void store_box(shader::BvhNode& n) const {
    lo.store(&n.bmin.x);
    hi.store(&n.bmax.x);
  }
  // half_area of a box known not to be empty, in registers: the SAH sweeps'
  // inner loops.
  float sweep_area() const {
#ifdef WP_BVH_SSE
    const __m128 d = _mm_sub_ps(hi.v, lo.v);
    const __m128 p = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));  // xy, yz, zx
    return _mm_cvtss_f32(_mm_add_ss(_mm_add_ss(p, _mm_shuffle_ps(p, p, 1)), _mm_movehl_ps(p, p)));
#else
    return half_area();
#endif
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
  void of(F4 centroid2, int out[4]) const { min((centroid2 - origin) * scale, last).bins(out); }
  void of(const PrimRef& r, int out[4]) const { of(r.centroid2(), out); }
  // Lane `a` of of(): the same operations in the same order, so the same bin.
  int on_axis(const PrimRef& r, int a, float o, float lastBin) const {
    float t = ((r.lo[a] + r.hi[a]) - o) * scaleOf[a];
    t = t < lastBin ? t : lastBin;
    return int(t > 0.0f ? t : 0.0f);
  }
};

// The cheapest split between bins: the axis, the last bin on the left, both
// sides' bounds and the left side's count. `count` is the bins' total; splits
// that leave a side empty are skipped. axis < 0 when no split is finite.
struct BinnedSplit {
  float cost = WP_INF;  // area x count, summed over both sides
  int axis = -1, bin = 0;
  Box4 left, right;
  uint32_t leftCount = 0;
};

BinnedSplit best_binned_split(const Bins& bins, const Binning& binning, uint32_t count) {
  const int nb = bins.used;
  BinnedSplit best;
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
      if (n > 0 && n < count && cost < best.cost) best = BinnedSplit{cost, a, b, acc, right[b + 1], n};
    }
  }
  return best;
}

// A float's bits as an unsigned integer that sorts in the float's order,
// -0 before +0 and NaNs at the ends: a total order, so that sorting by
// centroid stays well defined however wrong the bounds.
uint32_t sort_key(float x) {
  uint32_t u;
  std::memcpy(&u, &x, sizeof(u));
  return u ^ (uint32_t(int32_t(u) >> 31) | 0x80000000u);
}

// Interleaves the low 10 bits of q[0], q[1], q[2] (x in the lowest bit).
uint32_t morton_code(const int q[4]) {
  auto spread = [](uint32_t v) {
    v &= 0x3ffu;
    v = (v | (v << 16)) & 0x030000ffu;
    v = (v | (v << 8)) & 0x0300f00fu;
    v = (v | (v << 4)) & 0x030c30c3u;
    v = (v | (v << 2)) & 0x09249249u;
    return v;
  };
  return spread(uint32_t(q[0])) | spread(uint32_t(q[1])) << 1 | spread(uint32_t(q[2])) << 2;
}

// Sorts keys by their bits 32-61 (a Morton code above an index), stably:
// three passes of 10 bits, each histogrammed and scattered by blocks in
// parallel. Returns the array holding the result (keys or scratch).
uint64_t* radix_sort_codes(uint64_t* keys, uint64_t* scratch, size_t n) {
  constexpr int kDigitBits = 10;
  constexpr uint32_t kDigits = 1u << kDigitBits;
  const size_t blocks = std::clamp<size_t>(n >> 16, 1, 64);
  std::vector<uint32_t> offset(blocks * kDigits);
  auto block = [&](size_t b) { return std::pair<size_t, size_t>(n * b / blocks, n * (b + 1) / blocks); };
  for (int pass = 0; pass < 3; ++pass) {
    const int shift = 32 + pass * kDigitBits;
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      uint32_t* h = &offset[b * kDigits];
      std::fill(h, h + kDigits, 0u);
      auto [lo, hi] = block(b);
      for (size_t i = lo; i < hi; ++i) h[(keys[i] >> shift) & (kDigits - 1)]++;
    });
    uint32_t sum = 0;  // digit by digit, block by block within a digit: stable
    for (uint32_t d = 0; d < kDigits; ++d)
      for (size_t b = 0; b < blocks; ++b) {
        const uint32_t c = offset[b * kDigits + d];
        offset[b * kDigits + d] = sum;
        sum += c;
      }
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      uint32_t* at = &offset[b * kDigits];
      auto [lo, hi] = block(b);
      for (size_t i = lo; i < hi; ++i) scratch[at[(keys[i] >> shift) & (kDigits - 1)]++] = keys[i];
    });
    std::swap(keys, scratch);
  }
  return keys;
}

// The bounds of the boxes corners(i, lo, hi) gives for i in [begin, end), and
// the bounds of their centroids (doubled, as PrimRef::centroid2); in parallel
// when there are many.
struct BoundsAndCentroids {
  Box4 bounds, centroids;
};

template <typename Corners>
BoundsAndCentroids bounds_and_centroids(size_t begin, size_t end, Corners corners) {
  auto body = [&corners](const tbb::blocked_range<size_t>& r, BoundsAndCentroids acc) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      F4 lo, hi;
      corners(i, lo, hi);
      acc.bounds.grow(lo, hi);
      acc.centroids.grow(lo + hi, lo + hi);
    }
    return acc;
  };
  if (end - begin < kParallelThreshold) return body(tbb::blocked_range<size_t>(begin, end), BoundsAndCentroids{});
  return tbb::parallel_reduce(tbb::blocked_range<size_t>(begin, end, kChunk), BoundsAndCentroids{}, body,
                              [](BoundsAndCentroids a, const BoundsAndCentroids& b) {
                                a.bounds.grow(b.bounds);
                                a.centroids.grow(b.centroids);
                                return a;
                              });
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
// chunks. Nodes of at most kBottomMax primitives take the exact SAH sweep
// (build_bottom). Leaves write their primitive ids straight into the tree's
// order.
//
// SplitMethod::ClusteredSah builds the top levels over clusters instead
// (build_clustered): the primitives sorted in Morton order of their
// centroids and cut into runs of at most kClusterMax, each run one item of
// the binned SAH, weighing its primitives; nodes refine their clusters as they
// shrink, and hand nodes of at most kBottomMax primitives to the exact sweep.
// Each primitive then takes part in few binning passes, mostly over data in
// cache: 1.3-1.5x faster than binned SAH at 1M-10M triangles, with trees of
// about the same SAH cost (docs/benchmarks.md).
class Builder {
 public:
  Builder(const BvhInput& in, const AcceleratorSettings& s)
      : settings_{s.maxLeafSize, split_for(s, in.bounds.size())},
        bounds_(in.bounds),
        n_(in.bounds.size()),
        refs0_(n_),
        refs1_(n_),
        nodes_(kFirstPair + 2 * n_ + max_chains(n_) * kNodeBlock) {
    // The reference arrays stay untouched (their pages unmapped) until a
    // build writes them: the clustered build needs little of them.
    refs_[0] = refs0_.get();
    refs_[1] = refs1_.get();
  }

  // Writes primitive i's reference to r.
  void ref_of(size_t i, PrimRef& r) const {
    F4 lo, hi;
    F4::load(bounds_[i], lo, hi);
    lo.store(r.lo);  // lane 3 lands in id, written next
    hi.store(r.hi);
    r.id = uint32_t(i);
    r.pad = 0;
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
    // The references are not needed past the build: give their memory to
    // the user of the slots (2 x 32 bytes per primitive).
    refs0_.release();
    refs1_.release();
    refs_[0] = refs_[1] = nullptr;
    const double rootArea = std::max(double(node_box(nodes_[0]).half_area()), 1e-30);
    const Measure m = measure(0, 0, rootArea);
    use(BvhSlots{nodes_.get(), nodeCount_.load(), order.get(), n_, m.depth, m.sahCost});
  }

 private:
  static uint32_t chunks_of(const Task& t) { return (t.end - t.begin + kChunk - 1) / kChunk; }
  // The primitives [begin, end) of task t's chunk c.
  static std::pair<uint32_t, uint32_t> chunk(const Task& t, uint32_t c) {
    const uint32_t begin = t.begin + c * kChunk;
    return {begin, std::min(t.end, begin + kChunk)};
  }

  // Node slots are handed out in blocks, one block at a time to each chain of
  // build_node calls (the root's, and each spawned task's), so threads do not
  // contend for a shared counter at every node. Every chain leaves at most
  // one partly used block: nodes_ has room for 2n nodes after the first
  // kFirstPair slots, and one block more per chain. The unused slots are
  // dropped by compact_nodes.
  static constexpr uint32_t kNodeBlock = 32;
  // The first pair of children goes to slots 2 and 3 (slot 1 stays unused),
  // so that every pair of 32-byte siblings shares one 64-byte cache line:
  // whoever reads a node's children reads both.
  static constexpr uint32_t kFirstPair = 2;
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
    nodeCount_ = kFirstPair;
    if (settings_.split == SplitMethod::ClusteredSah && n_ > kBottomMax) return build_clustered();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n_, kChunk), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) ref_of(i, refs_[0][i]);
    });
    Task root{0, 0, uint32_t(n_), 0, 0, {}, {}};
    bounds_of(root);
    tbb::task_group tasks;
    NodeBlock block;
    build_node(root, tasks, block);
    tasks.wait();
  }

  // A node of the top levels: the clusters [begin, end) of array `items`
  // (`scratch` is the same size, for the children), holding `prims`
  // primitives, whose leaves will take order_[primBegin, primBegin + prims).
  struct ClusterTask {
    uint32_t node, begin, end, primBegin, prims;
    int depth;
    PrimRef *items, *scratch;
    Box4 bounds, centroids;
  };

  // Cells per axis of the Morton order's grid: 30-bit codes.
  static constexpr int kMortonCells = 1024;
  // Clusters of at most this many primitives start the top levels.
  static constexpr uint32_t kClusterMax = 32;
  // A top-level node with fewer clusters than this splits them into smaller
  // ones (refine), so that its split planes need not follow the boundaries of
  // clusters large against the node.
  static constexpr uint32_t kMinClusters = 64;
  // So a node that refines holds fewer than kMinClusters * kClusterMax
  // primitives, and spawns no task that could outlive its refined clusters.
  static_assert(kMinClusters * kClusterMax < kParallelThreshold);

  // The clustered SAH build (see the class comment).
  void build_clustered() {
    const BoundsAndCentroids all =
        bounds_and_centroids(0, n_, [this](size_t i, F4& lo, F4& hi) { F4::load(bounds_[i], lo, hi); });
    // Morton order of the centroids, on a grid of kMortonCells^3 over their bounds.
    const Binning grid(all.centroids, kMortonCells);
    WorkArray<uint64_t> keys(n_), scratch(n_);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n_, kChunk), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        int q[4];
        F4 lo, hi;
        F4::load(bounds_[i], lo, hi);
        grid.of(lo + hi, q);
        keys[i] = uint64_t(morton_code(q)) << 32 | i;
      }
    });
    const uint64_t* sortedKeys = radix_sort_codes(keys.get(), scratch.get(), n_);
    WorkArray<PrimRef> sorted(n_);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n_, kChunk), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) ref_of(uint32_t(sortedKeys[i]), sorted[i]);
    });
    sorted_ = sorted.get();
    keys_ = sortedKeys;
    float lo[4], hi[4];
    all.centroids.lo.store(lo);
    all.centroids.hi.store(hi);
    for (int k = 0; k < 3; ++k) cell_[k] = 0.5f * (hi[k] - lo[k]) / float(kMortonCells);  // in world units
    std::vector<PrimRef> clusters = make_clusters();
    std::vector<PrimRef> clusterScratch(clusters.size());
    ClusterTask top{0, 0, uint32_t(clusters.size()), 0, uint32_t(n_), 0, clusters.data(), clusterScratch.data(), all.bounds, {}};
    for (const PrimRef& c : clusters) top.centroids.grow(c.centroid2(), c.centroid2());
    tbb::task_group tasks;
    NodeBlock block;
    build_top(top, tasks, block);
    tasks.wait();
  }

  // Clusters: runs of the Morton order split at their highest differing code
  // bit until each holds at most `limit` primitives, so each lies in one
  // octree cell. A run whose box is far larger than its cell holds a large
  // primitive (a floor under a mesh) and is split further, down to single
  // primitives, so that the large one does not drag its neighbours up the
  // tree. Appends them to `out` as references: bounds, first sorted
  // reference (id) and count (pad).
  void cluster_run(uint32_t b, uint32_t e, uint32_t limit, std::vector<PrimRef>& out) const {
    const uint32_t cb = uint32_t(keys_[b] >> 32), ce = uint32_t(keys_[e - 1] >> 32);
    if (e - b <= limit) {
      Box4 box;
      for (uint32_t j = b; j < e; ++j) box.grow(sorted_[j].lo4(), sorted_[j].hi4());
      // The cell of the run's common code prefix, grown by its own size on
      // every side.
      const int freeBits = cb == ce ? 0 : 32 - __builtin_clz(cb ^ ce);
      float ext[3];
      for (int k = 0; k < 3; ++k) ext[k] = 3.0f * cell_[k] * float(1u << ((freeBits + 2 - k) / 3));
      if (e - b == 1 || box.half_area() <= ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0]) {
        PrimRef c;
        box.lo.store(c.lo);  // lane 3 lands in id, set next
        box.hi.store(c.hi);
        c.id = b;
        c.pad = e - b;
        out.push_back(c);
        return;
      }
    }
    const uint32_t m = split_run(b, e, cb, ce);
    cluster_run(b, m, limit, out);
    cluster_run(m, e, limit, out);
  }

  // Where the sorted run [b, e) (codes cb to ce) splits: at its highest
  // differing code bit, or in the middle when all its codes are equal.
  uint32_t split_run(uint32_t b, uint32_t e, uint32_t cb, uint32_t ce) const {
    if (cb == ce) return b + (e - b) / 2;
    const uint32_t bit = 1u << (31 - __builtin_clz(cb ^ ce));
    return uint32_t(std::partition_point(keys_ + b, keys_ + e, [bit](uint64_t k) { return (uint32_t(k >> 32) & bit) == 0; }) - keys_);
  }

  // All primitives' clusters, the runs of about n / 64 split in parallel.
  std::vector<PrimRef> make_clusters() const {
    using Run = std::pair<uint32_t, uint32_t>;
    std::vector<Run> runs{{0, uint32_t(n_)}};
    const uint32_t coarse = std::max<uint32_t>(kClusterMax, uint32_t(n_ / 64));
    for (size_t i = 0; i < runs.size();) {  // breadth-first, in order
      auto [b, e] = runs[i];
      if (e - b <= coarse) {
        ++i;
        continue;
      }
      const uint32_t m = split_run(b, e, uint32_t(keys_[b] >> 32), uint32_t(keys_[e - 1] >> 32));
      runs[i] = {m, e};
      runs.insert(runs.begin() + std::ptrdiff_t(i), Run{b, m});
    }
    std::vector<std::vector<PrimRef>> fine(runs.size());
    tbb::parallel_for(size_t(0), runs.size(), [&](size_t i) { cluster_run(runs[i].first, runs[i].second, kClusterMax, fine[i]); });
    std::vector<PrimRef> clusters;
    for (const auto& f : fine) clusters.insert(clusters.end(), f.begin(), f.end());
    return clusters;
  }

  // Top-level binned SAH over clusters, each weighing its primitives. A node
  // of at most kBottomMax primitives (or one cluster, or no split) is handed
  // on (hand_off).
  void build_top(const ClusterTask& t, tbb::task_group& tasks, NodeBlock& block) {
    const uint32_t items = t.end - t.begin;
    if (items < kMinClusters && t.prims >= 2 * items && t.prims > kBottomMax) {
      // Refine: about 4 kMinClusters clusters for the node, built on this
      // thread (the node is far below kParallelThreshold, so nothing
      // spawned outlives these arrays).
      std::vector<PrimRef> refined;
      const uint32_t limit = std::max<uint32_t>(1, t.prims / (4 * kMinClusters));
      for (uint32_t i = t.begin; i < t.end; ++i) cluster_run(t.items[i].id, t.items[i].id + t.items[i].pad, limit, refined);
      if (refined.size() > items) {
        std::vector<PrimRef> scratch(refined.size());
        ClusterTask r = t;
        r.begin = 0;
        r.end = uint32_t(refined.size());
        r.items = refined.data();
        r.scratch = scratch.data();
        r.centroids = Box4();
        for (const PrimRef& c : refined) r.centroids.grow(c.centroid2(), c.centroid2());
        return build_top(r, tasks, block);
      }
    }
    t.bounds.store_box(nodes_[t.node]);
    ClusterTask l{0, 0, 0, 0, 0, t.depth + 1, t.scratch, t.items, {}, {}}, r = l;
    if (t.prims <= kBottomMax || items == 1 || t.depth >= BVH_MAX_DEPTH - 33 || !cluster_split(t, l, r))
      return hand_off(t, tasks, block);
    build_children(t.node, t.prims, l, r, tasks, block, &Builder::build_top);
  }

  // Binned SAH over t's clusters, each counting as its primitives. Fills the
  // children and returns true, or returns false when no split has a finite
  // cost (the clusters' centroids coincide, or their bounds are not finite).
  bool cluster_split(const ClusterTask& t, ClusterTask& l, ClusterTask& r) {
    const PrimRef* src = t.items;
    const int nb = bins_for(t.end - t.begin);
    Binning binning(t.centroids, nb);
    Bins bins(nb);
    bin_range<true>(src, t.begin, t.end, binning, bins);
    const BinnedSplit best = best_binned_split(bins, binning, t.prims);
    if (best.axis < 0) return false;
    float o[4];
    binning.origin.store(o);
    const float origin = o[best.axis], lastBin = float(nb - 1);
    const uint32_t items = partition_range(
        src, t.scratch, t.begin, t.end, t.begin, t.end,
        [&](const PrimRef& p) { return binning.on_axis(p, best.axis, origin, lastBin) <= best.bin; }, l.centroids,
        r.centroids);
    l.begin = t.begin;
    l.end = r.begin = t.begin + items;
    r.end = t.end;
    l.primBegin = t.primBegin;
    l.prims = best.leftCount;
    r.primBegin = t.primBegin + best.leftCount;
    r.prims = t.prims - best.leftCount;
    l.bounds = best.left;
    r.bounds = best.right;
    return true;
  }

  // Builds the subtree of t's primitives: by the exact sweep straight from
  // the sorted references when few, else copied together into the first
  // reference array for build_node.
  void hand_off(const ClusterTask& t, tbb::task_group& tasks, NodeBlock& block) {
    const PrimRef* clusters = t.items;
    if (t.prims <= kBottomMax) {
      Bottom bt;
      PrimRef* dst = bt.refs;
      for (uint32_t i = t.begin; i < t.end; ++i) dst = std::copy_n(sorted_ + clusters[i].id, clusters[i].pad, dst);
      return build_bottom(bt, t.prims, t.primBegin, t.node, t.depth, t.bounds, block);
    }
    Task h{t.node, t.primBegin, t.primBegin + t.prims, t.depth, 0, t.bounds, {}};
    PrimRef* dst = refs_[0] + t.primBegin;
    for (uint32_t i = t.begin; i < t.end; ++i) {
      for (uint32_t j = clusters[i].id; j < clusters[i].id + clusters[i].pad; ++j) {
        *dst++ = sorted_[j];
        const F4 c = sorted_[j].centroid2();
        h.centroids.grow(c, c);
      }
    }
    build_node(h, tasks, block);
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
    const PrimRef* refs = refs_[t.buf];
    const BoundsAndCentroids acc =
        bounds_and_centroids(t.begin, t.end, [refs](size_t i, F4& lo, F4& hi) { lo = refs[i].lo4(), hi = refs[i].hi4(); });
    t.bounds = acc.bounds;
    t.centroids = acc.centroids;
  }

  // Bins references [begin, end); Weighted: each counts as its `pad`
  // primitives (a cluster).
  template <bool Weighted = false>
  static void bin_range(const PrimRef* refs, uint32_t begin, uint32_t end, const Binning& binning, Bins& acc) {
    for (uint32_t i = begin; i < end; ++i) {
      const PrimRef& p = refs[i];
      int b[4];
      binning.of(p, b);
      F4 lo = p.lo4(), hi = p.hi4();
      for (int a = 0; a < 3; ++a) {
        acc.box[a][b[a]].grow(lo, hi);
        acc.count[a][b[a]] += Weighted ? p.pad : 1u;
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
    t.bounds.store_box(nodes_[t.node]);
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
    } else if (count <= kBottomMax) {
      return build_bottom(t, block);
    } else if (!sah_split(t, l, r)) {
      return make_leaf(t);
    }

    build_children(t.node, count, l, r, tasks, block, &Builder::build_node);
  }

  // Gives the split node at `node` its children's two slots and builds them
  // with `build` (build_node or build_top), the left one as a task of its own
  // (with its own chain of node blocks) when the node holds at least
  // kParallelThreshold primitives, which max_chains counts on.
  template <typename T, typename Build>
  void build_children(uint32_t node, uint32_t count, T l, T r, tbb::task_group& tasks, NodeBlock& block, Build build) {
    const uint32_t left = allocate_pair(block);
    nodes_[node].leftFirst = left;
    nodes_[node].count = 0;
    l.node = left;
    r.node = left + 1;
    if (count >= kParallelThreshold) {
      tasks.run([this, l, &tasks, build] {
        NodeBlock own;
        (this->*build)(l, tasks, own);
      });
    } else {
      (this->*build)(l, tasks, block);
    }
    (this->*build)(r, tasks, block);
  }

  // Whether a node of `count` primitives in `bounds` should be a leaf rather
  // than split at `splitArea` (the children's areas weighted by their
  // primitive counts): a leaf must be allowed (at most maxLeafSize
  // primitives) and no dearer than the split.
  bool leaf_is_better(uint32_t count, const Box4& bounds, float splitArea) const {
    const float splitCost = kTraversalCost + kLeafIntersectCost * splitArea / std::max(bounds.half_area(), 1e-30f);
    return count <= uint32_t(settings_.maxLeafSize) && splitCost >= kLeafIntersectCost * float(count);
  }

  // Nodes of at most kBottomMax primitives, the bottom of every SAH tree
  // (over half of its nodes), are built by the exact SAH sweep: the
  // primitives sorted by centroid once per axis, every split of each order
  // swept at every node, and the three orders partitioned stably on the way
  // down (the full-sweep build of Wald 2007, on a cache-resident handful).
  // Binning such nodes costs more, in the fixed costs of the bins, and only
  // approximates the best split.
  static constexpr uint32_t kBottomMax = 64;

  struct Bottom {
    PrimRef refs[kBottomMax];      // the subtree's references, copied together
    uint32_t first;                // where its leaves start in order_
    uint8_t order[3][kBottomMax];  // per axis, the references by centroid
    float rightCost[3][kBottomMax];  // sweep scratch: area x count of the suffixes
  };

  void build_bottom(const Task& t, NodeBlock& block) {
    Bottom bt;
    std::copy(refs_[t.buf] + t.begin, refs_[t.buf] + t.end, bt.refs);
    build_bottom(bt, t.end - t.begin, t.begin, t.node, t.depth, t.bounds, block);
  }

  // The subtree at `node` over bt's first `count` references, whose leaves
  // take order_[first, first + count).
  void build_bottom(Bottom& bt, uint32_t count, uint32_t first, uint32_t node, int depth, const Box4& bounds,
                    NodeBlock& block) {
    bt.first = first;
    for (int a = 0; a < 3; ++a) {
      uint32_t key[kBottomMax];
      // + 0: -0 becomes +0.
      for (uint32_t i = 0; i < count; ++i) key[i] = sort_key(bt.refs[i].lo[a] + bt.refs[i].hi[a] + 0.0f);
      // Each reference's place is the number of those before it, ties in
      // reference order: count x count comparisons in loops the compiler
      // vectorizes, where a comparison sort's branches mispredict.
      for (uint32_t i = 0; i < count; ++i) {
        uint32_t place = 0;
        for (uint32_t j = 0; j < i; ++j) place += key[j] <= key[i] ? 1u : 0u;
        for (uint32_t j = i + 1; j < count; ++j) place += key[j] < key[i] ? 1u : 0u;
        bt.order[a][place] = uint8_t(i);
      }
    }
    bottom_node(bt, node, 0, count, depth, bounds, block);
  }

  // The node at `node` over positions [begin, end) of bt's orders.
  void bottom_node(Bottom& bt, uint32_t node, uint32_t begin, uint32_t end, int depth, const Box4& bounds,
                   NodeBlock& block) {
    bounds.store_box(nodes_[node]);
    const uint32_t count = end - begin;
    auto leaf = [&] {
      nodes_[node].leftFirst = bt.first + begin;
      nodes_[node].count = count;
      for (uint32_t p = begin; p < end; ++p) order_[bt.first + p] = bt.refs[bt.order[0][p]].id;
    };
    if (count == 1) return leaf();
    auto grow = [&](Box4& acc, int a, uint32_t p) { acc.grow(bt.refs[bt.order[a][p]].lo4(), bt.refs[bt.order[a][p]].hi4()); };
    float best = WP_INF;
    int axis = -1;
    uint32_t split = 0;
    Box4 left, right;
    // Near the depth limit only halving splits (see build_node).
    if (count == 2 && depth < BVH_MAX_DEPTH - 33) {
      // Two references: every axis splits them one from the other at the
      // same cost, the sum of their areas, so the sweep would take axis 0.
      // With leaves of one primitive a fifth of all nodes are such pairs,
      // and the sweep cost them more than the rest of the node.
      Box4 first, second;
      grow(first, 0, begin);
      grow(second, 0, begin + 1);
      best = first.sweep_area() + second.sweep_area();
      if (best < WP_INF) {
        if (leaf_is_better(count, bounds, best)) return leaf();
        axis = 0;
        split = begin + 1;
      }
    } else if (depth < BVH_MAX_DEPTH - 33) {
      // The three axes swept side by side: three independent chains of
      // min / max, which the core overlaps (one after another, each waited
      // on its own).
      Box4 acc[3];
      for (uint32_t p = end - 1; p > begin; --p) {
#pragma GCC unroll 3
        for (int a = 0; a < 3; ++a) {
          grow(acc[a], a, p);
          bt.rightCost[a][p] = acc[a].sweep_area() * float(end - p);
        }
      }
      float axisBest[3] = {WP_INF, WP_INF, WP_INF};
      uint32_t axisSplit[3] = {0, 0, 0};
      acc[0] = acc[1] = acc[2] = Box4();
      for (uint32_t p = begin + 1; p < end; ++p) {  // [begin, p) on the left
        const float n = float(p - begin);
#pragma GCC unroll 3
        for (int a = 0; a < 3; ++a) {
          grow(acc[a], a, p - 1);
          const float cost = acc[a].sweep_area() * n + bt.rightCost[a][p];
          axisSplit[a] = cost < axisBest[a] ? p : axisSplit[a];
          axisBest[a] = cost < axisBest[a] ? cost : axisBest[a];
        }
      }
      for (int a = 0; a < 3; ++a) {
        if (axisBest[a] < best) {
          best = axisBest[a];
          axis = a;
          split = axisSplit[a];
        }
      }
      if (axis >= 0 && leaf_is_better(count, bounds, best)) return leaf();
    }
    if (axis < 0) {  // the depth limit, or no finite cost (bounds not finite)
      if (count <= uint32_t(settings_.maxLeafSize)) return leaf();
      axis = 0;
      split = begin + count / 2;
    }
    for (uint32_t p = begin; p < end; ++p) grow(p < split ? left : right, axis, p);
    // The other two orders, partitioned stably by the side each reference
    // took in the chosen one.
    bool isLeft[kBottomMax];
    for (uint32_t p = begin; p < end; ++p) isLeft[bt.order[axis][p]] = p < split;
    for (int a = 0; a < 3; ++a) {
      if (a == axis) continue;
      uint8_t rights[kBottomMax];
      uint32_t l = begin, r = 0;
      for (uint32_t p = begin; p < end; ++p) {
        const uint8_t i = bt.order[a][p];
        bt.order[a][l] = i;  // l <= p: never overwrites what is still to be read
        rights[r] = i;
        l += isLeft[i];
        r += !isLeft[i];
      }
      std::memcpy(&bt.order[a][l], rights, r);
    }
    const uint32_t children = allocate_pair(block);
    nodes_[node].leftFirst = children;
    nodes_[node].count = 0;
    bottom_node(bt, children, begin, split, depth + 1, left, block);
    bottom_node(bt, children + 1, split, end, depth + 1, right, block);
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
    const BinnedSplit best = best_binned_split(bins, binning, count);
    const int bestAxis = best.axis, bestBin = best.bin;
    if (bestAxis < 0 || leaf_is_better(count, t.bounds, best.cost)) {
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
    l.bounds = best.left;
    r.bounds = best.right;
    return true;
  }

  AcceleratorSettings settings_;
  const std::vector<Aabb>& bounds_;
  size_t n_;
  WorkArray<PrimRef> refs0_, refs1_;
  PrimRef* refs_[2];
  WorkArray<shader::BvhNode> nodes_;
  uint32_t* order_ = nullptr;
  std::atomic<uint32_t> nodeCount_{0};
  // The clustered top levels (build_clustered): references in Morton order,
  // the clusters' two arrays, and the nodes handed to build_node.
  const PrimRef* sorted_ = nullptr;
  const uint64_t* keys_ = nullptr;  // their keys: Morton code above index
  float cell_[3] = {0, 0, 0};       // the Morton grid's cell, in world units
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
