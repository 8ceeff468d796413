#version 460
// Sizes the next indirect dispatch from a queue counter, and resets the queues
// the next stage appends to; when sorting by material class, also resets the
// sort keys' queues, and later sizes each key's shade dispatch. Runs as a
// single invocation.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

uint groups_for(uint n) {
  // Every kernel of a renderer shares the specialized workgroup size.
  return (n + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x;
}

void set_dispatch(uint slot, uint groups) {
  indirect[slot * 3u] = groups;
  indirect[slot * 3u + 1u] = 1u;
  indirect[slot * 3u + 2u] = 1u;
}

// Workgroups for a tracing kernel's n rays (trace_items.glsl).
uint tracing_groups(uint n) {
  return groups_for(TRACING_INVOCATIONS(n, kRaysPerInvocation, kTracingFill));
}

void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  if (pc.phase == PREPARE_EXTEND) {
    uint queued = counters[COUNTER_QUEUE0 + pc.queueIn];
    set_dispatch(INDIRECT_EXTEND, tracing_groups(queued));
    set_dispatch(INDIRECT_SHADE, groups_for(queued));
    // With compaction every queued path casts its ray; without, extend counts
    // the ones it traces (finished paths keep their slots).
    if (kCompaction) count_rays(COUNTER_CLOSEST_RAYS, queued);
    counters[COUNTER_QUEUE0 + (1u - pc.queueIn)] = 0u;
    counters[COUNTER_SHADOW] = 0u;
    counters[COUNTER_TRACE_BLOCKS] = 0u;
    if (kSortByMaterial) {
      for (uint k = 0u; k < SORT_KEYS; ++k) sortBins[k] = 0u;
    }
  } else if (pc.phase == PREPARE_SORT) {
    // Each key's shade kernel: a workgroup per workgroup's worth of its paths.
    for (uint k = 0u; k < SORT_KEYS; ++k) set_dispatch(INDIRECT_SHADE_KEY0 + k, groups_for(sortBins[k]));
  } else {
    // Through media each shadow ray is tracked by an invocation of its own
    // (connect_through_media), whatever the tracing kernels take a lane.
    uint shadowRays = counters[COUNTER_SHADOW];
    set_dispatch(INDIRECT_CONNECT, FEATURE_COMPILED(FEATURE_MEDIA) ? groups_for(shadowRays) : tracing_groups(shadowRays));
    counters[COUNTER_TRACE_BLOCKS] = 0u;
    count_rays(COUNTER_SHADOW_RAYS, shadowRays);
  }
}
