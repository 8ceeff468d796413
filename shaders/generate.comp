#version 460
// Stage 1: one camera ray per pixel and sample of the wave (consecutive
// pixels, or those of the adaptive sampler's list); every path enters queue 0.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i == 0u) counters[COUNTER_QUEUE0] = pc.pathCount;
  if (i >= pc.pathCount) return;
  PathState p;
  path_begin(p, wave_pixel(i), wave_sample(i));
  write_path(i, p);
  queues[i] = i;
}
