// scene.glsl — queries against the uploaded scene: BVH traversal, surface
// interactions and emitter sampling. Reads the buffers `scene`, `nodes`,
// `triangles`, `spheres`, `materials` and `emitters`: in GLSL they are the
// descriptor bindings of bindings.glsl; in C++ this file is included inside
// struct wp::shader::SceneView, whose members carry the same names.
#ifndef WP_SCENE_GLSL
#define WP_SCENE_GLSL

#define TRACE_OK 0u
#define TRACE_TRUNCATED 1u

struct SurfaceHit {
  vec3 p;  // position, reprojected onto the surface
  uint material;
  vec3 ng;  // unit geometric normal; its side is the emitting (front) side
  uint emitter;
  vec3 ns;  // unit shading normal (interpolated vertex normals), on ng's side
  float pad;
  vec2 uv;  // texture coordinates
};

// A point chosen on an emitter by next-event estimation, seen from a shading point.
struct LightSample {
  vec3 wi;     // unit direction from the shading point towards the light
  float dist;  // distance to the light point (the shadow ray stops short of it)
  vec3 radiance;  // emitted radiance towards the shading point (point lights: I / d^2)
  float pdf;      // solid-angle density of wi, pick probability included (point lights: the pick probability)
  vec3 p;         // the light point
  uint isDelta;   // 1 for point lights: no BSDF sample can hit them, so no MIS
  vec3 n;         // surface normal at p (zero for point lights)
};

// ---- records in texel buffers -------------------------------------------------
// Decoded from RGBA32UI texels (bindings.glsl), field by field as the structs
// in types.glsl lay them out; on the host the same code reads the uploaded
// arrays through texelFetch on plain pointers. Unused fields cost nothing: a
// texel fetch whose result is not used is removed by the compiler.

vec3 texel_xyz(uvec4 t) {
  return vec3(uintBitsToFloat(t.x), uintBitsToFloat(t.y), uintBitsToFloat(t.z));
}

BvhNode load_node(uint i) {
  int at = int(i) * BVH_NODE_TEXELS;
  uvec4 a = texelFetch(nodeTexels, at);
  uvec4 b = texelFetch(nodeTexels, at + 1);
  BvhNode n;
  n.bmin = texel_xyz(a);
  n.leftFirst = a.w;
  n.bmax = texel_xyz(b);
  n.count = b.w;
  return n;
}

WideNode load_wide_node(uint i) {
  int at = int(i) * WIDE_NODE_TEXELS;
  uvec4 a = texelFetch(wideNodeTexels, at);
  uvec4 b = texelFetch(wideNodeTexels, at + 1);
  WideNode n;
  n.origin = texel_xyz(a);
  n.exyzImask = a.w;
  n.childBase = b.x;
  n.primBase = b.y;
  n.meta0123 = b.z;
  n.meta4567 = b.w;
  n.qlo = texelFetch(wideNodeTexels, at + 2);
  n.qloZqhiX = texelFetch(wideNodeTexels, at + 3);
  n.qhi = texelFetch(wideNodeTexels, at + 4);
  return n;
}

Triangle load_triangle(uint i) {
  int at = int(i) * TRIANGLE_TEXELS;
  uvec4 a = texelFetch(triangleTexels, at);
  uvec4 b = texelFetch(triangleTexels, at + 1);
  uvec4 c = texelFetch(triangleTexels, at + 2);
  Triangle t;
  t.v0 = texel_xyz(a);
  t.material = a.w;
  t.v1 = texel_xyz(b);
  t.emitter = b.w;
  t.v2 = texel_xyz(c);
  t.shading = c.w;
  return t;
}

TriangleShading load_shading(uint i) {
  int at = int(i) * TRIANGLE_SHADING_TEXELS;
  uvec4 a = texelFetch(shadingTexels, at);
  uvec4 b = texelFetch(shadingTexels, at + 1);
  uvec4 c = texelFetch(shadingTexels, at + 2);
  uvec4 d = texelFetch(shadingTexels, at + 3);
  TriangleShading sh;
  sh.n0 = texel_xyz(a);
  sh.u0 = uintBitsToFloat(a.w);
  sh.n1 = texel_xyz(b);
  sh.v0 = uintBitsToFloat(b.w);
  sh.n2 = texel_xyz(c);
  sh.hasNormals = c.w;
  sh.uv12 = vec4(uintBitsToFloat(d.x), uintBitsToFloat(d.y), uintBitsToFloat(d.z), uintBitsToFloat(d.w));
  return sh;
}

vec4 texel_vec4(uvec4 t) {
  return vec4(uintBitsToFloat(t.x), uintBitsToFloat(t.y), uintBitsToFloat(t.z), uintBitsToFloat(t.w));
}

Sphere load_sphere(uint i) {
  int at = int(i) * SPHERE_TEXELS;
  Sphere sp;
  sp.toWorld0 = texel_vec4(texelFetch(sphereTexels, at));
  sp.toWorld1 = texel_vec4(texelFetch(sphereTexels, at + 1));
  sp.toWorld2 = texel_vec4(texelFetch(sphereTexels, at + 2));
  sp.toObject0 = texel_vec4(texelFetch(sphereTexels, at + 3));
  sp.toObject1 = texel_vec4(texelFetch(sphereTexels, at + 4));
  sp.toObject2 = texel_vec4(texelFetch(sphereTexels, at + 5));
  uvec4 g = texelFetch(sphereTexels, at + 6);
  sp.material = g.x;
  sp.emitter = g.y;
  sp.area = uintBitsToFloat(g.z);
  sp.pad = g.w;
  return sp;
}

