#version 460
// Ray casting without shading: closest hit for each ray of a fixed set (read
// from the shadow-ray buffer: origin, tmax, direction). Used by the BVH tests
// and the traversal benchmark.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.pathCount) return;
  ShadowRay r = read_shadow_ray(pc.waveStart + i);
  Hit h;
  if (trace_ray(r.origin, r.dir, r.tmax, false, h) != TRACE_OK) {
    atomicAdd(counters[COUNTER_TRUNCATED], 1u);
    h.prim = WP_INVALID;
  }
  hits[i] = h;
}
