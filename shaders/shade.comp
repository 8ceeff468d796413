#version 460
// Stage 3: emission, next-event estimation, BSDF sampling, Russian roulette.
// Survivors are appended to the other queue (dead paths drop out: compaction);
// shadow rays are appended to the shadow queue.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint count = counters[COUNTER_QUEUE0 + pc.queueIn];
  if (i >= count) return;
  uint path = queues[pc.shadeQueue * pc.capacity + i];  // the extended queue, or its sorted order
  uint queueOut = 1u - pc.queueIn;
  if (!kCompaction) {
    // Every path keeps its slot for the next bounce, dead or alive.
    queues[queueOut * pc.capacity + i] = path;
    if (i == 0u) counters[COUNTER_QUEUE0 + queueOut] = count;
  }
  PathState p = paths[path];
  if (!kCompaction && (p.flags & PATH_DEAD) != 0u) return;
  ShadowRays srs;
  bool alive = path_shade(p, hits[path], srs);
  if (!kCompaction && !alive) p.flags |= PATH_DEAD;
  paths[path] = p;
  if (kCompaction && alive) {
    uint slot = atomicAdd(counters[COUNTER_QUEUE0 + queueOut], 1u);
    queues[queueOut * pc.capacity + slot] = path;
  }
  for (uint j = 0u; j < kLightSamples; ++j) {
    if (srs.ray[j].tmax > 0.0f) {
      srs.ray[j].path = path;
      shadowRays[atomicAdd(counters[COUNTER_SHADOW], 1u)] = srs.ray[j];
    }
  }
}
