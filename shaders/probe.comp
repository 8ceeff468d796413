#version 460
// The probes of probes.glsl, one query to an invocation: query i rides in
// shadowRays[i], its answer comes back in hit record i.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"
#include "shared/probes.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.pathCount) return;
  write_hit(i, run_probe(read_shadow_ray(pc.waveStart + i)));
}