Material load_material(uint i) {
  int at = int(i) * MATERIAL_TEXELS;
  Material m;
  m.info = texelFetch(materialTexels, at);
  m.children = texelFetch(materialTexels, at + 1);
  m.params = texel_vec4(texelFetch(materialTexels, at + 2));
  return m;
}

Texture load_texture(uint i) {
  int at = int(i) * TEXTURE_TEXELS;
  Texture t;
  t.info = texelFetch(textureTexels, at);
  t.color0 = texel_vec4(texelFetch(textureTexels, at + 1));
  t.color1 = texel_vec4(texelFetch(textureTexels, at + 2));
  t.map0 = texel_vec4(texelFetch(textureTexels, at + 3));
  t.map1 = texel_vec4(texelFetch(textureTexels, at + 4));
  t.map2 = texel_vec4(texelFetch(textureTexels, at + 5));
  return t;
}

PointLight load_point_light(uint i) {
  int at = int(i) * POINT_LIGHT_TEXELS;
  PointLight l;
  l.position = texel_vec4(texelFetch(pointLightTexels, at));
  l.intensity = texel_vec4(texelFetch(pointLightTexels, at + 1));
  return l;
}

Emitter load_emitter(uint i) {
  uvec4 t = texelFetch(emitterTexels, int(i) * EMITTER_TEXELS);
  Emitter e;
  e.prim = t.x;
  e.alias = t.y;
  e.threshold = uintBitsToFloat(t.z);
  e.pmf = uintBitsToFloat(t.w);
  return e;
}

// Entry i of the environment map's sampling distribution.
float cdf_at(uint i) {
  return texelFetch(environmentCdf, int(i)).x;
}

// ---- traversal ----------------------------------------------------------------
//
// Loop budget: lavapipe silently ends all loops of a shader invocation after
// 65,535 iterations in total, and counts the iterations of nested loops in ways
// a counter cannot follow. So each walk is one flat loop whose every iteration
// does a bounded amount of work and counts itself against scene.counts.z
// (below the budget). A walk that reaches the cap returns TRACE_TRUNCATED,
// which the host turns into an error.

// Tests primitive record i (a triangle, or a sphere's placeholder), loaded as
// tri, and keeps the nearer hit.
void intersect_loaded_prim(uint i, Triangle tri, vec3 o, vec3 d, RayShear sh, INOUT(Hit) hit) {
  float t;
  if (tri.material != WP_INVALID) {
    float u;
    float v;
    if (intersect_triangle(o, sh, tri.v0, tri.v1, tri.v2, hit.t, t, u, v)) {
      hit.t = t;
      hit.prim = i;
      hit.u = u;
      hit.v = v;
    }
  } else if (SCENE_HAS(FEATURE_SPHERES)) {
    Sphere sp = load_sphere(tri.shading);
    vec3 ol = xform_point(sp.toObject0, sp.toObject1, sp.toObject2, o);
    vec3 dl = xform_vector(sp.toObject0, sp.toObject1, sp.toObject2, d);
    if (intersect_unit_sphere(ol, dl, hit.t, t)) {
      hit.t = t;
      hit.prim = tri.shading | HIT_SPHERE_BIT;
      hit.u = 0.0f;
      hit.v = 0.0f;
    }
  }
}

// Tests primitive record i and keeps the nearer hit.
void intersect_prim(uint i, vec3 o, vec3 d, RayShear sh, INOUT(Hit) hit) {
  intersect_loaded_prim(i, load_triangle(i), o, d, sh, hit);
}

