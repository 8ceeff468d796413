#version 460
// Stage 2b (variant gpu-sort): appends each extended path to the queue of its
// sort key (the class of the material its ray hit, or the misses), so that
// each key's shade kernel, which holds only its class's kinds, runs over a
// queue of its own. The order within a queue is whatever the atomics give;
// each path's result depends only on its own state, so the image does not
// change.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint count = counters[COUNTER_QUEUE0 + pc.queueIn];
  if (i >= count) return;
  uint path = read_queue(pc.queueIn, i);
  uint key = SORT_KEY_MISS;
  if (kCompaction) {
    key = sort_key(read_hit(path));
  } else {
    // Every path keeps its slot for the next bounce (shade does not append);
    // a finished one has no hit to shade, and its kernel skips it.
    uint queueOut = 1u - pc.queueIn;
    queues[queueOut * pc.capacity + i] = path;
    if (i == 0u) counters[COUNTER_QUEUE0 + queueOut] = count;
    if ((texelFetch(pathTexels, int(path) * PATH_STATE_TEXELS + 2).w & PATH_DEAD) == 0u) key = sort_key(read_hit(path));
  }
  // An atomic per path: taken per subgroup and key instead, the sort was no
  // faster on lavapipe.
  queues[(QUEUE_SORTED + key) * pc.capacity + atomicAdd(sortBins[key], 1u)] = path;
}
