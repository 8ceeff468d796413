// simt_model.h — a SIMT model of the BVH walks, after Aila and Laine's
// simulator ("Understanding the Efficiency of Ray Traversal on GPUs", HPG
// 2009): rays are replayed through the CPU traversal, which runs the kernels'
// own walk code (shader_cpp.h), each walk logged iteration by iteration
// (walk_log.h); the rays are grouped in warps in the order the kernels launch
// them, and each warp's lanes advance in lockstep through the walk's loop.
// From that it counts what a GPU pays for and lavapipe does not show: lanes
// idle while others walk on, divergent phases run one after the other, the
// memory sectors and lines each warp iteration touches, and, through a cache
// model of an SM's L1, what reaches L2. A roofline of those counts against
// one GPU's published rates predicts each variant's rays per second; the
// prediction is for ordering variants, not a promise of a figure.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/compiled_scene.h"
#include "render/walk_log.h"

namespace wp {

// What the model assumes of a GPU: its published shape and rates, per SM.
struct GpuModel {
  std::string name;
  int sms = 0;
  double clockGHz = 0.0;
  int residentWarps = 0;          // warps of the tracing kernel an SM holds at once
  double issuePerClock = 0.0;     // warp instructions an SM issues per clock
  double l1WavefrontsPerClock = 0.0; // a load's 128-byte lines, or a texel fetch's quads of lanes, per clock
  double l2SectorsPerClock = 0.0; // 32-byte sectors L2 returns per clock, per SM
  uint32_t l1Bytes = 0;           // L1 capacity left to the kernel (no shared memory)
  uint32_t l1Ways = 0;
  double l1Latency = 0.0;         // clocks from a load to its use, hitting L1
  double l2Latency = 0.0;         // missing L1, hitting L2
  double clocksPerInstruction = 0.0;  // a warp's own pace through its instructions
};

// The models the command knows ("h200"); an unknown name is an InputError.
const GpuModel& gpu_model(const std::string& name);

// How a kernel variant walks: the tree it walks is the CompiledScene's.
struct SimtWalk {
  std::string variant;
  bool wide = true;           // the 8-wide walk (wide_walk_step.glsl), else the binary one
  bool indexedStack = true;   // the stack in an indexed array (local memory), else in registers
  uint32_t stackSlots = 0;    // the register stack's entries (TRAVERSAL_STACK_SLOTS)
  uint32_t raysPerLane = 1;   // 1: one ray per invocation; more: lanes take the next ray as theirs ends (trace_items.glsl)
  uint32_t fillInvocations = TRACING_INVOCATIONS_ON_GPUS;  // with raysPerLane > 1, the dispatch's fewest invocations, rays permitting
  bool walkLoads = false;     // nodes and primitives read by loads (variants *-loads), not through the texture unit
  bool nearestFirst = false;  // the wide walk sorts a node's hit children by distance (WIDE_ORDER_DISTANCE; closest hits only)
  bool rootAtEntry = false;   // entering an instance loads its root and visits it in the same iteration
  bool binaryFused = false;   // the binary walk tests a primitive and visits a node in one iteration
  // The nodes' layout in memory: 0, the records' own (80 bytes a wide node,
  // 32 a binary one, back to back, the binary root alone before its pairs of
  // siblings); else each wide node, or each binary pair of siblings (which
  // the walk loads together), this many bytes apart (128 or 64: one a cache
  // line, or half of one), a layout modelled before it is built.
  uint32_t nodeStrideBytes = 0;
};

// The walk a kernel variant runs on a GPU (where `gpu` picks the indexed
// stack and one ray per invocation), over the tree compiled for it.
SimtWalk simt_walk(const std::string& variant, const CompiledScene& cs);

// Instructions a lane spends on each phase of an iteration, counted from the
// walks' code (simt_model.cpp says how): a warp runs a phase once if any of
// its lanes takes it.
struct WalkCosts {
  double iteration = 0.0;  // every iteration: the loop's bookkeeping and its loads' addresses
  double phase[WALK_PHASES] = {};  // by WALK_PHASE_* bit: prim, node, pop, leaf, instance
  double stackMovePerSlot = 0.0;   // the register stack: one entry moved through selects
  double rayStart = 0.0;           // several rays per lane: taking the next ray
};
WalkCosts walk_costs(const SimtWalk& walk);

struct SimtFigures {
  uint64_t rays = 0, warps = 0;
  uint64_t warpIterations = 0;  // iterations of the walk's loop, summed over warps
  uint64_t laneIterations = 0;  // iterations that lanes with a ray took
  double simdEfficiency = 0.0;  // laneIterations / (warpIterations * width)
  double phaseEfficiency = 0.0; // lanes' instructions / (instructions the warps issued * width)
  double iterationsPerWarp = 0.0;
  double stepsPerRay = 0.0;     // the walk's iterations per ray (bench --raycast's "walk steps")
  // Of those, the iterations that visited a node, and of these the ones in an
  // instance's tree. Node visits bound a walk's iterations from below (an
  // iteration visits at most one).
  double nodeVisitsPerRay = 0.0, instanceNodeVisitsPerRay = 0.0;
  // Per warp iteration, over its active lanes: distinct 32-byte sectors and
  // 128-byte lines, by what they hold.
  double nodeSectors = 0.0, nodeLines = 0.0;
  double primSectors = 0.0, primLines = 0.0;
  double stackSectors = 0.0, stackLines = 0.0;  // local memory (indexed stacks)
  double otherSectors = 0.0;                    // instances, materials of cut-outs
  double bytesPerRay = 0.0;                     // sectors requested x 32 / rays
  double l1HitRate = 0.0;
  double l2BytesPerRay = 0.0;                   // sectors past L1 x 32 / rays
  uint32_t deepestStack = 0;
  // The prediction: an SM takes as long as the largest of four bounds: its
  // instructions at its issue rate, its loads at L1's rate, its misses at
  // its share of L2's, and its warps' own times (instructions and loads in
  // sequence) spread over its resident warp slots. The slowest SM sets the
  // time; the shares are how busy it keeps each (1: the bound).
  double issueShare = 0.0, l1Share = 0.0, l2Share = 0.0, latencyShare = 0.0;
  double predictedRaysPerSecond = 0.0;
  std::string bound;
  // The mean SM's time over the slowest's (1: balanced): SMs take their
  // workgroups in turn, so this is the most that fetching work dynamically
  // across SMs (persistent threads) could gain.
  double smBalance = 0.0;
};

// Replays `rays` (closest hit, or any hit) through the walk of `cs` in warps
// of `width` lanes on `gpu`. Deterministic: the same inputs give the same
// figures on any machine.
SimtFigures simulate_walks(const CompiledScene& cs, const std::vector<shader::ShadowRay>& rays, bool anyHit,
                           const SimtWalk& walk, const GpuModel& gpu, int width);

}  // namespace wp