// The binary BVH (BvhNode), ordered and stack-based: each iteration visits one
// node (testing both children's boxes) or tests one primitive.
uint trace_binary(vec3 o, vec3 d, float tmax, bool anyHit, OUT(Hit) hit) {
  hit.t = tmax;
  hit.prim = WP_INVALID;
  hit.u = 0.0f;
  hit.v = 0.0f;
  vec3 invDir = vec3(1.0f) / d;
  RayShear sh = make_ray_shear(d);
  // Nodes are named by their (leftFirst, count) pair, read when their parent
  // tested their boxes, so each node is fetched from memory once.
  uvec2 stack[TRAVERSAL_STACK_SIZE];
  uint sp = 0u;
  BvhNode root = load_node(0u);
  uvec2 node = uvec2(root.leftFirst, root.count);
  bool haveNode = true;  // `node` is still to be visited
  uint leafNext = 0u;    // primitives [leafNext, leafEnd) of the current leaf remain
  uint leafEnd = 0u;
  uint steps = 0u;
  uint cap = scene.counts.z;
  // An empty scene's root has an inverted box, which the slab test alone would
  // take for the whole space.
  bool empty = root.bmin.x > root.bmax.x;
  if (root.count == 0u && (empty || intersect_aabb(o, invDir, root.bmin, root.bmax, tmax) == WP_INF)) return TRACE_OK;
  while (true) {
    steps += 1u;
    if (steps > cap) return TRACE_TRUNCATED;
    WP_NOTE_STEP();
    if (leafNext < leafEnd) {
      intersect_prim(leafNext, o, d, sh, hit);
      leafNext += 1u;
      if (anyHit && hit.prim != WP_INVALID) return TRACE_OK;
      continue;
    }
    if (!haveNode) {
      if (sp == 0u) break;
      sp -= 1u;
      node = stack[sp];
    }
    haveNode = false;
    if (node.y != 0u) {
      leafNext = node.x;
      leafEnd = node.x + node.y;
      continue;
    }
    BvhNode n0 = load_node(node.x);
    BvhNode n1 = load_node(node.x + 1u);
    float d0 = intersect_aabb(o, invDir, n0.bmin, n0.bmax, hit.t);
    float d1 = intersect_aabb(o, invDir, n1.bmin, n1.bmax, hit.t);
    uvec2 near = uvec2(n0.leftFirst, n0.count);
    uvec2 far = uvec2(n1.leftFirst, n1.count);
    if (d1 < d0) {
      float td = d0;
      d0 = d1;
      d1 = td;
      uvec2 tn = near;
      near = far;
      far = tn;
    }
    if (d0 == WP_INF) continue;  // neither child: pop on the next iteration
    node = near;
    haveNode = true;
    if (d1 != WP_INF) {
      stack[sp] = far;
      sp += 1u;
      WP_NOTE_STACK_DEPTH(sp);
    }
  }
  return TRACE_OK;
}

