// trace_items.glsl — the loop of the tracing kernels (extend, connect,
// connect_multi, raycast): one dispatch traces a list of items, each one ray.
//
// On lavapipe an invocation is a lane of an 8-wide SIMD loop, and a loop runs
// until its slowest lane is done: with one ray per invocation, incoherent
// bounce rays kept fewer than half of the lanes busy. So with the wide BVH
// each invocation takes up to kRaysPerInvocation items (item = invocation +
// k * stride, stride = items / kRaysPerInvocation) and walks them in one loop:
// a lane whose ray is done starts its next ray in the next iteration. The
// host asks for one ray per invocation on GPUs, and where it knows the rays
// are coherent (the ray-casting benchmark's camera rays: their lanes finish
// together anyway).
//
// lavapipe's loop budget (65,535 iterations per invocation, all loops
// together) is shared: each ray gets scene.counts.z / kRaysPerInvocation
// steps, and one that needs more is counted as truncated. The host then runs
// the same work again one ray per invocation, each ray with the whole cap
// (wavefront.cpp), so only a ray that needs more than that fails a render.
//
// The including kernel defines, before including this file:
//   TRACE_ANY_HIT    true for shadow rays (the first hit ends the walk)
//   uint trace_item_count()   the items of this dispatch
//   void trace_item_ray(uint item, out vec3 o, out vec3 d, out float tmax, out uint tag)
//     the item's ray, and a word the kernel wants back with the result
//   void trace_item_done(uint item, uint tag, Hit hit, bool truncated)
//     its result: hit.prim is WP_INVALID for a miss, and for a truncated walk
// and calls trace_items() from main().

// Hands an item's result to the kernel; a truncated walk is counted and
// reported as a miss.
void finish_item(uint item, uint tag, Hit hit, bool truncated) {
  if (truncated) {
    atomicAdd(counters[COUNTER_TRUNCATED], 1u);
    hit.prim = WP_INVALID;
  }
  trace_item_done(item, tag, hit, truncated);
}

// One item, one walk with the whole step cap (where kRaysPerInvocation is 1).
void trace_one_item(uint item) {
  vec3 o;
  vec3 d;
  float tmax;
  uint tag;
  trace_item_ray(item, o, d, tmax, tag);
  Hit hit;
  hit.t = tmax;
  hit.prim = WP_INVALID;
  hit.u = 0.0f;
  hit.v = 0.0f;
  bool truncated = tmax > 0.0f && trace_ray(o, d, tmax, TRACE_ANY_HIT, hit) != TRACE_OK;
  finish_item(item, tag, hit, truncated);
}

void trace_items() {
  uint count = trace_item_count();
  if (kRaysPerInvocation == 1u || BVH_LAYOUT_OF_SCENE != BVH_LAYOUT_WIDE) {
    uint item = dispatch_item(count);
    if (item < count) trace_one_item(item);
    return;
  }
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  // Invocation i takes items i, i + stride, ...: at most kRaysPerInvocation.
  // (The dispatch may have a few invocations more; they take none.)
  uint stride = (count + kRaysPerInvocation - 1u) / kRaysPerInvocation;
  if (id >= stride) return;
  uint item = id;
  uint cap = scene.counts.z / kRaysPerInvocation;
  const bool anyHit = TRACE_ANY_HIT;
  vec3 o;
  vec3 d;
  float tmax;
  uint tag;
  Hit hit;
#include "wide_walk_state.glsl"
  bool start = true;
  uint steps = 0u;
  while (true) {
    if (start) {
      trace_item_ray(item, o, d, tmax, tag);
#include "wide_walk_begin.glsl"
      steps = 0u;
      start = false;
    }
    steps += 1u;
    bool truncated = steps > cap;
    bool walkDone = false;
    if (!truncated) {
#include "wide_walk_step.glsl"
    }
    if (walkDone || truncated) {
      finish_item(item, tag, hit, truncated);
      item += stride;
      if (item >= count) break;
      start = true;
    }
  }
}
