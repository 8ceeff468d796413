#version 460
// Stage 3: emission, next-event estimation, BSDF sampling, Russian roulette.
// Survivors are appended to the other queue (dead paths drop out: compaction);
// shadow rays are appended to the shadow queue.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "shared/kernel.glsl"

// A slot in the list counted by counters[counter] for each invocation that
// wants one: one atomic per subgroup, not one per invocation.
uint append_slot(uint counter, bool want) {
  uvec4 ballot = subgroupBallot(want);
  uint base = 0u;
  if (subgroupElect()) base = atomicAdd(counters[counter], subgroupBallotBitCount(ballot));
  return subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(ballot);
}

// Sorted by material class (kSortByMaterial): the sort key whose queue this
// kernel shades, compiled with the material and texture kinds of that key's class;
// SORT_KEYS: every queued path, unsorted.
layout(constant_id = SPEC_SHADE_KEY) const uint kShadeKey = SORT_KEYS;

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint queueOut = 1u - pc.queueIn;
  uint path;
  if (kShadeKey == SORT_KEYS) {
    uint count = counters[COUNTER_QUEUE0 + pc.queueIn];
    if (i >= count) return;
    path = read_queue(pc.queueIn, i);
    if (!kCompaction) {
      // Every path keeps its slot for the next bounce, dead or alive (sorted,
      // the sort kernel copies the queue).
      queues[queueOut * pc.capacity + i] = path;
      if (i == 0u) counters[COUNTER_QUEUE0 + queueOut] = count;
    }
  } else {
    if (i >= sortBins[kShadeKey]) return;
    path = read_queue(QUEUE_SORTED + kShadeKey, i);
  }
  PathState p = read_path(path);
  if (!kCompaction && (p.flags & PATH_DEAD) != 0u) return;
  Hit h = read_hit(path);
  // The AOV layers record the first hit, from the path as the camera ray left.
  // (A camera ray continued past an interface has crossings.)
  if (kAovs && path_depth(p) == 0u && p.crossings == 0u) aovSamples[path] = aov_sample(p, h);
  ShadowRays srs;
  bool alive = path_shade(p, h, srs);
  if (!kCompaction && !alive) p.flags |= PATH_DEAD;
  // Reserve the queue and shadow-ray slots before storing anything: on a CPU
  // an atomic waits for every store before it to land, which stalled it
  // behind the path's 64 bytes (a fifth of this kernel's time on lavapipe).
  uint queueSlot = kCompaction ? append_slot(COUNTER_QUEUE0 + queueOut, alive) : 0u;
  uint shadowSlots[LIGHT_SAMPLE_SLOTS];
  for (uint j = 0u; j < kLightSamples; ++j) shadowSlots[j] = append_slot(COUNTER_SHADOW, srs.ray[j].tmax > 0.0f);
  write_path(path, p);
  if (kCompaction && alive) queues[queueOut * pc.capacity + queueSlot] = path;
  for (uint j = 0u; j < kLightSamples; ++j) {
    if (srs.ray[j].tmax > 0.0f) {
      srs.ray[j].path = path;
      write_shadow_ray(shadowSlots[j], srs.ray[j]);
    }
  }
}