// Hit-mask bits of interior children (bits 0-23 are primitives).
#define WIDE_NODE_BITS 0xff000000u

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
// before tmax, else 0. Per axis the ray's distance to a quantized plane q is
// q * scale + base; nearX / farX are the plane words facing the ray and facing
// away (lower and upper planes swapped for negative directions). `meta` has
// the interior slots already permuted for the ray's octant.
uint wide_child_bits(uint slot, uvec2 meta, uvec2 nearX, uvec2 farX, uvec2 nearY, uvec2 farY, uvec2 nearZ, uvec2 farZ,
                     vec3 scale, vec3 base, float tmax) {
  float tnx = fma(float(slot_byte(nearX, slot)), scale.x, base.x);
  float tny = fma(float(slot_byte(nearY, slot)), scale.y, base.y);
  float tnz = fma(float(slot_byte(nearZ, slot)), scale.z, base.z);
  float tfx = fma(float(slot_byte(farX, slot)), scale.x, base.x);
  float tfy = fma(float(slot_byte(farY, slot)), scale.y, base.y);
  float tfz = fma(float(slot_byte(farZ, slot)), scale.z, base.z);
  float tnear = max_of(max_of(tnx, tny), max_of(tnz, 0.0f));
  // Widened by a few ulps against rounding in the slab distances.
  float tfar = min_of(min_of(tfx, tfy), min_of(tfz, tmax)) * 1.0000004f;
  uint m = slot_byte(meta, slot);
  return tnear <= tfar ? (m >> 5u) << (m & 31u) : 0u;
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
  WP_MOVE(r, c, 31u, 30u); WP_MOVE(r, c, 30u, 29u); WP_MOVE(r, c, 29u, 28u); WP_MOVE(r, c, 28u, 27u); \
  WP_MOVE(r, c, 27u, 26u); WP_MOVE(r, c, 26u, 25u); WP_MOVE(r, c, 25u, 24u); WP_MOVE(r, c, 24u, 23u); \
  WP_MOVE(r, c, 23u, 22u); WP_MOVE(r, c, 22u, 21u); WP_MOVE(r, c, 21u, 20u); WP_MOVE(r, c, 20u, 19u); \
  WP_MOVE(r, c, 19u, 18u); WP_MOVE(r, c, 18u, 17u); WP_MOVE(r, c, 17u, 16u); WP_MOVE(r, c, 16u, 15u); \
  WP_MOVE(r, c, 15u, 14u); WP_MOVE(r, c, 14u, 13u); WP_MOVE(r, c, 13u, 12u); WP_MOVE(r, c, 12u, 11u); \
  WP_MOVE(r, c, 11u, 10u); WP_MOVE(r, c, 10u, 9u); WP_MOVE(r, c, 9u, 8u); WP_MOVE(r, c, 8u, 7u); \
  WP_MOVE(r, c, 7u, 6u); WP_MOVE(r, c, 6u, 5u); WP_MOVE(r, c, 5u, 4u); WP_MOVE(r, c, 4u, 3u); \
  WP_MOVE(r, c, 3u, 2u); WP_MOVE(r, c, 2u, 1u); WP_MOVE(r, c, 1u, 0u);
// Every entry one place up where c (a pop drops the top).
#define WP_REGISTER_STACK_UP(r, c) \
  WP_MOVE(r, c, 0u, 1u); WP_MOVE(r, c, 1u, 2u); WP_MOVE(r, c, 2u, 3u); WP_MOVE(r, c, 3u, 4u); \
  WP_MOVE(r, c, 4u, 5u); WP_MOVE(r, c, 5u, 6u); WP_MOVE(r, c, 6u, 7u); WP_MOVE(r, c, 7u, 8u); \
  WP_MOVE(r, c, 8u, 9u); WP_MOVE(r, c, 9u, 10u); WP_MOVE(r, c, 10u, 11u); WP_MOVE(r, c, 11u, 12u); \
  WP_MOVE(r, c, 12u, 13u); WP_MOVE(r, c, 13u, 14u); WP_MOVE(r, c, 14u, 15u); WP_MOVE(r, c, 15u, 16u); \
  WP_MOVE(r, c, 16u, 17u); WP_MOVE(r, c, 17u, 18u); WP_MOVE(r, c, 18u, 19u); WP_MOVE(r, c, 19u, 20u); \
  WP_MOVE(r, c, 20u, 21u); WP_MOVE(r, c, 21u, 22u); WP_MOVE(r, c, 22u, 23u); WP_MOVE(r, c, 23u, 24u); \
  WP_MOVE(r, c, 24u, 25u); WP_MOVE(r, c, 25u, 26u); WP_MOVE(r, c, 26u, 27u); WP_MOVE(r, c, 27u, 28u); \
  WP_MOVE(r, c, 28u, 29u); WP_MOVE(r, c, 29u, 30u); WP_MOVE(r, c, 30u, 31u);

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

// ---- surfaces ----------------------------------------------------------------

// darts / Ray Tracing in One Weekend sphere coordinates on the unit sphere
// (y up): u around the y axis, v from the south pole (0) to the north pole (1).
vec2 sphere_uv(vec3 pl) {
  float theta = acos(clamp(-pl.y, -1.0f, 1.0f));
  float phi = atan(-pl.z, pl.x) + WP_PI;
  return vec2(phi * (0.5f * WP_INV_PI), theta * WP_INV_PI);
}

// The surface of sphere `sp` nearest to world point pw (reprojected onto it).
SurfaceHit sphere_surface_of(Sphere sp, vec3 pw) {
  vec3 pl = normalize(xform_point(sp.toObject0, sp.toObject1, sp.toObject2, pw));
  SurfaceHit s;
  s.p = xform_point(sp.toWorld0, sp.toWorld1, sp.toWorld2, pl);
  s.ng = normalize(xform_normal_by_inverse(sp.toObject0, sp.toObject1, sp.toObject2, pl));
  s.ns = s.ng;
  s.uv = sphere_uv(pl);
  s.material = sp.material;
  s.emitter = sp.emitter;
  s.pad = 0.0f;
  return s;
}

SurfaceHit sphere_surface(uint i, vec3 pw) {
  return sphere_surface_of(load_sphere(i), pw);
}

// The surface of triangle `tri` at barycentrics (b1, b2).
SurfaceHit triangle_surface_of(Triangle tri, float b1, float b2) {
  float b0 = 1.0f - b1 - b2;
  SurfaceHit s;
  s.p = tri.v0 * b0 + tri.v1 * b1 + tri.v2 * b2;
  s.ng = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
  s.ns = s.ng;
  s.uv = vec2(b1, b2);
  if (SCENE_HAS(FEATURE_SHADING_DATA) && tri.shading != WP_INVALID) {
    TriangleShading sh = load_shading(tri.shading);
    s.uv = vec2(sh.u0, sh.v0) * b0 + vec2(sh.uv12.x, sh.uv12.y) * b1 + vec2(sh.uv12.z, sh.uv12.w) * b2;
    if (sh.hasNormals != 0u) {
      vec3 n = sh.n0 * b0 + sh.n1 * b1 + sh.n2 * b2;
      float len = length(n);
      if (len > 0.0f) s.ns = dot(n, s.ng) >= 0.0f ? n / len : -n / len;
    }
  }
  s.material = tri.material;
  s.emitter = tri.emitter;
  s.pad = 0.0f;
  return s;
}

SurfaceHit triangle_surface(uint i, float b1, float b2) {
  return triangle_surface_of(load_triangle(i), b1, b2);
}

// The surface at a hit of the ray (o, d).
SurfaceHit surface_at(vec3 o, vec3 d, Hit h) {
  if (SCENE_HAS(FEATURE_SPHERES) && (h.prim & HIT_SPHERE_BIT) != 0u) return sphere_surface(h.prim & ~HIT_SPHERE_BIT, o + d * h.t);
  return triangle_surface(h.prim, h.u, h.v);
}

// The material at a ray's hit, or WP_INVALID where it hit nothing. Only the
// texel holding the material is fetched; the loaders stay the one definition
// of where it lies.
uint hit_material(Hit h) {
  if (h.prim == WP_INVALID) return WP_INVALID;
  if (SCENE_HAS(FEATURE_SPHERES) && (h.prim & HIT_SPHERE_BIT) != 0u) return load_sphere(h.prim & ~HIT_SPHERE_BIT).material;
  return load_triangle(h.prim).material;
}

float triangle_area(Triangle tri) {
  return 0.5f * length(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
}

// ---- textures ----------------------------------------------------------------

#define TEXTURE_MAX_NESTING 8

// Where texture t is looked up: its mapping applied to the hit point (solid
// textures) or to (u, v, 0).
vec3 texture_point(Texture t, vec2 uv, vec3 p) {
  vec3 q = (t.info.x & TEX_SOLID) != 0u ? p : vec3(uv.x, uv.y, 0.0f);
  return xform_point(t.map0, t.map1, t.map2, q);
}

vec3 texel_at(Texture t, uint x, uint y) {
  uvec4 packed = texelFetch(imageTexels, int(t.info.y + y * t.info.z + x));
  vec2 rg = unpackHalf2x16(packed.x);
  vec2 b = unpackHalf2x16(packed.y);
  return vec3(rg.x, rg.y, b.x);
}

// Bilinear lookup, repeating; v = 0 is the bottom row of the image.
vec3 image_lookup(Texture t, vec3 q) {
  uint w = t.info.z;
  uint h = t.info.w;
  float x = (q.x - floor(q.x)) * float(w) - 0.5f;
  float y = (1.0f - (q.y - floor(q.y))) * float(h) - 0.5f;
  float x0f = floor(x);
  float y0f = floor(y);
  float fx = x - x0f;
  float fy = y - y0f;
  // x0f lies in [-1, w - 1]: wrap without a (GLSL-undefined) negative modulo.
  uint x0 = x0f < 0.0f ? w - 1u : min(uint(x0f), w - 1u);
  uint y0 = y0f < 0.0f ? h - 1u : min(uint(y0f), h - 1u);
  uint x1 = x0 + 1u >= w ? 0u : x0 + 1u;
  uint y1 = y0 + 1u >= h ? 0u : y0 + 1u;
  vec3 top = mix(texel_at(t, x0, y0), texel_at(t, x1, y0), fx);
  vec3 bottom = mix(texel_at(t, x0, y1), texel_at(t, x1, y1), fx);
  return mix(top, bottom, fy);
}

// Colour of texture `index` at a surface point. Reads only the fields a
// texture's type needs: on lavapipe every 16 bytes loaded costs more than the
// arithmetic around them, and most textures are constants.
vec3 texture_eval(uint index, vec2 uv, vec3 p) {
  uvec4 info = load_texture(index).info;
  // A checker picks one of two textures; follow the picks (the loader bounds the nesting).
  for (uint depth = 0u; SCENE_HAS(FEATURE_CHECKER) && depth < TEXTURE_MAX_NESTING && (info.x & TEX_TYPE_MASK) == TEX_CHECKER; ++depth) {
    Texture t = load_texture(index);
    vec3 c = floor(texture_point(t, uv, p) * t.color0.w);
    int parity = (int(c.x) + int(c.y) + int(c.z)) & 1;
    index = parity == 0 ? info.y : info.z;
    info = load_texture(index).info;
  }
  uint type = info.x & TEX_TYPE_MASK;
  if (SCENE_HAS(FEATURE_MARBLE) && type == TEX_MARBLE) {
    Texture t = load_texture(index);
    float m = marble_pattern(texture_point(t, uv, p) * t.color0.w);
    return mix(vec3(t.color0.x, t.color0.y, t.color0.z), vec3(t.color1.x, t.color1.y, t.color1.z), m);
  }
  if (SCENE_HAS(FEATURE_IMAGE) && type == TEX_IMAGE) {
    Texture t = load_texture(index);
    return image_lookup(t, texture_point(t, uv, p));
  }
  vec4 c = load_texture(index).color0;
  return vec3(c.x, c.y, c.z);
}

// ---- materials ---------------------------------------------------------------

// Radiance the surface emits towards wo (front side only). Emission is
// nearly always one colour: a scene without FEATURE_EMISSION_TEXTURES reads
// it and spares its kernels the copies of texture_eval that shade inlines
// here (the hit's and each light sample's), which lavapipe would run for
// every path.
vec3 emitted_radiance(SurfaceHit s, vec3 wo) {
  uint tex = load_material(s.material).info.z;
  if (tex == WP_INVALID || dot(s.ng, wo) <= 0.0f) return vec3(0.0f);
  if (!SCENE_HAS(FEATURE_EMISSION_TEXTURES)) {
    vec4 c = load_texture(tex).color0;
    return vec3(c.x, c.y, c.z);
  }
  return texture_eval(tex, s.uv, s.p);
}

// The lobe a non-blend material contributes, with its colour and weight.
void bsdf_set_lobe(INOUT(Bsdf) b, uint k, Material m, vec3 color, float w) {
  b.lobeType[k] = m.info.x;
  b.lobeColor[k] = color;
  b.lobeParam[k] = m.params.x;
  b.lobeWeight[k] = w;
}

// Whether a material's step of bsdf_at looks up no texture: the dielectric
// is white, a light adds no lobe, and a Fresnel blend computes its amount.
bool material_needs_no_texture(Material m) {
  if (SCENE_HAS(FEATURE_DIELECTRIC) && m.info.x == MAT_DIELECTRIC) return true;
  if (m.info.x == MAT_LIGHT) return true;
  return SCENE_HAS(FEATURE_BLEND) && m.info.x == MAT_BLEND && (load_texture(m.info.w).info.x & TEX_TYPE_MASK) == TEX_FRESNEL;
}

// The BSDF at s seen from wo: textures looked up, blends flattened into
// weighted lobes (depth-first, bounded: the loader allows at most
// BSDF_MAX_LOBES leaves per material).
Bsdf bsdf_at(SurfaceHit s, vec3 wo) {
  Bsdf b;
  b.front = dot(s.ng, wo) >= 0.0f;
  b.ng = b.front ? s.ng : -s.ng;
  b.ns = b.front ? s.ns : -s.ns;
  b.lobeCount = 0u;
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    b.lobeType[i] = MAT_LAMBERTIAN;
    b.lobeColor[i] = vec3(0.0f);
    b.lobeParam[i] = 0.0f;
    b.lobeWeight[i] = 0.0f;
  }
  Material m = load_material(s.material);
  if (m.info.x == MAT_LIGHT) return b;  // emits, does not scatter
  if (!SCENE_HAS(FEATURE_BLEND)) {  // one lobe
    vec3 color = material_needs_no_texture(m) ? vec3(1.0f) : texture_eval(m.info.y, s.uv, s.p);
    bsdf_set_lobe(b, 0u, m, color, 1.0f);
    b.lobeCount = 1u;
    return b;
  }
  // Scenes with blends take every material through the loop, a plain one in
  // one step. Each step looks up one texture, a blend's amount or a lobe's
  // colour, so one copy of texture_eval serves both: lavapipe runs every
  // copy, masked, for every SIMD group, and a separate path for plain
  // materials ran one more.
  uint stackMaterial[BSDF_MAX_LOBES];
  float stackWeight[BSDF_MAX_LOBES];
  stackMaterial[0] = s.material;
  stackWeight[0] = 1.0f;
  uint sp = 1u;
  float total = 0.0f;
  for (uint iter = 0u; iter < 2u * BSDF_MAX_LOBES && sp > 0u; ++iter) {
    sp -= 1u;
    m = load_material(stackMaterial[sp]);
    float w = stackWeight[sp];
    bool blend = m.info.x == MAT_BLEND;
    bool untextured = material_needs_no_texture(m);
    vec3 color = untextured ? vec3(1.0f) : texture_eval(blend ? m.info.w : m.info.y, s.uv, s.p);
    if (blend) {
      // The amount: a texture's mean, or the Fresnel reflectance at the hit.
      float ior = untextured ? load_texture(m.info.w).color0.x : 1.0f;
      float amount = untextured ? fresnel_dielectric(abs(dot(wo, s.ns)), b.front ? ior : 1.0f / ior)
                                : clamp((color.x + color.y + color.z) * (1.0f / 3.0f), 0.0f, 1.0f);
      if (sp + 2u <= BSDF_MAX_LOBES) {
        stackMaterial[sp] = m.children.y;
        stackWeight[sp] = w * amount;
        stackMaterial[sp + 1u] = m.children.x;
        stackWeight[sp + 1u] = w * (1.0f - amount);
        sp += 2u;
      }
      continue;
    }
    if (m.info.x == MAT_LIGHT || w <= 0.0f || b.lobeCount >= BSDF_MAX_LOBES) continue;
    bsdf_set_lobe(b, b.lobeCount, m, color, w);
    b.lobeCount += 1u;
    total += w;
  }
  // Weights are sampling probabilities: normalise them and move their sum into
  // the colours, so f is unchanged.
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    if (i < b.lobeCount) {
      b.lobeWeight[i] /= total;
      b.lobeColor[i] *= total;
    }
  }
  return b;
}

