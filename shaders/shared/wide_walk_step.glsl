// wide_walk_step.glsl — one iteration of the wide BVH walk (scene.glsl): test
// one primitive of the current primitive group, visit one node, take what the
// stack holds next. A fragment of a function body, not a header: trace_wide
// includes it in its loop, and trace_items.glsl in the loop that walks
// several rays per invocation, so both run the same code. It reads and writes
// the locals of wide_walk_state.glsl, reads o, d (the world ray) and anyHit,
// updates hit, and sets walkDone once the walk is over (with anyHit: at the
// first hit). Entering and leaving instances: see traverse_binary.glsl.
// This iteration's two loads come first, before either test, so that their
// cache misses overlap: on lavapipe the walk spent about a quarter of its time
// waiting on the node's and the primitive's loads, one after the other. (A
// lane with nothing to test or visit loads record 0.)
uint stepPrim = primGroup.x + uint(findLSB(primGroup.y));
Triangle stepTri = load_triangle(primGroup.y != 0u ? stepPrim : 0u);
WideNode n = load_wide_node(visit != WP_INVALID ? visit : 0u);
bool enter = false;
if (primGroup.y != 0u) {
  WP_NOTE_PHASE(WALK_PHASE_PRIM);
  primGroup.y &= primGroup.y - 1u;
  if (FEATURE_COMPILED(FEATURE_INSTANCES) && stepTri.material == PRIM_INSTANCE) {
    enter = meets_instance(stepTri, o, invDir, hit.t);
  } else {
    intersect_loaded_prim(stepPrim, stepTri, ro, rd, sh, instance, hit);
    walkDone = anyHit && hit.prim != WP_INVALID;
  }
}
// Entering an instance: with its root visited in the same iteration
// (ROOT_AT_ENTRY_OF_SCENE), before the node phase; otherwise after it, so
// that the iteration also visits the top level's waiting node, in the world's
// space, instead of setting it aside for an iteration of its own.
if (FEATURE_COMPILED(FEATURE_INSTANCES) && ROOT_AT_ENTRY_OF_SCENE && enter) {
#include "wide_walk_enter.glsl"
}
// A node waits while it might bring a primitive group that there is no
// room to set aside, and, in an iteration that enters an instance after it,
// while the instance's primitive group has more to test: that rest must be
// tested before this node's primitives, so it cannot go under them.
if (!walkDone && visit != WP_INVALID && (primGroupsSetAside < WIDE_STACK_PRIM_GROUPS || primGroup.y == 0u) &&
    (!enter || ROOT_AT_ENTRY_OF_SCENE || primGroup.y == 0u)) {
  WP_NOTE_PHASE(WALK_PHASE_NODE);
  WP_NOTE_PHASE(instance != WP_INVALID ? WALK_NOTE_NODE_IN_INSTANCE : 0u);
  vec3 cell = vec3(uintBitsToFloat((n.exyzImask & 0xffu) << 23u), uintBitsToFloat(((n.exyzImask >> 8u) & 0xffu) << 23u),
                   uintBitsToFloat(((n.exyzImask >> 16u) & 0xffu) << 23u));
  vec3 scale = cell * invDir;
  vec3 base = (n.origin - ro) * invDir;
  uvec2 loX = uvec2(n.qlo.x, n.qlo.y);
  uvec2 loY = uvec2(n.qlo.z, n.qlo.w);
  uvec2 loZ = uvec2(n.qloZqhiX.x, n.qloZqhiX.y);
  uvec2 hiX = uvec2(n.qloZqhiX.z, n.qloZqhiX.w);
  uvec2 hiY = uvec2(n.qhi.x, n.qhi.y);
  uvec2 hiZ = uvec2(n.qhi.z, n.qhi.w);
  uvec2 nearX = negX ? hiX : loX;
  uvec2 farX = negX ? loX : hiX;
  uvec2 nearY = negY ? hiY : loY;
  uvec2 farY = negY ? loY : hiY;
  uvec2 nearZ = negZ ? hiZ : loZ;
  uvec2 farZ = negZ ? loZ : hiZ;
  uint imask = n.exyzImask >> 24u;
  uvec2 meta = uvec2(permute_meta(n.meta0123, imask & 15u, xorSlot), permute_meta(n.meta4567, imask >> 4u, xorSlot));
  // Eight explicit calls, not a loop: a loop would count against lavapipe's budget.
  float t0, t1, t2, t3, t4, t5, t6, t7;
  uint b0 = wide_child_bits(0u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t, t0);
  uint b1 = wide_child_bits(1u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t, t1);
  uint b2 = wide_child_bits(2u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t, t2);
  uint b3 = wide_child_bits(3u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t, t3);
  uint b4 = wide_child_bits(4u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t, t4);
  uint b5 = wide_child_bits(5u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t, t5);
  uint b6 = wide_child_bits(6u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t, t6);
  uint b7 = wide_child_bits(7u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t, t7);
  uint bits = b0 | b1 | b2 | b3 | b4 | b5 | b6 | b7;
  // The node group's y: the hit interior slots' bits (24-31, in the ray's
  // octant order) and imask (0-7), or, nearest first, their count (24-27)
  // and their ranks among the interior children, 3 bits each, the nearest
  // lowest (0-23).
  uint groupBits = (bits & WIDE_NODE_BITS) | imask;
  if (WP_NEAREST_FIRST) {
    uint r1 = imask & 1u;
    uint r2 = r1 + ((imask >> 1u) & 1u);
    uint r3 = r2 + ((imask >> 2u) & 1u);
    uint r4 = r3 + ((imask >> 3u) & 1u);
    uint r5 = r4 + ((imask >> 4u) & 1u);
    uint r6 = r5 + ((imask >> 5u) & 1u);
    uint r7 = r6 + ((imask >> 6u) & 1u);
    uint k0 = wide_child_key(b0, t0, 0u);
    uint k1 = wide_child_key(b1, t1, r1);
    uint k2 = wide_child_key(b2, t2, r2);
    uint k3 = wide_child_key(b3, t3, r3);
    uint k4 = wide_child_key(b4, t4, r4);
    uint k5 = wide_child_key(b5, t5, r5);
    uint k6 = wide_child_key(b6, t6, r6);
    uint k7 = wide_child_key(b7, t7, r7);
    groupBits = wide_nearest_first(uint(bitCount(bits & WIDE_NODE_BITS)), k0, k1, k2, k3, k4, k5, k6, k7);
  }
  // Set aside what is left of the current node group, and the current
  // primitive group when this node brings a new one.
  bool pushNodes = (nodeGroup.y & WIDE_NODE_BITS) != 0u;
  uint prims = bits & ~WIDE_NODE_BITS;
  bool pushPrims = prims != 0u && primGroup.y != 0u;
  uint pushes = (pushNodes ? 1u : 0u) + (pushPrims ? 1u : 0u);
  if (pushNodes) {
    WP_NOTE_STACK_WRITE(sp);
  }
  if (pushPrims) {
    WP_NOTE_STACK_WRITE(sp + (pushNodes ? 1u : 0u));
  }
  if (inRegisters) {
    WP_REGISTER_STACK_DOWN(regs, pushNodes);
    regs[0u] = pushNodes ? nodeGroup : regs[0u];
    WP_REGISTER_STACK_DOWN(regs, pushPrims);
    regs[0u] = pushPrims ? primGroup : regs[0u];
  } else {
    if (pushNodes) stack[sp] = nodeGroup;
    if (pushPrims) stack[sp + (pushNodes ? 1u : 0u)] = primGroup;
  }
  sp += pushes;
  WP_NOTE_STACK_DEPTH(sp);
  primGroupsSetAside += pushPrims ? 1u : 0u;
  nodeGroup = uvec2(n.childBase, groupBits);
  if (prims != 0u) primGroup = uvec2(n.primBase, prims);
  visit = WP_INVALID;
}
if (FEATURE_COMPILED(FEATURE_INSTANCES) && !ROOT_AT_ENTRY_OF_SCENE && enter) {
#include "wide_walk_enter.glsl"
}
// With no node group left, take the top of the stack: a node group at
// once, a primitive group once the current one is done, the way back out of
// an instance once nothing of its walk remains.
if ((nodeGroup.y & WIDE_NODE_BITS) == 0u && sp > 0u) {
  WP_NOTE_PHASE(WALK_PHASE_POP);
  WP_NOTE_STACK_READ(sp - 1u);
  uvec2 top = inRegisters ? regs[0u] : stack[sp - 1u];
  bool isNodes = (top.y & WIDE_NODE_BITS) != 0u;
  bool isReturn = FEATURE_COMPILED(FEATURE_INSTANCES) && !isNodes && (top.x & WIDE_RETURN_X) != 0u;
  bool pop = isNodes || (primGroup.y == 0u && (!isReturn || visit == WP_INVALID));
  if (inRegisters) {
    WP_REGISTER_STACK_UP(regs, pop);
  }
  if (pop) {
    sp -= 1u;
    if (isNodes) {
      nodeGroup = top;
    } else if (isReturn) {
      primGroupsSetAside = (top.x >> WIDE_RETURN_SET_ASIDE_SHIFT) & 3u;
      primGroup = uvec2(top.x & WIDE_RETURN_PRIM_MASK, top.y);
      instance = WP_INVALID;
      ro = o;
      rd = d;
      WP_WIDE_WALK_AIM();
    } else {
      primGroup = top;
      primGroupsSetAside -= 1u;
    }
  }
}
// The next node to visit, unless one is still waiting.
if (visit == WP_INVALID) {
  if ((nodeGroup.y & WIDE_NODE_BITS) != 0u) {
    if (WP_NEAREST_FIRST) {
      visit = nodeGroup.x + (nodeGroup.y & 7u);
      nodeGroup.y = ((nodeGroup.y & WIDE_NODE_BITS) - (1u << 24u)) | ((nodeGroup.y & 0x00ffffffu) >> 3u);
    } else {
      uint bit = uint(findMSB(nodeGroup.y));
      nodeGroup.y &= ~(1u << bit);
      uint slot = (bit - 24u) ^ xorSlot;
      visit = nodeGroup.x + uint(bitCount(nodeGroup.y & ((1u << slot) - 1u) & 0xffu));
    }
  } else if (primGroup.y == 0u && (!FEATURE_COMPILED(FEATURE_INSTANCES) || sp == 0u)) {
    walkDone = true;  // nothing to visit or test, and the stack is empty
  }
}
