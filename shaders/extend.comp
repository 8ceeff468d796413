#version 460
// Stage 2: closest hit for every queued path. One ray per invocation, so the
// traversal's bounded step count is the invocation's whole loop budget. When
// sorting by material, also counts each hit's sort key.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= counters[COUNTER_QUEUE0 + pc.queueIn]) return;
  uint path = queues[pc.queueIn * pc.capacity + i];
  Hit h;
  h.prim = WP_INVALID;
  // Without compaction, shade skips dead paths too.
  PathState p = read_path(path);
  if (kCompaction || (p.flags & PATH_DEAD) == 0u) {
    if (trace_ray(p.origin, p.dir, WP_INF, false, h) != TRACE_OK) {
      atomicAdd(counters[COUNTER_TRUNCATED], 1u);
      h.prim = WP_INVALID;
    }
    hits[path] = h;
    if (!kCompaction) count_rays(COUNTER_CLOSEST_RAYS, 1u);  // prepare counts them with compaction
  }
  if (kSortByMaterial) {
    uint key = sort_key(h);
    sortKeys[i] = key;
    atomicAdd(sortBins[key], 1u);
  }
}