// ---- environment map ----------------------------------------------------------

// Equirectangular: -Z at the image's centre column, +Y at its top row.
vec2 environment_uv(vec3 d) {
  float phi = atan(d.x, -d.z);
  float theta = acos(clamp(d.y, -1.0f, 1.0f));
  return vec2(0.5f + phi * (0.5f * WP_INV_PI), 1.0f - theta * WP_INV_PI);
}

// Radiance arriving from direction d out of the scene: the environment map, or
// the constant background.
vec3 background_radiance(vec3 d) {
  if (!SCENE_HAS(FEATURE_ENVIRONMENT) || scene.environment.x == WP_INVALID) return vec3(scene.background.x, scene.background.y, scene.background.z);
  return texture_eval(scene.environment.x, environment_uv(d), d);
}

// The interval i in [0, count) of the CDF at `offset` with cdf[i] <= u < cdf[i + 1]
// (never an empty one). Bisection: at most 32 steps.
uint cdf_find(uint offset, uint count, float u) {
  uint lo = 0u;
  uint hi = count;
  while (lo + 1u < hi) {
    uint mid = (lo + hi) / 2u;
    if (cdf_at(offset + mid) <= u) lo = mid;
    else hi = mid;
  }
  return lo;
}

// Density of the grid cell (row, col) per unit of the (u, v) square.
float environment_cell_pdf(uint row, uint col) {
  uint w = scene.environment.z;
  uint h = scene.environment.w;
  uint rowCdf = h + 1u + row * (w + 1u);
  float pRow = (cdf_at(row + 1u) - cdf_at(row)) * float(h);
  float pCol = (cdf_at(rowCdf + col + 1u) - cdf_at(rowCdf + col)) * float(w);
  return pRow * pCol;
}

