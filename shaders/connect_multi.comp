#version 460
// Stage 4 with several light samples per vertex (CS184's -l): like
// connect.comp, but a path may own several shadow rays in one dispatch, so
// their contributions are added with float atomics (VK_EXT_shader_atomic_float;
// the renderer uses this kernel only when the device has them).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_float : require
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
  if (h.prim == WP_INVALID) {
    atomicAdd(paths[sr.path].radiance.x, sr.contribution.x);
    atomicAdd(paths[sr.path].radiance.y, sr.contribution.y);
    atomicAdd(paths[sr.path].radiance.z, sr.contribution.z);
  }
}
