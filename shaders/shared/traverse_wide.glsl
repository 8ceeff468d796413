// traverse_wide.glsl — the walk of the 8-wide compressed BVH (WideNode): the
// slab tests of a node's quantized child boxes, the register stack, and
// trace_wide. The walk's own steps are in wide_walk_*.glsl, shared with the
// kernels that walk several rays in one loop (trace_items.glsl). The loop
// budget rules of traverse_binary.glsl hold here too.
#ifndef WP_TRAVERSE_WIDE_GLSL
#define WP_TRAVERSE_WIDE_GLSL

// Hit-mask bits of interior children (bits 0-23 are primitives).
#define WIDE_NODE_BITS 0xff000000u
// The entry that takes the walk back out of an instance (wide_walk_enter.glsl)
// in x: this bit, which no node index and no primitive index reaches (records
// are fewer than EMITTER_UNSEEN_BIT, 2^28: compile_geometry), the count of
// primitive groups set aside beneath it (bits 28-29) and the first primitive
// of the top level's primitive group it keeps; that group's bits in y.
#define WIDE_RETURN_X 0x80000000u
#define WIDE_RETURN_SET_ASIDE_SHIFT 28u
#define WIDE_RETURN_PRIM_MASK 0x0fffffffu

// max / min for operands that are never NaN: a plain compare and select,
// where GLSL's max / min compile to NaN-aware sequences on lavapipe.
float max_of(float a, float b) {
  return a > b ? a : b;
}

float min_of(float a, float b) {
  return a < b ? a : b;
}

// Byte `slot` of the eight packed in a pair of words (slots 0-3, then 4-7).
uint slot_byte(uvec2 words, uint slot) {
  return ((slot < 4u ? words.x : words.y) >> ((slot & 3u) * 8u)) & 0xffu;
}

// The hit-mask bits of child `slot` of a wide node if the ray meets its box
// before tmax, else 0; tnear: where it enters the box. Per axis the ray's distance to a quantized plane q is
// q * scale + base; nearX / farX are the plane words facing the ray and facing
// away (lower and upper planes swapped for negative directions). `meta` has
// the interior slots already permuted for the ray's octant.
uint wide_child_bits(uint slot, uvec2 meta, uvec2 nearX, uvec2 farX, uvec2 nearY, uvec2 farY, uvec2 nearZ, uvec2 farZ,
                     vec3 scale, vec3 base, float tmax, OUT(float) tnear) {
  float tnx = fma(float(slot_byte(nearX, slot)), scale.x, base.x);
  float tny = fma(float(slot_byte(nearY, slot)), scale.y, base.y);
  float tnz = fma(float(slot_byte(nearZ, slot)), scale.z, base.z);
  float tfx = fma(float(slot_byte(farX, slot)), scale.x, base.x);
  float tfy = fma(float(slot_byte(farY, slot)), scale.y, base.y);
  float tfz = fma(float(slot_byte(farZ, slot)), scale.z, base.z);
  tnear = max_of(max_of(tnx, tny), max_of(tnz, 0.0f));
  // Widened by a few ulps against rounding in the slab distances.
  float tfar = min_of(min_of(tfx, tfy), min_of(tfz, tmax)) * 1.0000004f;
  uint m = slot_byte(meta, slot);
  return tnear <= tfar ? (m >> 5u) << (m & 31u) : 0u;
}

// WIDE_ORDER_DISTANCE: a slot's sort key, the bits of its entry distance
// (non-negative floats order as their bits) with its rank among the node's
// interior children in the lowest three, or ~0 (sorted last) unless it is an
// interior child the ray meets. `slotBits`: what wide_child_bits gave it.
uint wide_child_key(uint slotBits, float tnear, uint rank) {
  return (slotBits & WIDE_NODE_BITS) != 0u ? ((floatBitsToUint(tnear) & ~7u) | rank) : 0xffffffffu;
}

