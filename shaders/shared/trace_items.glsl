// trace_items.glsl — the loop of the tracing kernels (extend, connect,
// connect_multi, raycast): one dispatch traces a list of items, each one ray.
//
// On lavapipe an invocation is a lane of an 8-wide SIMD loop, and a loop runs
// until its slowest lane is done: with one ray per invocation, incoherent
// bounce rays kept fewer than half of the lanes busy. So with the wide BVH
// the lanes of a subgroup (the SIMD group) share about kRaysPerInvocation
// items each: a lane whose ray is done takes the subgroup's next item as
// soon as the subgroup leaves the inner walking loop, at the end of the pass
// in which some lane finished (subgroupBallot hands items out in lane
// order). The host asks for one ray per invocation on GPUs, and
// where it knows the rays are coherent (the ray-casting benchmark's camera
// rays and the shadow rays from their hits: their lanes finish together
// anyway).
//
// lavapipe's loop budget (65,535 iterations per invocation, all loops
// together) is shared: each ray gets a share of scene.counts.z (see
// trace_items), and one that needs more is counted as truncated. The host
// then runs the same work again one ray per invocation, each ray with the
// whole cap (wavefront.cpp), so only a ray that needs more than that fails a
// render.
//
// The including kernel defines, before including this file:
//   TRACE_ANY_HIT    true for shadow rays (the first hit ends the walk)
//   uint trace_item_count()   the items of this dispatch
//   void trace_item_ray(uint item, out vec3 o, out vec3 d, out float tmax, out uint tag)
//     the item's ray, and a word the kernel wants back with the result
//   void trace_item_done(uint item, uint tag, Hit hit, bool truncated)
//     its result: hit.prim is WP_INVALID for a miss, and for a truncated walk
// and calls trace_items() from main().

// Hands an item's result to the kernel; a truncated walk is counted and
// reported as a miss.
void finish_item(uint item, uint tag, Hit hit, bool truncated) {
  if (truncated) {
    atomicAdd(counters[COUNTER_TRUNCATED], 1u);
    hit.prim = WP_INVALID;
  }
  trace_item_done(item, tag, hit, truncated);
}

// One item, one walk with the whole step cap (where kRaysPerInvocation is 1).
void trace_one_item(uint item) {
  vec3 o;
  vec3 d;
  float tmax;
  uint tag;
  trace_item_ray(item, o, d, tmax, tag);
  Hit hit = no_hit(tmax);
  bool truncated = tmax > 0.0f && trace_ray(o, d, tmax, TRACE_ANY_HIT, hit) != TRACE_OK;
  finish_item(item, tag, hit, truncated);
}

// kDynamicFetch: the next block of items for the calling subgroup (uniform
// control flow), from COUNTER_TRACE_BLOCKS.
uint take_block() {
  uint got = 0u;
  if (subgroupElect()) got = atomicAdd(counters[COUNTER_TRACE_BLOCKS], 1u);
  return subgroupBroadcastFirst(got);
}

