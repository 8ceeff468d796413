#version 460
// Stage 4 with several light samples per vertex (CS184's -l): like
// connect.comp, but a path may own several shadow rays in one dispatch, so
// their contributions are added with float atomics (VK_EXT_shader_atomic_float;
// the renderer uses this kernel only when the device has them).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_EXT_shader_atomic_float : require
#define WP_PATH_RADIANCE_ATOMICS  // paths as PathState (bindings.glsl)
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

void add_to_path(uint path, Spectrum light) {
  uint at = (path * PATH_STATE_TEXELS + PATH_RADIANCE_TEXEL) * 4u;
  atomicAdd(pathFloats[at], light.x);
  atomicAdd(pathFloats[at + 1u], light.y);
  atomicAdd(pathFloats[at + 2u], light.z);
#ifdef WP_SPECTRUM4
  atomicAdd(pathFloats[(path * PATH_STATE_TEXELS + PATH_FOURTH_TEXEL) * 4u + 1u], light.w);
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
