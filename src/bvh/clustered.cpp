// The clustered SAH build's top levels (SplitMethod::ClusteredSah; see the
// Builder's comment): Morton order, clusters, binned SAH over clusters, and
// the hand-off of small nodes to build_node.
#include "bvh/builder.h"

namespace wp::build {

void Builder::build_clustered() {
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

void Builder::cluster_run(uint32_t b, uint32_t e, uint32_t limit, std::vector<PrimRef>& out) const {
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

std::vector<PrimRef> Builder::make_clusters() const {
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

void Builder::build_top(const ClusterTask& t, tbb::task_group& tasks, NodeBlock& block) {
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

bool Builder::cluster_split(const ClusterTask& t, ClusterTask& l, ClusterTask& r) {
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

void Builder::hand_off(const ClusterTask& t, tbb::task_group& tasks, NodeBlock& block) {
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

}  // namespace wp::build
