// wide_walk_enter.glsl — the wide walk enters the instance whose box the
// iteration's primitive test met (wide_walk_step.glsl includes it, where the
// variant's order puts it). A fragment of a function body, not a header.
{
  WP_NOTE_PHASE(WALK_PHASE_INSTANCE);
  // Set aside the top level's node group, its node still to visit if this
  // iteration did not visit it (as a group of that one node, its first in
  // either order), its primitive group, then the way back, which keeps the
  // count of primitive groups set aside: the instance's walk starts with none.
  if ((nodeGroup.y & WIDE_NODE_BITS) != 0u) {
    WP_WIDE_PUSH(nodeGroup);
  }
  if (visit != WP_INVALID) {
    WP_WIDE_PUSH(uvec2(visit, WP_NEAREST_FIRST ? 1u << 24u : 1u << (24u + xorSlot)));
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
  if (ROOT_AT_ENTRY_OF_SCENE) {
    n = load_wide_node(visit);
  }
}
