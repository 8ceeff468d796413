#version 460
// Stage 3: emission, next-event estimation, BSDF sampling, Russian roulette.
// Survivors are appended to the other queue (dead paths drop out: compaction);
// shadow rays are appended to the shadow queue.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= counters[COUNTER_QUEUE0 + pc.queueIn]) return;
  uint path = queues[pc.queueIn * pc.capacity + i];
  PathState p = paths[path];
  ShadowRay sr;
  bool alive = path_shade(p, hits[path], sr);
  paths[path] = p;
  if (alive) {
    uint queueOut = 1u - pc.queueIn;
    uint slot = atomicAdd(counters[COUNTER_QUEUE0 + queueOut], 1u);
    queues[queueOut * pc.capacity + slot] = path;
  }
  if (sr.tmax > 0.0f) {
    sr.path = path;
    shadowRays[atomicAdd(counters[COUNTER_SHADOW], 1u)] = sr;
  }
}
