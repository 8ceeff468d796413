// build_parts.h — what the BVH builders share (bvh.cpp, clustered.cpp): the
// SAH's costs, four-float SIMD (SSE on x86-64), primitive references and
// boxes, bins and the binned SAH's best split, Morton codes and their radix
// sort, and a node's build task. Internal to src/bvh.
#pragma once

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

namespace wp::build {

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
inline int bins_for(uint32_t count) {
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

inline BinnedSplit best_binned_split(const Bins& bins, const Binning& binning, uint32_t count) {
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
inline uint32_t sort_key(float x) {
  uint32_t u;
  std::memcpy(&u, &x, sizeof(u));
  return u ^ (uint32_t(int32_t(u) >> 31) | 0x80000000u);
}

// Interleaves the low 10 bits of q[0], q[1], q[2] (x in the lowest bit).
inline uint32_t morton_code(const int q[4]) {
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
inline uint64_t* radix_sort_codes(uint64_t* keys, uint64_t* scratch, size_t n) {
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
inline double sah_term(const shader::BvhNode& n, double rootArea) {
  const double rel = double(node_box(n).half_area()) / rootArea;
  return n.count == 0 ? kTraversalCost * rel : kIntersectCost * rel * double(n.count);
}

inline int largest_axis(glm::vec3 extent) {
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

}  // namespace wp::build