// Whether the walk sorts a node's hit children nearest first: in that order
// (WIDE_ORDER_DISTANCE), for closest hits only. An any-hit walk stops at the
// first hit wherever it lies, so the sort would only cost it (the forest's
// shadow rays: 20 % on the SIMT model). Reads the walk's anyHit.
#define WP_NEAREST_FIRST (WIDE_CHILD_ORDER_OF_SCENE == WIDE_ORDER_DISTANCE && !anyHit)

// One comparator of a sorting network: a gets the smaller key, b the larger.
#define WP_SORT_PAIR(a, b) \
  {                        \
    uint low_ = min(a, b); \
    b = max(a, b);         \
    a = low_;              \
  }

// WIDE_ORDER_DISTANCE: the node group's y for a node whose children have the
// keys k0..k7, `count` of them hit interior children: the count in bits
// 24-27, and their ranks nearest first, 3 bits each from bit 0.
uint wide_nearest_first(uint count, uint k0, uint k1, uint k2, uint k3, uint k4, uint k5, uint k6, uint k7) {
  // Batcher's odd-even merge sort of eight: 19 comparators.
  WP_SORT_PAIR(k0, k2); WP_SORT_PAIR(k1, k3); WP_SORT_PAIR(k4, k6); WP_SORT_PAIR(k5, k7);
  WP_SORT_PAIR(k0, k4); WP_SORT_PAIR(k1, k5); WP_SORT_PAIR(k2, k6); WP_SORT_PAIR(k3, k7);
  WP_SORT_PAIR(k0, k1); WP_SORT_PAIR(k2, k3); WP_SORT_PAIR(k4, k5); WP_SORT_PAIR(k6, k7);
  WP_SORT_PAIR(k2, k4); WP_SORT_PAIR(k3, k5);
  WP_SORT_PAIR(k1, k4); WP_SORT_PAIR(k3, k6);
  WP_SORT_PAIR(k1, k2); WP_SORT_PAIR(k3, k4); WP_SORT_PAIR(k5, k6);
  return (count << 24u) | (k0 & 7u) | ((k1 & 7u) << 3u) | ((k2 & 7u) << 6u) | ((k3 & 7u) << 9u) | ((k4 & 7u) << 12u) |
         ((k5 & 7u) << 15u) | ((k6 & 7u) << 18u) | ((k7 & 7u) << 21u);
}

// The interior slots' bytes of a meta word (4 slots, `imask4` their interior
// bits) XORed with the ray's slot permutation: imask spread to 0xff per
// interior byte by a multiply, so all four bytes change in a few operations.
uint permute_meta(uint meta, uint imask4, uint xorSlot) {
  uint interiorBytes = ((imask4 * 0x00204081u) & 0x01010101u) * 0xffu;
  return meta ^ (interiorBytes & (xorSlot * 0x01010101u));
}

// The wide walk's stack. lavapipe keeps an indexed private array in memory
// and reaches it lane by lane: each push was a loop of masked scalar stores
// and each pop a loop of loads, together about a third of the walk's time. So
// the stack is an array indexed by constants only, which the compiler holds
// in registers: entry 0 is the top, and a push or a pop moves every entry one
// place through selects. That costs in proportion to the entries kept, so the
// walk bounds them: one node group per level below the root, and at most
// WIDE_STACK_PRIM_GROUPS primitive groups (types.glsl; a node that would set
// aside one more waits until the current primitive group is done). The host
// sizes the stack by the tree (TRAVERSAL_STACK_SLOTS, a specialization
// constant: the compiler drops the code of unused entries); a tree needing more
// than WIDE_REGISTER_STACK entries keeps the stack in an indexed array.
#define WIDE_REGISTER_STACK 32u
#define WP_MOVE(r, c, to, from) \
  if ((to) < TRAVERSAL_STACK_SLOTS) {           \
    r[to] = (c) ? r[from] : r[to];              \
  }
