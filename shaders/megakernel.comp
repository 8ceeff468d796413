#version 460
// Variant gpu-mega: the whole path in one kernel. One invocation renders one
// sample of one pixel with trace_sample (integrator.glsl), the loop the CPU
// reference runs too; no path state leaves the invocation.
//
// With kMegakernelSamples > 1 (gpu-mega-bvh2-regen), a wave holds that many
// samples of each of its pixels, and one invocation renders all of a
// pixel's, one after another, in one loop of passes: a lane whose path ends
// accumulates it and begins the next in the same pass (path regeneration),
// instead of idling masked until the longest path of its warp ends. Each
// path is the one trace_sample renders, so the image is the same.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

layout(constant_id = SPEC_MEGAKERNEL_SAMPLES) const uint kMegakernelSamples = 1u;

void count_sample_rays(SampleRays rays) {
  if (rays.truncated > 0u) atomicAdd(counters[COUNTER_TRUNCATED], rays.truncated);
  count_rays(COUNTER_CLOSEST_RAYS, rays.closest);
  count_rays(COUNTER_SHADOW_RAYS, rays.shadow);
}

void main() {
  SampleRays rays;
  AovSample aov;
  if (kMegakernelSamples == 1u) {
    uint i = dispatch_item(pc.pathCount);
    if (i >= pc.pathCount) return;
    PathState p = trace_sample(wave_pixel(i), wave_sample(i), rays, aov);
    count_sample_rays(rays);
    accumulate_path(p, aov);
    return;
  }
  // Path i + k waveSpan is sample k of pixel i (wave_pixel, wave_sample).
  uint item = dispatch_item(pc.waveSpan);
  if (item >= pc.waveSpan) return;
  rays.closest = 0u;
  rays.shadow = 0u;
  rays.truncated = 0u;
  PathState p;
  sample_begin(wave_pixel(item), wave_sample(item), p, aov);
  uint passes = path_passes_max();
  uint pass = 0u;
  while (true) {
    bool alive = trace_pass(p, pass, rays, aov);
    pass += 1u;
    if (alive && pass < passes) continue;
    accumulate_path(p, aov);
    item += pc.waveSpan;
    if (item >= pc.pathCount) break;
    sample_begin(wave_pixel(item), wave_sample(item), p, aov);
    pass = 0u;
  }
  count_sample_rays(rays);
}
