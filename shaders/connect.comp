#version 460
// Stage 4: shadow rays. An unoccluded segment adds its NEE contribution to its
// path (each path has at most one shadow ray per bounce: no atomics needed;
// connect_multi.comp handles several light samples per vertex).
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= counters[COUNTER_SHADOW]) return;
  ShadowRay sr = read_shadow_ray(i);
  Hit h;
  if (trace_ray(sr.origin, sr.dir, sr.tmax, true, h) != TRACE_OK) {
    atomicAdd(counters[COUNTER_TRUNCATED], 1u);
    return;
  }
  if (h.prim == WP_INVALID) paths[sr.path].radiance += sr.contribution;
}
