// wide_walk_begin.glsl — starts the wide BVH walk of the ray o + t d, t in
// (0, tmax): sets the locals of wide_walk_state.glsl and hit. A fragment of a
// function body, not a header: see wide_walk_step.glsl.
{
  hit.t = tmax;
  hit.prim = WP_INVALID;
  hit.u = 0.0f;
  hit.v = 0.0f;
  sh = make_ray_shear(d);
  // A zero direction component becomes a tiny one, so that no slab distance
  // is 0 * inf: the result differs only for rays exactly in a box's face.
  vec3 dd = vec3(abs(d.x) < 1e-20f ? 1e-20f : d.x, abs(d.y) < 1e-20f ? 1e-20f : d.y, abs(d.z) < 1e-20f ? 1e-20f : d.z);
  invDir = vec3(1.0f) / dd;
  negX = invDir.x < 0.0f;
  negY = invDir.y < 0.0f;
  negZ = invDir.z < 0.0f;
  // Slot order for this ray: the builder put the child lying towards octant
  // s in slot s, and the walk takes the highest bit first, so bit 24 + (s ^
  // xorSlot) puts the child facing the ray's origin first.
  xorSlot = (negX ? 0u : 1u) | (negY ? 0u : 2u) | (negZ ? 0u : 4u);
  sp = 0u;
  primGroupsSetAside = 0u;
  visit = 0u;
  nodeGroup = uvec2(0u, 0u);
  primGroup = uvec2(0u, 0u);
}