#define WP_CLEAR_REGISTER_STACK(r) \
  r[0u] = uvec2(0u, 0u); r[1u] = uvec2(0u, 0u); r[2u] = uvec2(0u, 0u); r[3u] = uvec2(0u, 0u); \
  r[4u] = uvec2(0u, 0u); r[5u] = uvec2(0u, 0u); r[6u] = uvec2(0u, 0u); r[7u] = uvec2(0u, 0u); \
  r[8u] = uvec2(0u, 0u); r[9u] = uvec2(0u, 0u); r[10u] = uvec2(0u, 0u); r[11u] = uvec2(0u, 0u); \
  r[12u] = uvec2(0u, 0u); r[13u] = uvec2(0u, 0u); r[14u] = uvec2(0u, 0u); r[15u] = uvec2(0u, 0u); \
  r[16u] = uvec2(0u, 0u); r[17u] = uvec2(0u, 0u); r[18u] = uvec2(0u, 0u); r[19u] = uvec2(0u, 0u); \
  r[20u] = uvec2(0u, 0u); r[21u] = uvec2(0u, 0u); r[22u] = uvec2(0u, 0u); r[23u] = uvec2(0u, 0u); \
  r[24u] = uvec2(0u, 0u); r[25u] = uvec2(0u, 0u); r[26u] = uvec2(0u, 0u); r[27u] = uvec2(0u, 0u); \
  r[28u] = uvec2(0u, 0u); r[29u] = uvec2(0u, 0u); r[30u] = uvec2(0u, 0u); r[31u] = uvec2(0u, 0u);
// Every entry one place down where c (a push makes room for the new top).
#define WP_REGISTER_STACK_DOWN(r, c) \
  WP_MOVE(r, c, 31u, 30u); WP_MOVE(r, c, 30u, 29u); WP_MOVE(r, c, 29u, 28u); WP_MOVE(r, c, 28u, 27u); WP_MOVE(r, c, 27u, 26u); WP_MOVE(r, c, 26u, 25u); WP_MOVE(r, c, 25u, 24u); WP_MOVE(r, c, 24u, 23u); \
  WP_MOVE(r, c, 23u, 22u); WP_MOVE(r, c, 22u, 21u); WP_MOVE(r, c, 21u, 20u); WP_MOVE(r, c, 20u, 19u); WP_MOVE(r, c, 19u, 18u); WP_MOVE(r, c, 18u, 17u); WP_MOVE(r, c, 17u, 16u); WP_MOVE(r, c, 16u, 15u); \
  WP_MOVE(r, c, 15u, 14u); WP_MOVE(r, c, 14u, 13u); WP_MOVE(r, c, 13u, 12u); WP_MOVE(r, c, 12u, 11u); WP_MOVE(r, c, 11u, 10u); WP_MOVE(r, c, 10u, 9u); WP_MOVE(r, c, 9u, 8u); WP_MOVE(r, c, 8u, 7u); \
  WP_MOVE(r, c, 7u, 6u); WP_MOVE(r, c, 6u, 5u); WP_MOVE(r, c, 5u, 4u); WP_MOVE(r, c, 4u, 3u); WP_MOVE(r, c, 3u, 2u); WP_MOVE(r, c, 2u, 1u); WP_MOVE(r, c, 1u, 0u);
// Every entry one place up where c (a pop drops the top).
#define WP_REGISTER_STACK_UP(r, c) \
  WP_MOVE(r, c, 0u, 1u); WP_MOVE(r, c, 1u, 2u); WP_MOVE(r, c, 2u, 3u); WP_MOVE(r, c, 3u, 4u); WP_MOVE(r, c, 4u, 5u); WP_MOVE(r, c, 5u, 6u); WP_MOVE(r, c, 6u, 7u); WP_MOVE(r, c, 7u, 8u); \
  WP_MOVE(r, c, 8u, 9u); WP_MOVE(r, c, 9u, 10u); WP_MOVE(r, c, 10u, 11u); WP_MOVE(r, c, 11u, 12u); WP_MOVE(r, c, 12u, 13u); WP_MOVE(r, c, 13u, 14u); WP_MOVE(r, c, 14u, 15u); WP_MOVE(r, c, 15u, 16u); \
  WP_MOVE(r, c, 16u, 17u); WP_MOVE(r, c, 17u, 18u); WP_MOVE(r, c, 18u, 19u); WP_MOVE(r, c, 19u, 20u); WP_MOVE(r, c, 20u, 21u); WP_MOVE(r, c, 21u, 22u); WP_MOVE(r, c, 22u, 23u); WP_MOVE(r, c, 23u, 24u); \
  WP_MOVE(r, c, 24u, 25u); WP_MOVE(r, c, 25u, 26u); WP_MOVE(r, c, 26u, 27u); WP_MOVE(r, c, 27u, 28u); WP_MOVE(r, c, 28u, 29u); WP_MOVE(r, c, 29u, 30u); WP_MOVE(r, c, 30u, 31u);

