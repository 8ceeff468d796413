#version 460
// Stage 4: shadow rays. An unoccluded segment adds its NEE contribution to its
// path (each path has at most one shadow ray per bounce: no atomics needed;
// connect_multi.comp handles several light samples per vertex). The rays go
// through trace_items.glsl.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "shared/kernel.glsl"

#define TRACE_ANY_HIT true

uint trace_item_count() {
  return counters[COUNTER_SHADOW];
}

void trace_item_ray(uint item, out vec3 o, out vec3 d, out float tmax, out uint path) {
  ShadowRay sr = read_shadow_ray(item);
  o = sr.origin;
  d = sr.dir;
  tmax = sr.tmax;
  path = sr.path;
}

// Adds light to a path's radiance through its view: shade wrote it in an
// earlier dispatch, and no other shadow ray of this one is the path's.
void add_to_path(uint path, Spectrum light) {
  uint at = path * PATH_STATE_TEXELS + PATH_RADIANCE_TEXEL;
  vec3 radiance = texel_xyz(texelFetch(pathTexels, int(at))) + spectrum_xyz(light);
  pathTexelsOut[at].xyz = floatBitsToUint(radiance);
#ifdef WP_SPECTRUM4
  uint fourth = path * PATH_STATE_TEXELS + PATH_FOURTH_TEXEL;
  pathTexelsOut[fourth].y = floatBitsToUint(uintBitsToFloat(texelFetch(pathTexels, int(fourth)).y) + light.w);
#endif
}

void trace_item_done(uint item, uint path, Hit h, bool truncated) {
  if (truncated || h.prim != WP_INVALID) return;
  add_to_path(path, shadow_ray_contribution(item));
}

#include "shared/trace_items.glsl"
#include "shared/connect_media.glsl"

void main() {
  if (FEATURE_COMPILED(FEATURE_MEDIA)) connect_through_media();
  else trace_items();
}
