#version 460
// Texture lookups without rendering, for the test that compares the GLSL and
// C++ texture code: query i rides in shadowRays[i] (origin: the hit point;
// dir.xy: the UV; path: the texture index) and its colour comes back in
// hit record i (t, u, v = r, g, b).
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.pathCount) return;
  ShadowRay q = read_shadow_ray(pc.waveStart + i);
  vec3 c = texture_eval(q.path, vec2(q.dir.x, q.dir.y), q.origin);
  Hit h;
  h.t = c.x;
  h.prim = 0u;
  h.u = c.y;
  h.v = c.z;
  write_hit(i, h);
}