void trace_items() {
  uint count = trace_item_count();
  if (kRaysPerInvocation == 1u || BVH_LAYOUT_OF_SCENE != BVH_LAYOUT_WIDE) {
    uint item = dispatch_item(count);
    if (item < count) trace_one_item(item);
    return;
  }
  // The items in blocks of L (the subgroup's size) consecutive ones; the S
  // subgroups of the dispatch take every S-th block, so that each spans the
  // whole list (lavapipe gives each thread one contiguous run of workgroups),
  // and a subgroup's lanes take its blocks' items in turn, each lane its
  // next one as soon as its ray is done. Entry q of subgroup sg is item
  // (sg + (q / L) * S) * L + q % L; past the first item out of range, all
  // are. (Fixed shares of 16 rays per lane kept 0.70-0.82 of the lanes busy
  // on bounce rays, by a replay of the walks on the CPU; shared, 0.87-0.92.)
  // With kDynamicFetch a subgroup takes each block, from the first, as its
  // lanes come to need it, from a counter (COUNTER_TRACE_BLOCKS, zeroed
  // before each dispatch), so that subgroups that finish early take more:
  // row r of its entries is the block it took r-th. It takes at most twice
  // its fixed share of rows; since all subgroups together could take twice
  // the blocks, every block is taken, and the share bounds its loop budget.
  const uint lanes = gl_SubgroupSize;
  const uint subgroups = gl_NumWorkGroups.x * gl_NumSubgroups;
  const uint subgroup = gl_WorkGroupID.x * gl_NumSubgroups + gl_SubgroupID;
  const uint blocks = (count + lanes - 1u) / lanes;
  const uint rows = (blocks + subgroups - 1u) / subgroups;
  const uint rowsMax = kDynamicFetch ? 2u * rows : rows;
  if (!kDynamicFetch && subgroup >= blocks) return;
  // While a subgroup's entries last its lanes are all busy, so a lane's loop
  // runs at most (its share of the entries + 1) rays' caps: with every lane
  // present, rowsMax + 1 (rows is kRaysPerInvocation, or one more where the
  // dispatch rounds down). A subgroup cut short by the workgroup's size has
  // fewer lanes to share the same entries.
  // Both loops below count against the budget. Every pass of the outer loop
  // but the last ends with a lane finishing a ray, so it makes at most
  // rowsMax * lanes + 1 passes (the subgroup's entries), which are set aside;
  // the inner loop's passes are bounded by the rays' caps as above.
  const uint present = subgroupBallotBitCount(subgroupBallot(true));
  const uint outerPasses = min(rowsMax * lanes + 1u, scene.counts.z);
  uint cap = (scene.counts.z - outerPasses) / ((rowsMax * lanes + present - 1u) / present + 1u);
  const bool anyHit = TRACE_ANY_HIT;
  vec3 o;
  vec3 d;
  float tmax;
  uint tag;
  Hit hit;
#include "wide_walk_state.glsl"
  uint item = 0u;
  uint steps = 0u;
  uint taken = 0u;  // entries handed out so far (the same in every lane)
  // kDynamicFetch: the blocks of rows `row` and row + 1 (the latter taken
  // once a lane needs an entry of it). Subgroup-uniform.
  uint row = WP_INVALID;
  uint block = 0u;
  uint nextBlock = 0u;
  bool haveNext = false;
  bool needRay = true;
  while (true) {
    uvec4 needing = subgroupBallot(needRay);
    uint entry = taken + subgroupBallotExclusiveBitCount(needing);
    uint needed = subgroupBallotBitCount(needing);
    if (kDynamicFetch && needed > 0u) {
      uint firstRow = taken / lanes;
      uint lastRow = (taken + needed - 1u) / lanes;
      if (firstRow != row && firstRow < rowsMax) {
        block = haveNext ? nextBlock : take_block();
        row = firstRow;
        haveNext = false;
      }
      if (lastRow != row && !haveNext && lastRow < rowsMax) {
        nextBlock = take_block();
        haveNext = true;
      }
    }
    taken += needed;
    if (needRay) {
      uint r = entry / lanes;
      if (kDynamicFetch) {
        item = r >= rowsMax ? count : (r == row ? block : nextBlock) * lanes + entry % lanes;
      } else {
        item = (subgroup + r * subgroups) * lanes + entry % lanes;
      }
      if (item >= count) break;
      trace_item_ray(item, o, d, tmax, tag);
#include "wide_walk_begin.glsl"
      steps = 0u;
      needRay = false;
    }
    // Walk until a lane's ray is done. lavapipe runs the ray start above
    // and the result's store below, masked, in every pass of the loop around
    // them, whether or not a lane needs them; in this inner loop they run
    // once per pass in which some lane finished, not once per step.
    bool truncated = false;
    bool finished = false;
    while (true) {
      steps += 1u;
      truncated = steps > cap;
      bool walkDone = false;
      if (!truncated) {
#include "wide_walk_step.glsl"
      }
      finished = walkDone || truncated;
      if (subgroupBallot(finished) != uvec4(0u)) break;
    }
    if (finished) {
      finish_item(item, tag, hit, truncated);
      needRay = true;
    }
  }
}
