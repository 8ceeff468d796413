#version 460
// Stage 5: add each finished path's radiance to its pixel's sums.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.pathCount) return;
  AovSample aov;
  if (kAovs) aov = aovSamples[i];
  accumulate_path(read_path(i), aov);
}