// Sets the walk's per-ray constants (wide_walk_state.glsl) for the ray rd, at
// the start and wherever the walk enters or leaves an instance's space.
// A zero direction component becomes a tiny one, so that no slab distance is
// 0 * inf: the result differs only for rays exactly in a box's face. Slot
// order for the ray: the builder put the child lying towards octant s in
// slot s (bit a set: towards -a), and the walk takes the highest bit first.
// A ray travelling towards -a meets the children on the +a side first, whose
// bit a is clear: so xorSlot sets bit a for it, and bit 24 + (s ^ xorSlot)
// puts the child facing the ray's origin first. (The other way round, the
// walk went back to front: Bvh.WalksMeetNearChildrenFirst.)
#define WP_WIDE_WALK_AIM()                                                                                        \
  sh = make_ray_shear(rd);                                                                                         \
  invDir = vec3(1.0f) / vec3(abs(rd.x) < 1e-20f ? 1e-20f : rd.x, abs(rd.y) < 1e-20f ? 1e-20f : rd.y,              \
                             abs(rd.z) < 1e-20f ? 1e-20f : rd.z);                                                  \
  negX = invDir.x < 0.0f;                                                                                          \
  negY = invDir.y < 0.0f;                                                                                          \
  negZ = invDir.z < 0.0f;                                                                                          \
  xorSlot = (negX ? 1u : 0u) | (negY ? 2u : 0u) | (negZ ? 4u : 0u);

// Pushes entry e on the wide walk's stack (either kind, see below).
#define WP_WIDE_PUSH(e)                \
  WP_NOTE_STACK_WRITE(sp);             \
  if (inRegisters) {                   \
    WP_REGISTER_STACK_DOWN(regs, true); \
    regs[0u] = (e);                    \
  } else {                             \
    stack[sp] = (e);                   \
  }                                    \
  sp += 1u;

// The 8-wide compressed BVH (WideNode), after Ylitie et al. 2017. The walk
// keeps a node group (the hit interior children of a node still to visit) and
// a primitive group (the hit primitives still to test); each iteration tests
// one primitive and visits one node, since lavapipe runs both paths of a loop
// body anyway. Groups set aside go on the stack (see above).
// The walk's state and steps are in wide_walk_*.glsl, shared with the kernels
// that walk several rays in one loop (trace_items.glsl).
uint trace_wide(vec3 o, vec3 d, float tmax, bool anyHit, OUT(Hit) hit) {
#include "wide_walk_state.glsl"
#include "wide_walk_begin.glsl"
  uint steps = 0u;
  uint cap = scene.counts.z;
  bool walkDone = false;
  while (!walkDone) {
    steps += 1u;
    if (steps > cap) return TRACE_TRUNCATED;
    WP_NOTE_STEP();
#include "wide_walk_step.glsl"
  }
  return TRACE_OK;
}

// Closest hit (or, with anyHit, any hit) of the ray o + t d, t in (0, tmax),
// through the scene's BVH layout. Returns TRACE_OK or TRACE_TRUNCATED.
uint trace_ray(vec3 o, vec3 d, float tmax, bool anyHit, OUT(Hit) hit) {
  if (BVH_LAYOUT_OF_SCENE == BVH_LAYOUT_WIDE) return trace_wide(o, d, tmax, anyHit, hit);
  return trace_binary(o, d, tmax, anyHit, hit);
}

#endif  // WP_TRAVERSE_WIDE_GLSL
