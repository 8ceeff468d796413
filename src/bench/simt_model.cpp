// The SIMT model of the walks (simt_model.h).
#include "bench/simt_model.h"

#include <algorithm>
#include <array>
#include <functional>
#include <mutex>

#include <tbb/parallel_for.h>

#include "gpu/wavefront.h"
#include "render/shader_cpp.h"
#include "util/error.h"

namespace wp {

const GpuModel& gpu_model(const std::string& name) {
  // NVIDIA H200 (Hopper GH100, 132 SMs): the clock measured while the
  // kernels ran (docs/benchmarks.md); four schedulers an SM, each issuing one
  // warp instruction a clock; L1 takes one 128-byte line of a load a clock,
  // texel fetches one quad of lanes a clock; L2 about 5.5 TB/s
  // for the chip (shared by the SMs: 5.5e12 / 132 / 1.98e9 / 32 sectors a
  // clock an SM); 256 KiB of L1 and shared memory an SM, most of it L1 for
  // kernels without shared memory; latencies as microbenchmarks of Hopper
  // report them (L1 about 35 clocks, L2 about 260). The tracing kernels keep
  // 43-67 registers a lane (`info --kernels` on the H200): about 24 warps.
  // A dependent instruction waits about 4 clocks for its operand; the walks'
  // code has about two independent chains, so a warp issues one every 2.
  static const GpuModel h200{"h200", 132, 1.98, 24, 4.0, 1.0, 5.5e12 / 132.0 / 1.98e9 / 32.0, 192u * 1024u, 16u, 35.0, 260.0, 2.0};
  if (name == h200.name) return h200;
  throw InputError("unknown GPU model \"" + name + "\" for the SIMT model (known: h200)");
}

SimtWalk simt_walk(const std::string& variant, const CompiledScene& cs) {
  const KernelVariant& v = kernel_variant(variant);
  SimtWalk w;
  w.variant = v.name;
  w.wide = cs.params.accel.x == BVH_LAYOUT_WIDE;
  // On a GPU `gpu` keeps the wide walk's stack in an indexed array and walks
  // one ray per invocation (pipelines.cpp); the binary walk always indexes.
  w.indexedStack = !w.wide || v.settings.stack != TraversalStack::Registers;
  w.stackSlots = cs.params.accel.z;
  w.raysPerLane = w.wide && v.settings.raysPerInvocation > 1 ? v.settings.raysPerInvocation : 1u;
  w.nearestFirst = w.wide && cs.params.accel.y == WIDE_ORDER_DISTANCE;
  w.rootAtEntry = w.wide && (cs.params.accel.w & WALK_ROOT_AT_ENTRY) != 0u;
  w.binaryFused = !w.wide && (cs.params.accel.w & WALK_BINARY_FUSED) != 0u;
  w.walkLoads = v.settings.walkLoads;
  return w;
}

WalkCosts walk_costs(const SimtWalk& walk) {
  // Operations a lane executes, counted from the GLSL: each texel fetch and
  // its address, each arithmetic operation, compare and select (a byte
  // extracted and converted counts two). They are estimates, good to about
  // a third: enough to weigh phases against each other, not a compiler's
  // count.
  WalkCosts c;
  if (walk.wide) {
    c.iteration = 27.0;  // the step's two loads (5 + 3 texels), picking the next node (findMSB, bitCount), the cap
    c.phase[0] = 53.0;   // prim: the watertight triangle test (shear, edge functions, t) and the hit's update
    c.phase[1] = 330.0;  // node: the grid's scale and base, the planes facing the ray, the meta bytes permuted, eight slab tests
    c.phase[2] = 12.0;   // pop: the top entry, what kind it is
    c.phase[3] = 0.0;    // (no leaf phase: primitive groups come with their node)
    c.phase[4] = 70.0;   // instance: its transform read, the ray taken into it, the pushes
    if (walk.nearestFirst) {
      c.iteration -= 4.0;  // the next node is the lowest rank: no findMSB, no bitCount
      c.phase[1] += 125.0; // the keys and the ranks (61), 19 comparators of two operations, the ranks packed (24)
    }
    if (walk.rootAtEntry) c.phase[4] += 12.0;  // the root's 5 texels and their address
    c.stackMovePerSlot = walk.indexedStack ? 0.0 : 2.0;  // a uvec2 entry through two selects
    c.rayStart = 40.0;   // the next ray: its record, the walk's constants, the ballots
  } else {
    c.iteration = 6.0;   // the cap and the branch tests
    c.phase[0] = 57.0;   // prim: the triangle's 3 texels, the test, the hit's update
    c.phase[1] = 57.0;   // node: two children's 4 texels, two slab tests, near first, the push
    c.phase[2] = 6.0;    // pop
    c.phase[3] = 3.0;    // leaf: its range
    c.phase[4] = 60.0;   // instance
    if (walk.binaryFused) {
      c.iteration += 4.0;  // each phase's test every iteration, and the end's
      c.phase[2] += 3.0;   // the top read before it is taken: the way back waits for the leaf
    }
  }
  return c;
}

namespace {

constexpr uint32_t kSectorBytes = 32, kLineBytes = 128;
constexpr int kWorkgroupSize = WORKGROUP_SIZE;
// Local memory holds each lane's stack entries interleaved by lane (the
// layout NVIDIA's compilers give it): word w of entry e of lane l in warp g
// lies at ((g * kStackEntries + e) * 2 + w) * width + l words.
constexpr uint64_t kStackEntries = 256;

// What a sector holds. Stack writes are apart: a store needs no fill from
// L2 (NVIDIA's L1 keeps byte masks), so they only take their place in L1.
enum Region : int { kNodes, kPrims, kStack, kOther, kStackWrites, kRegions };

Region region_of(WalkMemory kind) {
  switch (kind) {
    case WalkMemory::Nodes: return kNodes;
    case WalkMemory::Primitives: return kPrims;
    case WalkMemory::StackRead: return kStack;
    case WalkMemory::StackWrite: return kStackWrites;
    default: return kOther;
  }
}

// An SM's L1: sectored lines (a miss fills only its 32-byte sector), LRU
// within each set.
class L1Model {
 public:
  explicit L1Model(const GpuModel& gpu) : ways_(gpu.l1Ways), sets_(gpu.l1Bytes / kLineBytes / gpu.l1Ways) {
    lines_.assign(size_t(sets_) * ways_, Line{});
  }
  // Reads `sector` (or, with `write`, writes it whole): whether it was there.
  bool hit(uint64_t sector, bool write = false) {
    const uint64_t line = sector / (kLineBytes / kSectorBytes);
    const uint32_t bit = 1u << (sector % (kLineBytes / kSectorBytes));
    Line* set = &lines_[size_t(mix(line) % sets_) * ways_];
    ++clock_;
    Line* victim = set;
    for (uint32_t w = 0; w < ways_; ++w) {
      Line& l = set[w];
      if (l.valid && l.tag == line) {
        l.used = clock_;
        const bool present = write || (l.sectors & bit) != 0;
        l.sectors |= bit;
        return present;
      }
      if (!l.valid || l.used < victim->used) victim = &l;
    }
    *victim = Line{line, clock_, bit, true};
    return write;
  }

