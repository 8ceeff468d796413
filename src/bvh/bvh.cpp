#include "bvh/bvh.h"

#include <tbb/parallel_reduce.h>
#include <tbb/blocked_range.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>

namespace wp {

namespace {

constexpr int kBins = 32;
constexpr uint32_t kParallelThreshold = 1u << 14;  // subtrees / ranges below this stay on one thread
constexpr float kTraversalCost = 1.0f;
constexpr float kIntersectCost = 1.0f;

struct RangeBounds {
  Aabb bounds;
  Aabb centroids;
  void join(const RangeBounds& o) {
    bounds.grow(o.bounds);
    centroids.grow(o.centroids);
  }
};

struct Bins {
  Aabb bounds[3][kBins];
  uint32_t count[3][kBins] = {};
  void join(const Bins& o) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < kBins; ++b) {
        bounds[a][b].grow(o.bounds[a][b]);
        count[a][b] += o.count[a][b];
      }
  }
};

class Builder {
 public:
  Builder(const BvhInput& in, const AcceleratorSettings& s) : in_(in), settings_(s) {
    size_t n = in.bounds.size();
    centroids_.resize(n);
    for (size_t i = 0; i < n; ++i) centroids_[i] = 0.5f * (in.bounds[i].lo + in.bounds[i].hi);
    // A binary tree over n primitives has at most 2n - 1 nodes.
    nodes_.resize(std::max<size_t>(1, 2 * n));
    order_.resize(n);
    for (size_t i = 0; i < n; ++i) order_[i] = uint32_t(i);
  }

  Bvh build() {
    Bvh bvh;
    if (order_.empty()) {
      // An empty scene: an interior root with an empty box, which every ray
      // misses before any child is read.
      shader::BvhNode root{};
      root.bmin = Aabb().lo;
      root.bmax = Aabb().hi;
      bvh.nodes.push_back(root);
      return bvh;
    }
    nodeCount_ = 1;
    tbb::task_group tasks;
    build_node(0, 0, uint32_t(order_.size()), 0, tasks);
    tasks.wait();
    nodes_.resize(nodeCount_.load());
    bvh.nodes = std::move(nodes_);
    bvh.order = std::move(order_);
    bvh.depth = maxDepth_.load();
    return bvh;
  }

