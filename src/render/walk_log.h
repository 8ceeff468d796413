// walk_log.h — what one BVH walk did, iteration by iteration: the phases of
// each iteration of the walk's loop and the records and stack entries it
// touched. The CPU traversal fills it where SceneView::walkLog is set
// (shader_cpp.h); the SIMT model (src/bench/simt_model.h) replays such logs
// in lockstep, as a GPU's warp runs the kernels' loop.
#pragma once

#include <cstdint>
#include <vector>

// The phases of an iteration (bits), named by the walks' WP_NOTE_PHASE
// (traverse_binary.glsl, wide_walk_step.glsl).
#define WALK_PHASE_PRIM 1u       // tested a primitive, or an instance's box
#define WALK_PHASE_NODE 2u       // visited a node: tested its children's boxes
#define WALK_PHASE_POP 4u        // took the top of the stack
#define WALK_PHASE_LEAF 8u       // the binary walk: took a leaf's range of primitives
#define WALK_PHASE_INSTANCE 16u  // entered an instance
#define WALK_PHASES 5
// Not a phase, a note beside one: the iteration's node lay in an instance's
// tree (not the top level's). The SIMT model splits node visits by it.
#define WALK_NOTE_NODE_IN_INSTANCE 32u

namespace wp {

// What an access reads or writes: a 16-byte texel of a record buffer, or an
// entry of the walk's stack.
enum class WalkMemory : uint8_t { Nodes, Primitives, Instances, Other, StackRead, StackWrite };
constexpr int kWalkMemoryKinds = 6;

struct WalkAccess {
  WalkMemory kind;
  uint32_t index;  // texel, or stack entry
};

struct WalkIteration {
  uint32_t firstAccess;  // this iteration's accesses run to the next one's first
  uint32_t phases;       // WALK_PHASE_* bits
};

struct WalkLog {
  std::vector<WalkIteration> iterations;
  // Accesses before the first iteration are the walk's prologue (the binary
  // walk's root, for one).
  std::vector<WalkAccess> accesses;
  uint32_t deepestStack = 0;

  void clear() {
    iterations.clear();
    accesses.clear();
    deepestStack = 0;
  }
  void step() { iterations.push_back(WalkIteration{uint32_t(accesses.size()), 0u}); }
  void phase(uint32_t p) {
    if (!iterations.empty()) iterations.back().phases |= p;
  }
  void access(WalkMemory kind, uint32_t index) { accesses.push_back(WalkAccess{kind, index}); }
  void stack_depth(uint32_t sp) {
    if (sp > deepestStack) deepestStack = sp;
  }
  // The accesses of iteration i: [begin, end); prologue_end() is the first
  // iteration's start.
  uint32_t prologue_end() const { return iterations.empty() ? uint32_t(accesses.size()) : iterations[0].firstAccess; }
  uint32_t end_of(size_t i) const {
    return i + 1 < iterations.size() ? iterations[i + 1].firstAccess : uint32_t(accesses.size());
  }
};

}  // namespace wp