 private:
  struct Line {
    uint64_t tag = 0, used = 0;
    uint32_t sectors = 0;
    bool valid = false;
  };
  static uint64_t mix(uint64_t x) {
    x ^= x >> 29;
    x *= 0xbf58476d1ce4e5b9ull;
    return x ^ (x >> 32);
  }
  uint32_t ways_, sets_;
  uint64_t clock_ = 0;
  std::vector<Line> lines_;
};

// One warp's pass through the walk's loop (or a pass that starts rays), as
// the machine sees it.
struct WarpStep {
  bool iteration = false;  // a pass of the walk's loop (not a prologue)
  uint32_t activeLanes = 0;
  double issued = 0.0;     // instructions the warp issued
  double useful = 0.0;     // lanes' own instructions, summed
  uint32_t firstSector = 0, sectorCount = 0;  // the distinct sectors it touched (WarpTrace::sectors)
  std::array<uint32_t, kRegions> regionSectors{}, regionLines{};
  bool popsIndexedStack = false;  // a lane took the top of a stack in memory
  uint32_t wavefronts = 0;  // clocks of L1 (and texture unit) throughput its loads take
};

struct WarpTrace {
  std::vector<WarpStep> steps;
  std::vector<uint64_t> sectors;
  uint64_t rays = 0, laneIterations = 0;
  uint64_t nodeVisits = 0, instanceNodeVisits = 0;
  uint32_t deepestStack = 0;
};

uint64_t region_base(Region r) { return uint64_t(r + 1) << 44; }

// Lane l's access a as a byte address: a record texel, or a word of a stack
// entry (both words: the entry is a uvec2).
void addresses_of(const WalkAccess& a, uint64_t warp, uint32_t lane, int width, const SimtWalk& walk, std::vector<uint64_t>& out) {
  const Region r = region_of(a.kind);
  if (r == kStack || r == kStackWrites) {
    for (uint64_t w = 0; w < 2; ++w)
      out.push_back(region_base(kStack) + (((warp * kStackEntries + a.index) * 2 + w) * uint64_t(width) + lane) * 4);
  } else if (r == kNodes && walk.nodeStrideBytes != 0) {
    // Records of `texels`, in blocks of `records` (a wide node, or a binary
    // pair after the root, which takes a block of its own).
    const uint64_t texels = (walk.wide ? sizeof(shader::WideNode) : sizeof(shader::BvhNode)) / 16;
    const uint64_t records = walk.wide ? 1 : 2;
    const uint64_t record = a.index / texels + (walk.wide ? 0 : 1);
    out.push_back(region_base(r) + record / records * walk.nodeStrideBytes + (record % records * texels + a.index % texels) * 16);
  } else {
    out.push_back(region_base(r) + uint64_t(a.kind) * (uint64_t(1) << 40) + uint64_t(a.index) * 16);
  }
}

// Counts a step's accesses: each lane's accesses [begin, end) of its log.
struct LaneSlice {
  uint32_t lane;
  const WalkLog* log;
  uint32_t begin, end;
};

void count_accesses(WarpStep& step, WarpTrace& trace, const std::vector<LaneSlice>& slices, uint64_t warp, int width,
                    const SimtWalk& walk) {
  std::array<std::vector<uint64_t>, kRegions> byRegion;
  std::vector<uint64_t> scratch;
  uint32_t longest = 0;
  for (const LaneSlice& s : slices) longest = std::max(longest, s.end - s.begin);
  // The k-th access of each lane stands for one load instruction of the
  // warp. L1 handles a load one 128-byte line a clock (a "wavefront"); a
  // texel fetch also goes through the texture unit a quad of lanes a clock.
  // (The texture path's longer latency is not modelled.)
  for (uint32_t k = 0; k < longest; ++k) {
    std::vector<uint64_t> lines;
    uint32_t texelLanes = 0;
    for (const LaneSlice& s : slices) {
      if (s.begin + k >= s.end) continue;
      const WalkAccess& a = s.log->accesses[s.begin + k];
      scratch.clear();
      addresses_of(a, warp, s.lane, width, walk, scratch);
      const Region r = region_of(a.kind);
      if (!walk.walkLoads && r != kStack && r != kStackWrites) ++texelLanes;
      for (uint64_t addr : scratch) {
        lines.push_back(addr / kLineBytes);
        byRegion[r].push_back(addr);
      }
    }
    std::sort(lines.begin(), lines.end());
    const uint32_t distinct = uint32_t(std::unique(lines.begin(), lines.end()) - lines.begin());
    step.wavefronts += std::max(distinct, (texelLanes + 3) / 4);
  }
  step.firstSector = uint32_t(trace.sectors.size());
  for (int r = 0; r < kRegions; ++r) {
    std::vector<uint64_t>& v = byRegion[r];
    for (uint64_t& addr : v) addr /= kSectorBytes;
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    step.regionSectors[r] = uint32_t(v.size());
    trace.sectors.insert(trace.sectors.end(), v.begin(), v.end());
    uint32_t lines = 0;
    for (size_t i = 0; i < v.size(); ++i)
      if (i == 0 || v[i] / (kLineBytes / kSectorBytes) != v[i - 1] / (kLineBytes / kSectorBytes)) ++lines;
    step.regionLines[r] = lines;
  }
  step.sectorCount = uint32_t(trace.sectors.size()) - step.firstSector;
}

// What a warp issues for one pass: every phase that any active lane takes
// runs once for the warp, masked; the register stack moves all its slots
// where a node is visited (two pushes' worth) or the top is taken.
double phases_cost(uint32_t phases, const WalkCosts& c, const SimtWalk& walk) {
  double cost = c.iteration;
  for (int b = 0; b < WALK_PHASES; ++b)
    if (phases & (1u << b)) cost += c.phase[b];
  const double slots = double(walk.stackSlots);
  if (phases & WALK_PHASE_NODE) cost += 2.0 * slots * c.stackMovePerSlot;
  if (phases & WALK_PHASE_POP) cost += slots * c.stackMovePerSlot;
  return cost;
}

void cost_step(WarpStep& step, const std::vector<uint32_t>& lanePhases, const WalkCosts& c, const SimtWalk& walk) {
  uint32_t any = 0;
  for (uint32_t p : lanePhases) {
    any |= p;
    step.useful += phases_cost(p, c, walk);
  }
  step.issued = lanePhases.empty() ? 0.0 : phases_cost(any, c, walk);
  step.popsIndexedStack = walk.indexedStack && (any & WALK_PHASE_POP) != 0;
}

// Walks the warp's rays: `nextRay(lane)` gives a lane its next ray (or
// false), at the start and, with several rays per lane, whenever its ray ends
// (at the end of the pass in which some lane's ended, as trace_items.glsl).
template <class NextRay>
WarpTrace run_warp(const shader::SceneView& view, const std::vector<shader::ShadowRay>& rays, bool anyHit, uint64_t warp,
                   int width, const SimtWalk& walk, const WalkCosts& costs, NextRay nextRay) {
  WarpTrace trace;
  std::vector<WalkLog> logs(width);
  std::vector<int> position(width, -1);  // the lane's next iteration; -1: no ray
  shader::SceneView logging = view;
  auto start = [&](uint32_t lane) {
    size_t ray;
    if (!nextRay(lane, ray)) return false;
    logs[lane].clear();
    logging.walkLog = &logs[lane];
    shader::Hit hit;
    logging.trace_ray(rays[ray].origin, rays[ray].dir, rays[ray].tmax, anyHit, hit);
    trace.deepestStack = std::max(trace.deepestStack, logs[lane].deepestStack);
    trace.rays += 1;
    for (const WalkIteration& it : logs[lane].iterations) {
      trace.nodeVisits += (it.phases & WALK_PHASE_NODE) ? 1u : 0u;
      trace.instanceNodeVisits += (it.phases & WALK_NOTE_NODE_IN_INSTANCE) ? 1u : 0u;
    }
    position[lane] = 0;
    return true;
  };
  std::vector<LaneSlice> slices;
  std::vector<uint32_t> phases;
  auto starting_pass = [&](const std::vector<uint32_t>& lanes) {
    // The rays' prologues (and, with several rays a lane, taking them).
    WarpStep step;
    slices.clear();
    for (uint32_t l : lanes) {
      if (!start(l)) continue;
      slices.push_back(LaneSlice{l, &logs[l], 0u, logs[l].prologue_end()});
      step.activeLanes += 1;
    }
    if (slices.empty()) return false;
    const double each = walk.raysPerLane > 1 ? costs.rayStart : 0.0;
    step.issued = each;
    step.useful = each * double(slices.size());
    count_accesses(step, trace, slices, warp, width, walk);
    trace.steps.push_back(step);
    return true;
  };
  std::vector<uint32_t> all(width);
  for (int l = 0; l < width; ++l) all[l] = uint32_t(l);
  if (!starting_pass(all)) return trace;
  while (true) {
    WarpStep step;
    step.iteration = true;
    slices.clear();
    phases.clear();
    std::vector<uint32_t> ended;
    for (int l = 0; l < width; ++l) {
      if (position[l] < 0) continue;
      const WalkLog& log = logs[l];
      if (size_t(position[l]) >= log.iterations.size()) {
        ended.push_back(uint32_t(l));  // a walk that ended before its loop (an empty tree)
        position[l] = -1;
        continue;
      }
      const size_t i = size_t(position[l]);
      slices.push_back(LaneSlice{uint32_t(l), &log, log.iterations[i].firstAccess, log.end_of(i)});
      phases.push_back(log.iterations[i].phases);
      if (++position[l] == int(log.iterations.size())) {
        ended.push_back(uint32_t(l));
        position[l] = -1;
      }
    }
    if (!slices.empty()) {
      step.activeLanes = uint32_t(slices.size());
      trace.laneIterations += slices.size();
      cost_step(step, phases, costs, walk);
      count_accesses(step, trace, slices, warp, width, walk);
      trace.steps.push_back(step);
    }
    if (walk.raysPerLane > 1 && !ended.empty()) starting_pass(ended);
    if (std::none_of(position.begin(), position.end(), [](int p) { return p >= 0; })) break;
  }
  return trace;
}

struct Totals {
  SimtFigures f;
  double regionSectors[kRegions] = {}, regionLines[kRegions] = {};
  double sectorsRequested = 0.0, l1Hits = 0.0, l2Sectors = 0.0;
  double useful = 0.0, issuedLaneSlots = 0.0;  // lanes' instructions; instructions issued x width
  uint64_t nodeVisits = 0, instanceNodeVisits = 0;
  double bounds[4] = {};   // clocks of issue, L1, L2 and latency (the slowest SM's, once added)
  double smClocks = 0.0;   // the largest bound (the slowest SM's, once added)
  double smClocksSum = 0.0;  // over the SMs added
  void add(const Totals& o) {
    smClocksSum += o.smClocks;
    f.rays += o.f.rays;
    f.warps += o.f.warps;
    f.warpIterations += o.f.warpIterations;
    f.laneIterations += o.f.laneIterations;
    nodeVisits += o.nodeVisits;
    instanceNodeVisits += o.instanceNodeVisits;
    useful += o.useful;
    issuedLaneSlots += o.issuedLaneSlots;
    f.deepestStack = std::max(f.deepestStack, o.f.deepestStack);
    for (int r = 0; r < kRegions; ++r) {
      regionSectors[r] += o.regionSectors[r];
      regionLines[r] += o.regionLines[r];
    }
    sectorsRequested += o.sectorsRequested;
    l1Hits += o.l1Hits;
    l2Sectors += o.l2Sectors;
    if (o.smClocks > smClocks) {
      smClocks = o.smClocks;
      std::copy(o.bounds, o.bounds + 4, bounds);
    }
  }
};

}  // namespace

SimtFigures simulate_walks(const CompiledScene& cs, const std::vector<shader::ShadowRay>& rays, bool anyHit,
                           const SimtWalk& walk, const GpuModel& gpu, int width) {
  if (width <= 0 || kWorkgroupSize % width != 0) throw InputError("the SIMT model's warps must divide a workgroup of 64 lanes");
  SimtWalk sorted = walk;
  sorted.nearestFirst = walk.nearestFirst && !anyHit;  // WP_NEAREST_FIRST: any-hit walks keep the octant's order
  const WalkCosts costs = walk_costs(sorted);
  const shader::SceneView view = cs.view();
  const uint64_t n = rays.size();
  // Warps as the kernels launch them: one ray per invocation, warp w the
  // invocations [w * width, (w + 1) * width); or, with several rays a lane,
  // as many warps as the dispatch holds (n / raysPerLane invocations, and at
  // least a GPU's fill), warp sg taking entry q as item (sg + (q / width) * S)
  // * width + q % width.
  const uint64_t invocations = TRACING_INVOCATIONS(n, uint64_t(walk.raysPerLane), uint64_t(walk.fillInvocations));
  const uint64_t groups = (invocations + kWorkgroupSize - 1) / kWorkgroupSize;
  const uint64_t warpsPerGroup = uint64_t(kWorkgroupSize / width);
  const uint64_t warps = walk.raysPerLane > 1 ? groups * warpsPerGroup : (n + width - 1) / width;
  const uint64_t itemBlocks = (n + width - 1) / width;
  // Workgroups go to SMs in turn; each SM runs its warps in rounds of
  // residentWarps, which share its L1.
  std::vector<Totals> perSm(gpu.sms);
  tbb::parallel_for(0, gpu.sms, [&](int sm) {
    Totals& t = perSm[sm];
    L1Model l1(gpu);
    std::vector<double> warpClocks;  // each warp's own time, waiting on itself
    std::vector<uint64_t> mine;
    for (uint64_t g = uint64_t(sm); g * warpsPerGroup < warps; g += uint64_t(gpu.sms))
      for (uint64_t w = g * warpsPerGroup; w < std::min(warps, (g + 1) * warpsPerGroup); ++w) mine.push_back(w);
    for (size_t r0 = 0; r0 < mine.size(); r0 += size_t(gpu.residentWarps)) {
      const size_t r1 = std::min(mine.size(), r0 + size_t(gpu.residentWarps));
      std::vector<WarpTrace> round;
      for (size_t k = r0; k < r1; ++k) {
        const uint64_t warp = mine[k];
        if (walk.raysPerLane > 1) {
          uint64_t taken = 0;
          round.push_back(run_warp(view, rays, anyHit, warp, width, walk, costs, [&](uint32_t, size_t& ray) {
            const uint64_t q = taken++;
            const uint64_t block = warp + (q / width) * warps;
            if (block >= itemBlocks) return false;
            ray = size_t(block * width + q % width);
            return ray < n;
          }));
        } else {
          round.push_back(run_warp(view, rays, anyHit, warp, width, walk, costs, [&](uint32_t lane, size_t& ray) {
            ray = size_t(warp * width + lane);
            return ray < n;
          }));
        }
      }
      // The round's warps take turns, pass by pass, through the L1.
      std::vector<double> latency(round.size(), 0.0);
      size_t longest = 0;
      for (const WarpTrace& wt : round) longest = std::max(longest, wt.steps.size());
      for (size_t s = 0; s < longest; ++s) {
        for (size_t k = 0; k < round.size(); ++k) {
          const WarpTrace& wt = round[k];
          if (s >= wt.steps.size()) continue;
          const WarpStep& st = wt.steps[s];
          uint32_t misses = 0, i = st.firstSector;
          for (int r = 0; r < kRegions; ++r)
            for (uint32_t e = i + st.regionSectors[r]; i < e; ++i)
              if (!l1.hit(wt.sectors[i], r == kStackWrites)) ++misses;
          t.bounds[0] += st.issued / gpu.issuePerClock;
          t.bounds[1] += st.wavefronts / gpu.l1WavefrontsPerClock;
          t.bounds[2] += misses / gpu.l2SectorsPerClock;
          t.l2Sectors += misses;
          t.l1Hits += st.sectorCount - misses;
          t.sectorsRequested += st.sectorCount;
          // A pass waits for its loads (L2 if any missed; a pop from an
          // indexed stack first, since the loads' addresses come from it),
          // and its instructions wait for each other.
          latency[k] += st.issued * gpu.clocksPerInstruction + (st.popsIndexedStack ? gpu.l1Latency : 0.0) +
                        (misses > 0 ? gpu.l2Latency : st.sectorCount > 0 ? gpu.l1Latency : 0.0);
          for (int r = 0; r < kRegions; ++r) {
            t.regionSectors[r] += st.regionSectors[r];
            t.regionLines[r] += st.regionLines[r];
          }
          if (st.iteration) t.f.warpIterations += 1;
          t.useful += st.useful;
          t.issuedLaneSlots += st.issued * double(width);
        }
      }
      for (size_t k = 0; k < round.size(); ++k) {
        warpClocks.push_back(latency[k]);
        t.f.rays += round[k].rays;
        t.f.laneIterations += round[k].laneIterations;
        t.nodeVisits += round[k].nodeVisits;
        t.instanceNodeVisits += round[k].instanceNodeVisits;
        t.f.deepestStack = std::max(t.f.deepestStack, round[k].deepestStack);
      }
      t.f.warps += round.size();
    }
    // Latency: the SM holds residentWarps warps; each new one takes the first
    // slot to come free, in launch order.
    std::vector<double> slots(size_t(gpu.residentWarps), 0.0);
    for (double c : warpClocks) {
      std::pop_heap(slots.begin(), slots.end(), std::greater<double>());
      slots.back() += c;
      std::push_heap(slots.begin(), slots.end(), std::greater<double>());
    }
    t.bounds[3] = *std::max_element(slots.begin(), slots.end());
    t.smClocks = *std::max_element(t.bounds, t.bounds + 4);
  });
  Totals all;
  for (const Totals& t : perSm) all.add(t);
  SimtFigures f = all.f;
  f.phaseEfficiency = all.issuedLaneSlots > 0.0 ? all.useful / all.issuedLaneSlots : 0.0;
  f.iterationsPerWarp = f.warps ? double(f.warpIterations) / double(f.warps) : 0.0;
  f.simdEfficiency = f.warpIterations ? double(f.laneIterations) / (double(f.warpIterations) * width) : 0.0;
  f.stepsPerRay = f.rays ? double(f.laneIterations) / double(f.rays) : 0.0;
  f.nodeVisitsPerRay = f.rays ? double(all.nodeVisits) / double(f.rays) : 0.0;
  f.instanceNodeVisitsPerRay = f.rays ? double(all.instanceNodeVisits) / double(f.rays) : 0.0;
  const double iters = double(std::max<uint64_t>(f.warpIterations, 1));
  f.nodeSectors = all.regionSectors[kNodes] / iters;
  f.nodeLines = all.regionLines[kNodes] / iters;
  f.primSectors = all.regionSectors[kPrims] / iters;
  f.primLines = all.regionLines[kPrims] / iters;
  f.stackSectors = walk.indexedStack ? (all.regionSectors[kStack] + all.regionSectors[kStackWrites]) / iters : 0.0;
  f.stackLines = walk.indexedStack ? (all.regionLines[kStack] + all.regionLines[kStackWrites]) / iters : 0.0;
  f.otherSectors = all.regionSectors[kOther] / iters;
  const double raysD = double(std::max<uint64_t>(f.rays, 1));
  f.bytesPerRay = all.sectorsRequested * kSectorBytes / raysD;
  f.l1HitRate = all.sectorsRequested > 0.0 ? all.l1Hits / all.sectorsRequested : 0.0;
  f.l2BytesPerRay = (all.sectorsRequested - all.l1Hits) * kSectorBytes / raysD;
  // How busy the slowest SM keeps each resource; the busiest bounds it.
  if (all.smClocks > 0.0) {
    f.issueShare = all.bounds[0] / all.smClocks;
    f.l1Share = all.bounds[1] / all.smClocks;
    f.l2Share = all.bounds[2] / all.smClocks;
    f.latencyShare = all.bounds[3] / all.smClocks;
  }
  static const char* names[4] = {"issue", "L1", "L2", "latency"};
  f.bound = names[std::max_element(all.bounds, all.bounds + 4) - all.bounds];
  f.predictedRaysPerSecond = all.smClocks > 0.0 ? double(f.rays) / (all.smClocks / (gpu.clockGHz * 1e9)) : 0.0;
  f.smBalance = all.smClocks > 0.0 ? all.smClocksSum / double(gpu.sms) / all.smClocks : 0.0;
  return f;
}

}  // namespace wp
