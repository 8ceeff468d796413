#version 460
// Variant gpu-mega: the whole path in one kernel. One invocation renders one
// sample of one pixel with trace_sample (integrator.glsl), the loop the CPU
// reference runs too; no path state leaves the invocation.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = dispatch_item(pc.pathCount);
  if (i >= pc.pathCount) return;
  SampleRays rays;
  AovSample aov;
  PathState p = trace_sample(wave_pixel(i), wave_sample(i), rays, aov);
  if (rays.truncated > 0u) atomicAdd(counters[COUNTER_TRUNCATED], rays.truncated);
  count_rays(COUNTER_CLOSEST_RAYS, rays.closest);
  count_rays(COUNTER_SHADOW_RAYS, rays.shadow);
  accumulate_path(p, aov);
}
