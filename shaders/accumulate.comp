#version 460
// Stage 5: add each finished path's radiance to its pixel's sums: one
// invocation a pixel of the wave, its samples in order (the wave's paths j,
// j + waveSpan, ...), so no two invocations add to one pixel and the sums are
// those of one sample a wave.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint j = gl_GlobalInvocationID.x;
  if (j >= pc.waveSpan) return;
  for (uint i = j; i < pc.pathCount; i += pc.waveSpan) {
    AovSample aov;
    if (kAovs) aov = aovSamples[i];
    accumulate_path(read_path(i), aov);
  }
}
