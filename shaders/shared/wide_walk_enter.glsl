// wide_walk_enter.glsl — the wide walk enters the instance whose box the
// iteration's primitive test met (wide_walk_step.glsl includes it, where the
// variant's order puts it). A fragment of a function body, not a header.
{
  WP_NOTE_PHASE(WALK_PHASE_INSTANCE);
  // Set aside the top level's node group, with its node still to visit if
  // this iteration did not visit it (taken back into the group, nearest
  // first; otherwise a group of that one node, its first in octant order),
  // then the way back, which keeps the rest of the primitive group and the
  // count of primitive groups set aside: the instance's walk starts with none.
  // At most two entries nearest first, three in octant order: each push
  // moves the whole register stack.
  if (WP_NEAREST_FIRST && visit != WP_INVALID) {
    nodeGroup.y = ((nodeGroup.y & WIDE_NODE_BITS) + (1u << 24u)) | ((nodeGroup.y & 0x001fffffu) << 3u) | (visit - nodeGroup.x);
  }
  if ((nodeGroup.y & WIDE_NODE_BITS) != 0u) {
    WP_WIDE_PUSH(nodeGroup);
  }
  if (!WP_NEAREST_FIRST && visit != WP_INVALID) {
    WP_WIDE_PUSH(uvec2(visit, 1u << (24u + xorSlot)));
  }
  WP_WIDE_PUSH(uvec2(WIDE_RETURN_X | (primGroupsSetAside << WIDE_RETURN_SET_ASIDE_SHIFT) | (primGroup.x & WIDE_RETURN_PRIM_MASK),
                     primGroup.y));
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
  if (ROOT_AT_ENTRY_OF_SCENE) {
    n = load_wide_node(visit);
  }
}
