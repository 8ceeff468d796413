#version 460
// Stage 5: add each finished path's radiance to its pixel's sums. A wave holds
// each pixel at most once, so plain read-modify-write is race free. Non-finite
// samples are counted and dropped, never allowed to poison a pixel.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.pathCount) return;
  PathState p = paths[i];
  if (!radiance_is_finite(p.radiance)) {
    atomicAdd(counters[COUNTER_NONFINITE], 1u);
    return;
  }
  vec3 l = p.radiance;
  PixelAccum a = accum[p.pixel];
  a.sum += vec4(l, 1.0f);
  float y = illuminance(l);
  a.sumSq += vec4(l * l, y * y);  // w: for adaptive sampling
  accum[p.pixel] = a;
}