// Solid-angle density with which environment_sample picks direction d: the
// cell's density over the sphere's area element, 2 pi^2 sin(theta).
float environment_pdf(vec3 d) {
  uint w = scene.environment.z;
  uint h = scene.environment.w;
  vec2 uv = environment_uv(d);
  uint col = min(uint(max(uv.x, 0.0f) * float(w)), w - 1u);
  uint row = min(uint(max(1.0f - uv.y, 0.0f) * float(h)), h - 1u);
  float sinTheta = length(vec2(d.x, d.z));  // not sqrt(1 - y^2): that cancels near the poles
  return sinTheta > 0.0f ? environment_cell_pdf(row, col) / (2.0f * WP_PI * WP_PI * sinTheta) : 0.0f;
}

// A direction in proportion to the environment's luminance (times sin theta):
// a row from the marginal CDF, a column from that row's CDF, uniform within the cell.
vec3 environment_sample(vec2 u, OUT(float) pdf) {
  uint w = scene.environment.z;
  uint h = scene.environment.w;
  uint row = cdf_find(0u, h, u.y);
  float r0 = cdf_at(row);
  float dv = clamp((u.y - r0) / (cdf_at(row + 1u) - r0), 0.0f, 1.0f);
  uint rowCdf = h + 1u + row * (w + 1u);
  uint col = cdf_find(rowCdf, w, u.x);
  float c0 = cdf_at(rowCdf + col);
  float du = clamp((u.x - c0) / (cdf_at(rowCdf + col + 1u) - c0), 0.0f, 1.0f);
  float theta = (float(row) + dv) / float(h) * WP_PI;
  float phi = ((float(col) + du) / float(w) - 0.5f) * (2.0f * WP_PI);
  float sinTheta = sin(theta);
  vec3 d = vec3(sinTheta * sin(phi), cos(theta), -sinTheta * cos(phi));
  sinTheta = length(vec2(d.x, d.z));  // exactly as environment_pdf computes it
  pdf = sinTheta > 0.0f ? environment_cell_pdf(row, col) / (2.0f * WP_PI * WP_PI * sinTheta) : 0.0f;
  return d;
}

