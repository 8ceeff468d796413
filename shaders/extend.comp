#version 460
// Stage 2: closest hit for every queued path (trace_items.glsl: several rays
// per invocation on CPU devices, each within its share of the loop budget).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "shared/kernel.glsl"

#define TRACE_ANY_HIT false

uint trace_item_count() {
  return counters[COUNTER_QUEUE0 + pc.queueIn];
}

// Without compaction a finished path keeps its queue slot; its ray is empty
// (tmax 0: nothing to find) and it writes no hit.
bool path_is_dead(uint path) {
  return !kCompaction && (texelFetch(pathTexels, int(path) * PATH_STATE_TEXELS + 2).w & PATH_DEAD) != 0u;
}

void trace_item_ray(uint item, out vec3 o, out vec3 d, out float tmax, out uint path) {
  path = read_queue(pc.queueIn, item);
  PathState p = read_path(path);
  o = p.origin;
  d = p.dir;
  tmax = kCompaction || (p.flags & PATH_DEAD) == 0u ? WP_INF : 0.0f;
}

void trace_item_done(uint item, uint path, Hit h, bool truncated) {
  if (!path_is_dead(path)) {
    write_hit(path, h);
    if (!kCompaction) count_rays(COUNTER_CLOSEST_RAYS, 1u);  // prepare counts them with compaction
  }
}

#include "shared/trace_items.glsl"

void main() {
  trace_items();
}
