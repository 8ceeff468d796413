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
if (FEATURE_COMPILED(FEATURE_INSTANCES) && enter) {
  WP_NOTE_PHASE(WALK_PHASE_INSTANCE);
  // Set aside the top level's node group, its node still to visit (as a
  // group of that one node, in slot 0 for this ray's order), its primitive
  // group, then the way back, which keeps the count of primitive groups set
  // aside: the instance's walk starts with none.
  if ((nodeGroup.y & WIDE_NODE_BITS) != 0u) {
    WP_WIDE_PUSH(nodeGroup);
  }
  if (visit != WP_INVALID) {
    WP_WIDE_PUSH(uvec2(visit, 1u << (24u + xorSlot)));
  }
  if (primGroup.y != 0u) {
    WP_WIDE_PUSH(primGroup);
    primGroupsSetAside += 1u;
  }
  WP_WIDE_PUSH(uvec2(primGroupsSetAside, INSTANCE_RETURN_Y));
  WP_NOTE_STACK_DEPTH(sp);
  primGroupsSetAside = 0u;
  nodeGroup = uvec2(0u, 0u);
  primGroup = uvec2(0u, 0u);
  instance = stepTri.shading;
  Instance inst = load_instance(instance);
  ro = xform_point(inst.toObject0, inst.toObject1, inst.toObject2, o);
  rd = xform_vector(inst.toObject0, inst.toObject1, inst.toObject2, d);
  WP_WIDE_WALK_AIM();
  visit = inst.root;
}
// A node waits while it might bring a primitive group that there is no
// room to set aside.
if (!walkDone && !enter && visit != WP_INVALID && (primGroupsSetAside < WIDE_STACK_PRIM_GROUPS || primGroup.y == 0u)) {
  WP_NOTE_PHASE(WALK_PHASE_NODE);
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
  uint bits = wide_child_bits(0u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t) |
              wide_child_bits(1u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t) |
              wide_child_bits(2u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t) |
              wide_child_bits(3u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t) |
              wide_child_bits(4u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t) |
              wide_child_bits(5u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t) |
              wide_child_bits(6u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t) |
              wide_child_bits(7u, meta, nearX, farX, nearY, farY, nearZ, farZ, scale, base, hit.t);
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
  nodeGroup = uvec2(n.childBase, (bits & WIDE_NODE_BITS) | imask);
  if (prims != 0u) primGroup = uvec2(n.primBase, prims);
  visit = WP_INVALID;
}
// With no node group left, take the top of the stack: a node group at
// once, a primitive group once the current one is done, the way back out of
// an instance once nothing of its walk remains.
if ((nodeGroup.y & WIDE_NODE_BITS) == 0u && sp > 0u) {
  WP_NOTE_PHASE(WALK_PHASE_POP);
  WP_NOTE_STACK_READ(sp - 1u);
  uvec2 top = inRegisters ? regs[0u] : stack[sp - 1u];
  bool isNodes = (top.y & WIDE_NODE_BITS) != 0u;
  bool isReturn = FEATURE_COMPILED(FEATURE_INSTANCES) && top.y == INSTANCE_RETURN_Y;
  bool pop = isNodes || (primGroup.y == 0u && (!isReturn || visit == WP_INVALID));
  if (inRegisters) {
    WP_REGISTER_STACK_UP(regs, pop);
  }
  if (pop) {
    sp -= 1u;
    if (isNodes) {
      nodeGroup = top;
    } else if (isReturn) {
      primGroupsSetAside = top.x;
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
    uint bit = uint(findMSB(nodeGroup.y));
    nodeGroup.y &= ~(1u << bit);
    uint slot = (bit - 24u) ^ xorSlot;
    visit = nodeGroup.x + uint(bitCount(nodeGroup.y & ((1u << slot) - 1u) & 0xffu));
  } else if (primGroup.y == 0u && (!FEATURE_COMPILED(FEATURE_INSTANCES) || sp == 0u)) {
    walkDone = true;  // nothing to visit or test, and the stack is empty
  }
}