// ---- emitters ----------------------------------------------------------------

// Picks an emitter index with the alias table (in proportion to power) and
// returns the probability of that pick.
uint pick_emitter(float u, OUT(float) pmf) {
  uint count = scene.counts.x;
  float x = u * float(count);
  uint i = min(uint(x), count - 1u);
  Emitter e = load_emitter(i);
  uint chosen = (x - float(i)) < e.threshold ? i : e.alias;
  pmf = load_emitter(chosen).pmf;
  return chosen;
}

// 1 - cos of the half-angle of the cone that sphere sp subtends from ref, or 0
// when ref is inside the sphere (then it sees only the sphere's unlit back).
float sphere_cone(Sphere sp, vec3 ref, OUT(vec3) center, OUT(float) radius) {
  center = vec3(sp.toWorld0.w, sp.toWorld1.w, sp.toWorld2.w);
  radius = sqrt(sp.area * (0.25f * WP_INV_PI));
  vec3 d = center - ref;
  float dc2 = dot(d, d);
  float r2 = radius * radius;
  if (dc2 <= r2) return 0.0f;
  float sin2 = r2 / dc2;
  // Series for small cones, where 1 - sqrt(1 - x) cancels.
  return sin2 < 1e-3f ? sin2 * (0.5f + 0.125f * sin2) : 1.0f - sqrt(1.0f - sin2);
}

// Solid-angle density with which sample_emitter, called at ref, reaches the
// emitter surface point s at distance dist along unit direction wi.
float emitter_pdf(uint emitter, vec3 ref, SurfaceHit s, vec3 wi, float dist) {
  Emitter e = load_emitter(emitter);
  if (SCENE_HAS(FEATURE_SPHERE_LIGHTS) && (e.prim & HIT_SPHERE_BIT) != 0u) {
    vec3 c;
    float r;
    float cone = sphere_cone(load_sphere(e.prim & ~HIT_SPHERE_BIT), ref, c, r);
    return cone > 0.0f ? e.pmf * uniform_cone_pdf(cone) : 0.0f;
  }
  float cosL = -dot(s.ng, wi);
  if (cosL <= 0.0f) return 0.0f;
  return e.pmf / triangle_area(load_triangle(e.prim)) * dist * dist / cosL;
}

