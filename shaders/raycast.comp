#version 460
// Ray casting without shading: the closest (or any) hit for each ray of a
// fixed set (read from the shadow-ray buffer: origin, tmax, direction),
// through the same loop as extend (trace_items.glsl). Used by the BVH tests
// and the traversal benchmark.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "shared/kernel.glsl"

// Constant 10: any hit instead of the closest (the benchmark's shadow rays):
// a hit with a valid prim means the segment is blocked.
layout(constant_id = SPEC_ANY_HIT) const bool kAnyHit = false;
#define TRACE_ANY_HIT kAnyHit

uint trace_item_count() {
  return pc.pathCount;
}

void trace_item_ray(uint item, out vec3 o, out vec3 d, out float tmax, out uint tag) {
  ShadowRay r = read_shadow_ray(pc.waveStart + item);
  o = r.origin;
  d = r.dir;
  tmax = r.tmax;
  tag = 0u;
}

void trace_item_done(uint item, uint tag, Hit h, bool truncated) {
  write_hit(item, h);
}

#include "shared/trace_items.glsl"

void main() {
  trace_items();
}