 private:
  RangeBounds range_bounds(uint32_t begin, uint32_t end) const {
    auto body = [&](const tbb::blocked_range<uint32_t>& r, RangeBounds acc) {
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        uint32_t p = order_[i];
        acc.bounds.grow(in_.bounds[p]);
        acc.centroids.grow(centroids_[p]);
      }
      return acc;
    };
    if (end - begin < kParallelThreshold) return body(tbb::blocked_range<uint32_t>(begin, end), RangeBounds{});
    return tbb::parallel_reduce(tbb::blocked_range<uint32_t>(begin, end, 4096), RangeBounds{}, body,
                                [](RangeBounds a, const RangeBounds& b) {
                                  a.join(b);
                                  return a;
                                });
  }

  static int bin_of(float c, float lo, float scale) {
    return std::min(kBins - 1, std::max(0, int((c - lo) * scale)));
  }

  Bins bin(uint32_t begin, uint32_t end, const Aabb& cb) const {
    glm::vec3 extent = cb.hi - cb.lo;
    glm::vec3 scale;
    for (int a = 0; a < 3; ++a) scale[a] = extent[a] > 0.0f ? float(kBins) / extent[a] : 0.0f;
    auto body = [&](const tbb::blocked_range<uint32_t>& r, Bins acc) {
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        uint32_t p = order_[i];
        for (int a = 0; a < 3; ++a) {
          int b = bin_of(centroids_[p][a], cb.lo[a], scale[a]);
          acc.bounds[a][b].grow(in_.bounds[p]);
          acc.count[a][b]++;
        }
      }
      return acc;
    };
    if (end - begin < kParallelThreshold) return body(tbb::blocked_range<uint32_t>(begin, end), Bins{});
    return tbb::parallel_reduce(tbb::blocked_range<uint32_t>(begin, end, 4096), Bins{}, body, [](Bins a, const Bins& b) {
      a.join(b);
      return a;
    });
  }

  // Partitions [begin, end) so that the first part satisfies `left`; returns the split.
  uint32_t partition(uint32_t begin, uint32_t end, const std::function<bool(uint32_t)>& left) {
    auto mid = std::partition(order_.begin() + begin, order_.begin() + end, left);
    return uint32_t(mid - order_.begin());
  }

  uint32_t median_split(uint32_t begin, uint32_t end, int axis) {
    uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
    return mid;
  }

  void make_leaf(uint32_t nodeIndex, uint32_t begin, uint32_t end, int depth) {
    shader::BvhNode& n = nodes_[nodeIndex];
    n.leftFirst = begin;
    n.count = end - begin;
    int d = maxDepth_.load();
    while (depth > d && !maxDepth_.compare_exchange_weak(d, depth)) {
    }
  }

  void set_interior(uint32_t nodeIndex, uint32_t left) {
    nodes_[nodeIndex].leftFirst = left;
    nodes_[nodeIndex].count = 0;
  }

  void build_node(uint32_t nodeIndex, uint32_t begin, uint32_t end, int depth, tbb::task_group& tasks) {
    RangeBounds rb = range_bounds(begin, end);
    nodes_[nodeIndex].bmin = rb.bounds.lo;
    nodes_[nodeIndex].bmax = rb.bounds.hi;
    uint32_t count = end - begin;
    uint32_t maxLeaf = uint32_t(settings_.maxLeafSize);
    if (count == 1) return make_leaf(nodeIndex, begin, end, depth);

    glm::vec3 extent = rb.centroids.hi - rb.centroids.lo;
    int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    uint32_t mid = begin;
    bool degenerate = extent[axis] <= 0.0f;
    // Near the depth limit only halving splits are allowed: 32 of them separate
    // any number of primitives a 32-bit index can hold, so the tree (and the
    // kernels' traversal stack) never exceeds BVH_MAX_DEPTH.
    bool forceMedian = depth >= BVH_MAX_DEPTH - 33;
    if (degenerate) {
      if (count <= maxLeaf) return make_leaf(nodeIndex, begin, end, depth);
      mid = begin + count / 2;  // identical centroids: any halving will do
    } else if (forceMedian || settings_.split == SplitMethod::Equal) {
      if (count <= maxLeaf) return make_leaf(nodeIndex, begin, end, depth);
      mid = median_split(begin, end, axis);
    } else if (settings_.split == SplitMethod::Middle) {
      if (count <= maxLeaf) return make_leaf(nodeIndex, begin, end, depth);
      float m = 0.5f * (rb.centroids.lo[axis] + rb.centroids.hi[axis]);
      mid = partition(begin, end, [&](uint32_t p) { return centroids_[p][axis] < m; });
      if (mid == begin || mid == end) mid = median_split(begin, end, axis);
    } else {
      Bins bins = bin(begin, end, rb.centroids);
      float best = WP_INF;
      int bestAxis = -1;
      int bestBin = 0;
      for (int a = 0; a < 3; ++a) {
        if (extent[a] <= 0.0f) continue;
        // Sweep from the right to get suffix areas, then from the left.
        float rightCost[kBins];
        Aabb acc;
        uint32_t cnt = 0;
        for (int b = kBins - 1; b > 0; --b) {
          acc.grow(bins.bounds[a][b]);
          cnt += bins.count[a][b];
          rightCost[b] = acc.half_area() * float(cnt);
        }
        acc = Aabb();
        cnt = 0;
        for (int b = 0; b < kBins - 1; ++b) {
          acc.grow(bins.bounds[a][b]);
          cnt += bins.count[a][b];
          float cost = acc.half_area() * float(cnt) + rightCost[b + 1];
          if (cnt > 0 && cnt < count && cost < best) {
            best = cost;
            bestAxis = a;
            bestBin = b;
          }
        }
      }
      float parentArea = rb.bounds.half_area();
      float splitCost = kTraversalCost + kIntersectCost * best / std::max(parentArea, 1e-30f);
      float leafCost = kIntersectCost * float(count);
      if (bestAxis < 0 || (splitCost >= leafCost && count <= maxLeaf)) {
        if (count <= maxLeaf) return make_leaf(nodeIndex, begin, end, depth);
        mid = median_split(begin, end, axis);
      } else {
        float lo = rb.centroids.lo[bestAxis];
        float scale = float(kBins) / extent[bestAxis];
        mid = partition(begin, end, [&](uint32_t p) { return bin_of(centroids_[p][bestAxis], lo, scale) <= bestBin; });
        if (mid == begin || mid == end) mid = median_split(begin, end, bestAxis);
      }
    }

    uint32_t left = nodeCount_.fetch_add(2);
    set_interior(nodeIndex, left);
    if (count >= kParallelThreshold) {
      tasks.run([=, &tasks] { build_node(left, begin, mid, depth + 1, tasks); });
      build_node(left + 1, mid, end, depth + 1, tasks);
    } else {
      build_node(left, begin, mid, depth + 1, tasks);
      build_node(left + 1, mid, end, depth + 1, tasks);
    }
  }

  const BvhInput& in_;
  AcceleratorSettings settings_;
  std::vector<glm::vec3> centroids_;
  std::vector<shader::BvhNode> nodes_;
  std::vector<uint32_t> order_;
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

}  // namespace

Bvh build_bvh(const BvhInput& input, const AcceleratorSettings& settings) {
  auto start = std::chrono::steady_clock::now();
  Bvh bvh = Builder(input, settings).build();
  bvh.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!input.bounds.empty()) bvh.sahCost = sah_cost(bvh.nodes);
  return bvh;
}

}  // namespace wp
