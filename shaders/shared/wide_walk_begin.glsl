// wide_walk_begin.glsl — starts the wide BVH walk of the ray o + t d, t in
// (0, tmax): sets the locals of wide_walk_state.glsl and hit. A fragment of a
// function body, not a header: see wide_walk_step.glsl.
{
  hit = no_hit(tmax);
  ro = o;
  rd = d;
  instance = WP_INVALID;
  WP_WIDE_WALK_AIM();
  sp = 0u;
  primGroupsSetAside = 0u;
  visit = 0u;
  nodeGroup = uvec2(0u, 0u);
  primGroup = uvec2(0u, 0u);
}
