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
  ShadowRays srs;
  bool alive = path_shade(p, hits[path], srs);
  paths[path] = p;
  if (alive) {
    uint queueOut = 1u - pc.queueIn;
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
