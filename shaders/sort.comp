#version 460
// Stage 2b (variant gpu-sort): scatters the queue into QUEUE_SORTED by the
// material each path's ray hit, so that shade's subgroups run one material's
// code. A counting sort: extend counted the keys, prepare (PREPARE_SORT) made
// the counts into start offsets, and each path here takes the next slot of
// its key. The order within a key is whatever the atomics give; each path's
// result depends only on its own state, so the image does not change.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= counters[COUNTER_QUEUE0 + pc.queueIn]) return;
  uint slot = atomicAdd(sortBins[sortKeys[i]], 1u);
  queues[QUEUE_SORTED * pc.capacity + slot] = read_queue(pc.queueIn, i);
}
