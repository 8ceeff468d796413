// types.glsl — every struct that crosses the host/device boundary, written once.
// Compiled as GLSL (std430 storage buffers, std140 uniform block) and as C++
// inside namespace wp::shader. Each struct is built from 16-byte groups so that
// std430, std140 and the C++ ABI lay it out identically; src/render/shader_cpp.h
// static_asserts the sizes and tests/test_layout.cpp compares every member offset
// with the offsets glslang assigned in the compiled SPIR-V.
#ifndef WP_TYPES_GLSL
#define WP_TYPES_GLSL

// ---- limits shared by the BVH builder and the traversal kernels -------------
// Deepest BVH the builder may produce; the traversal stack has this many slots,
// so it can never overflow.
#define BVH_MAX_DEPTH 80
#define BVH_MAX_LEAF_SIZE 255
// Leaf node flag in BvhNode.count: the leaf holds spheres, not triangles.
#define BVH_SPHERE_LEAF 0x80000000u

// Hit.prim: bit 31 marks a sphere; WP_INVALID marks a miss.
#define HIT_SPHERE_BIT 0x80000000u

// Material types.
#define MAT_LAMBERTIAN 0u
#define MAT_LIGHT 1u  // darts diffuse_light: emits, does not scatter

// PathState.flags bits (above the 16-bit bounce depth).
#define PATH_DEPTH_MASK 0xffffu
#define PATH_SPECULAR 0x10000u  // previous bounce was a delta lobe (or the camera)

// SceneParams.flags bits.
#define SCENE_FLAG_NO_NEE 1u      // BSDF sampling only (darts "path tracer mats")
#define SCENE_FLAG_NO_BSDF_MIS 2u // NEE only: emitters hit by BSDF rays are ignored

// Counters[] slots written by the kernels (see CounterSlot in src/gpu).
#define COUNTER_QUEUE0 0u
#define COUNTER_QUEUE1 1u
#define COUNTER_SHADOW 2u
#define COUNTER_TRUNCATED 3u
#define COUNTER_NONFINITE 4u
#define COUNTER_COUNT 8u

// Dispatch-indirect argument slots (3 uints each) in the indirect buffer.
#define INDIRECT_EXTEND 0u
#define INDIRECT_CONNECT 1u

// Two-level-free BVH2 node, 32 bytes. Interior node: count == 0, children at
// leftFirst and leftFirst + 1 (siblings are adjacent so one index suffices).
// Leaf: count = number of primitives (low 31 bits) starting at leftFirst in the
// triangle array, or in the sphere array when BVH_SPHERE_LEAF is set.
struct BvhNode {
  vec3 bmin;
  uint leftFirst;
  vec3 bmax;
  uint count;
};

// A triangle in world space, in BVH leaf order. 48 bytes.
struct Triangle {
  vec3 v0;
  uint material;
  vec3 v1;
  uint emitter;  // index into the emitter table, or WP_INVALID
  vec3 v2;
  uint sourceIndex;  // index of the triangle in scene order (for debugging / later UVs)
};

// A sphere: the unit sphere placed by an affine transform (so it may be an
// ellipsoid). Both directions of the transform are stored as 3x4 row matrices:
// world->object for intersection and normals, object->world for sampling and
// for reprojecting hit points onto the surface.
struct Sphere {
  vec4 toWorld0;
  vec4 toWorld1;
  vec4 toWorld2;
  vec4 toObject0;
  vec4 toObject1;
  vec4 toObject2;
  uint material;
  uint emitter;
  float area;  // surface area in world space (only valid when uniformly scaled)
  uint sourceIndex;
};

struct Material {
  vec4 albedo;    // rgb reflectance, a unused
  vec4 emission;  // rgb radiance emitted from the front side, a unused
  uvec4 info;     // x: MAT_* type
};

// One entry of the emitter alias table (Vose). Picking: i = floor(u * N);
// take i if frac < threshold, else alias. pmf is the probability of i itself.
struct Emitter {
  uint prim;  // Hit.prim encoding: triangle index, or sphere index | HIT_SPHERE_BIT
  uint alias;
  float threshold;
  float pmf;
};

// Everything the kernels know about the scene and the render, one uniform block.
struct SceneParams {
  vec4 camToWorld0;  // camera-to-world 3x4, rows; camera looks down -Z
  vec4 camToWorld1;
  vec4 camToWorld2;
  vec4 camLens;      // x: tan(vfov/2), y: aspect w/h, z: lens radius, w: focus distance
  vec4 background;   // rgb radiance of escaped rays
  uvec4 image;       // x: width, y: height, z: max bounces, w: Russian roulette start depth
  uvec4 counts;      // x: emitter count, y: seed, z: traversal step cap, w: SCENE_FLAG_*
  vec4 debug;        // x: radiance scale inside debugRegion (1 unless a bias is planted)
  uvec4 debugRegion; // pixels [x0, x1) x [y0, y1) the planted bias applies to
};

// A path in flight. 64 bytes.
struct PathState {
  vec3 origin;
  uint pixel;
  vec3 dir;  // unit length
  uint rng;
  vec3 throughput;
  uint flags;  // bounce depth in the low 16 bits, PATH_* flags above
  vec3 radiance;
  float bsdfPdf;  // solid-angle pdf of the direction that produced this ray
};

// Closest hit of a path's current ray. 16 bytes.
struct Hit {
  float t;
  uint prim;  // WP_INVALID on a miss
  float u;    // barycentrics for triangles
  float v;
};

// A next-event-estimation shadow ray; valid when tmax > 0. 48 bytes.
struct ShadowRay {
  vec3 origin;
  float tmax;  // the segment ends at origin + tmax * dir
  vec3 dir;
  uint path;
  vec3 contribution;  // added to the path's radiance if the segment is unoccluded
  uint pad;
};

// Per-pixel accumulator of one batch, 32 bytes: sum in xyz, sample count in
// sum.w, sum of squares in sumSq.xyz. Each batch holds few samples, so float
// is exact enough; the host folds batches into double precision.
struct PixelAccum {
  vec4 sum;
  vec4 sumSq;
};

#endif  // WP_TYPES_GLSL