// Next-event estimation: picks an emitter, then a point on it as seen from ref:
// uniform in the subtended cone for spheres, uniform by area for triangles, by
// luminance for the environment map (a direction, at distance WP_INF).
bool sample_emitter(vec3 ref, vec3 u, OUT(LightSample) ls) {
  ls.wi = vec3(0.0f);
  ls.dist = 0.0f;
  ls.radiance = vec3(0.0f);
  ls.pdf = 0.0f;
  ls.p = vec3(0.0f);
  ls.isDelta = 0u;
  ls.n = vec3(0.0f);
  if (scene.counts.x == 0u) return false;
  float pmf;
  Emitter e = load_emitter(pick_emitter(u.x, pmf));
  vec2 uv = vec2(u.y, u.z);
  if (SCENE_HAS(FEATURE_ENVIRONMENT) && e.prim == EMITTER_ENVIRONMENT) {
    float pdfDir;
    ls.wi = environment_sample(uv, pdfDir);
    if (pdfDir <= 0.0f) return false;
    ls.dist = WP_INF;  // at infinity: the shadow ray is unbounded
    ls.radiance = background_radiance(ls.wi);
    ls.pdf = pmf * pdfDir;
    ls.n = -ls.wi;
    return true;
  }
  if (SCENE_HAS(FEATURE_POINT_LIGHTS) && (e.prim & EMITTER_POINT_BIT) != 0u) {
    PointLight l = load_point_light(e.prim & ~EMITTER_POINT_BIT);
    vec3 d = vec3(l.position.x, l.position.y, l.position.z) - ref;
    float dist2 = dot(d, d);
    if (dist2 <= 0.0f) return false;
    ls.dist = sqrt(dist2);
    ls.wi = d / ls.dist;
    ls.p = vec3(l.position.x, l.position.y, l.position.z);
    ls.radiance = vec3(l.intensity.x, l.intensity.y, l.intensity.z) / dist2;
    ls.pdf = pmf;
    ls.isDelta = 1u;
    return true;
  }
  SurfaceHit s;
  if (SCENE_HAS(FEATURE_SPHERE_LIGHTS) && (e.prim & HIT_SPHERE_BIT) != 0u) {
    Sphere sp = load_sphere(e.prim & ~HIT_SPHERE_BIT);
    vec3 c;
    float r;
    float cone = sphere_cone(sp, ref, c, r);
    if (cone <= 0.0f) return false;
    vec3 axis = normalize(c - ref);
    vec3 t;
    vec3 b;
    make_frame(axis, t, b);
    vec3 local = square_to_uniform_cone(uv, cone);
    vec3 w = frame_to_world(local, t, b, axis);
    // The nearer intersection of the ray (ref, w) with the sphere.
    float dc = length(c - ref);
    float sin2 = max(0.0f, 1.0f - local.z * local.z);
    float ds = dc * local.z - sqrt(max(0.0f, r * r - dc * dc * sin2));
    s = sphere_surface_of(sp, ref + w * ds);
    ls.pdf = pmf * uniform_cone_pdf(cone);
  } else {
    Triangle tri = load_triangle(e.prim);
    vec2 bary = square_to_triangle_barycentric(uv);
    s = triangle_surface_of(tri, bary.x, bary.y);
    ls.pdf = pmf / triangle_area(tri);  // per unit area; per solid angle below
  }
  vec3 d = s.p - ref;
  float dist2 = dot(d, d);
  if (dist2 <= 0.0f) return false;
  ls.dist = sqrt(dist2);
  ls.wi = d / ls.dist;
  float cosL = -dot(s.ng, ls.wi);
  if (cosL <= 0.0f) return false;  // back side: emits nothing
  if (!SCENE_HAS(FEATURE_SPHERE_LIGHTS) || (e.prim & HIT_SPHERE_BIT) == 0u) ls.pdf *= dist2 / cosL;
  ls.p = s.p;
  ls.n = s.ng;
  ls.radiance = emitted_radiance(s, -ls.wi);
  return true;
}

// Solid-angle density with which sample_emitter at ref produces direction wi:
// the sum over every emitter the line crosses from the front, occluded or not
// (the mixture integrator needs the exact density). Loops over all emitters.
float emitters_pdf_direction(vec3 ref, vec3 wi) {
  float pdf = 0.0f;
  RayShear sh = make_ray_shear(wi);
  for (uint i = 0u; i < scene.counts.x; ++i) {
    Emitter e = load_emitter(i);
    if (SCENE_HAS(FEATURE_ENVIRONMENT) && e.prim == EMITTER_ENVIRONMENT) {
      pdf += e.pmf * environment_pdf(wi);  // every direction reaches it
      continue;
    }
    if ((e.prim & (EMITTER_POINT_BIT | EMITTER_ENVIRONMENT)) != 0u) continue;
    float t;
    SurfaceHit s;
    if (SCENE_HAS(FEATURE_SPHERE_LIGHTS) && (e.prim & HIT_SPHERE_BIT) != 0u) {
      Sphere sp = load_sphere(e.prim & ~HIT_SPHERE_BIT);
      vec3 ol = xform_point(sp.toObject0, sp.toObject1, sp.toObject2, ref);
      vec3 dl = xform_vector(sp.toObject0, sp.toObject1, sp.toObject2, wi);
      if (!intersect_unit_sphere(ol, dl, WP_INF, t)) continue;
      s = sphere_surface_of(sp, ref + wi * t);
    } else {
      Triangle tri = load_triangle(e.prim);
      float b1;
      float b2;
      if (!intersect_triangle(ref, sh, tri.v0, tri.v1, tri.v2, WP_INF, t, b1, b2)) continue;
      s = triangle_surface_of(tri, b1, b2);
    }
    if (dot(s.ng, wi) < 0.0f) pdf += emitter_pdf(i, ref, s, wi, t);
  }
  return pdf;
}

#endif  // WP_SCENE_GLSL
