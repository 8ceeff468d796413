// builder.h — the BVH builder (binned SAH, the exact sweep at the bottom,
// and the clustered build's top levels in clustered.cpp). Internal to src/bvh.
#pragma once

#include "bvh/build_parts.h"

namespace wp::build {

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
  void build_clustered();

  // Clusters: runs of the Morton order split at their highest differing code
  // bit until each holds at most `limit` primitives, so each lies in one
  // octree cell. A run whose box is far larger than its cell holds a large
  // primitive (a floor under a mesh) and is split further, down to single
  // primitives, so that the large one does not drag its neighbours up the
  // tree. Appends them to `out` as references: bounds, first sorted
  // reference (id) and count (pad).
  void cluster_run(uint32_t b, uint32_t e, uint32_t limit, std::vector<PrimRef>& out) const;

  // Where the sorted run [b, e) (codes cb to ce) splits: at its highest
  // differing code bit, or in the middle when all its codes are equal.
  uint32_t split_run(uint32_t b, uint32_t e, uint32_t cb, uint32_t ce) const {
    if (cb == ce) return b + (e - b) / 2;
    const uint32_t bit = 1u << (31 - __builtin_clz(cb ^ ce));
    return uint32_t(std::partition_point(keys_ + b, keys_ + e, [bit](uint64_t k) { return (uint32_t(k >> 32) & bit) == 0; }) - keys_);
  }

  // All primitives' clusters, the runs of about n / 64 split in parallel.
  std::vector<PrimRef> make_clusters() const;

  // Top-level binned SAH over clusters, each weighing its primitives. A node
  // of at most kBottomMax primitives (or one cluster, or no split) is handed
  // on (hand_off).
  void build_top(const ClusterTask& t, tbb::task_group& tasks, NodeBlock& block);

  // Binned SAH over t's clusters, each counting as its primitives. Fills the
  // children and returns true, or returns false when no split has a finite
  // cost (the clusters' centroids coincide, or their bounds are not finite).
  bool cluster_split(const ClusterTask& t, ClusterTask& l, ClusterTask& r);

  // Builds the subtree of t's primitives: by the exact sweep straight from
  // the sorted references when few, else copied together into the first
  // reference array for build_node.
  void hand_off(const ClusterTask& t, tbb::task_group& tasks, NodeBlock& block);

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

}  // namespace wp::build
