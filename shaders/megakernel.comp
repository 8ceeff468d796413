#version 460
// Variant gpu-mega: the whole path in one kernel. One invocation renders one
// sample of one pixel, from the camera ray through every bounce's closest hit,
// shading and shadow rays to the pixel's sums; no path state leaves the
// invocation. Lavapipe's loop budget (65,535 iterations per invocation, shared
// by all loops) then covers every traversal of the path: the host lowers the
// traversal step cap (scene.counts.z) so that all of them fit.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = dispatch_item(pc.pathCount);
  if (i >= pc.pathCount) return;
  PathState p;
  path_begin(p, wave_pixel(i), pc.sampleIndex);
  uint closestCount = 0u, shadowCount = 0u;  // rays this path traced
  // path_shade ends every path at max bounces: at most max + 1 passes.
  for (uint pass = 0u; pass <= scene.image.z; ++pass) {
    Hit h;
    ++closestCount;
    if (trace_ray(p.origin, p.dir, WP_INF, false, h) != TRACE_OK) {
      atomicAdd(counters[COUNTER_TRUNCATED], 1u);
      break;
    }
    ShadowRays srs;
    bool alive = path_shade(p, h, srs);
    for (uint j = 0u; j < kLightSamples; ++j) {
      ShadowRay sr = srs.ray[j];
      if (sr.tmax <= 0.0f) continue;
      Hit blocker;
      ++shadowCount;
      if (trace_ray(sr.origin, sr.dir, sr.tmax, true, blocker) != TRACE_OK) {
        atomicAdd(counters[COUNTER_TRUNCATED], 1u);
      } else if (blocker.prim == WP_INVALID) {
        p.radiance += sr.contribution;
      }
    }
    if (!alive) break;
  }
  count_rays(COUNTER_CLOSEST_RAYS, closestCount);
  count_rays(COUNTER_SHADOW_RAYS, shadowCount);
  accumulate_path(p);
}
