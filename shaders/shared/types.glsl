// types.glsl — every struct that crosses the host/device boundary, written once.
// Compiled as GLSL (std430 storage buffers, std140 uniform block) and as C++
// inside namespace wp::shader. Each struct is built from 16-byte groups so that
// std430, std140 and the C++ ABI lay it out identically; src/render/shader_cpp.h
// static_asserts the sizes and tests/test_layout.cpp compares every member offset
// with the offsets glslang assigned in the compiled SPIR-V.
#ifndef WP_TYPES_GLSL
#define WP_TYPES_GLSL

#include "limits.glsl"

// ---- limits shared by the BVH builders and the traversal kernels ------------
// Primitive groups the wide walk sets aside on its stack at most, beside one
// node group per level below the root (scene.glsl, trace_wide).
#define WIDE_STACK_PRIM_GROUPS 2u
// Entries a walk sets aside when it enters an instance (traverse_*.glsl):
// what remains of the top level (the wide walk's node group and, in octant
// order, its node to visit; the binary walk's leaf) and the entry that
// returns to it, with the wide walk's primitive group.
#define INSTANCE_ENTRY_SLOTS 3u
// Slots of the traversal stack in C++: enough for any two-level tree the
// builders make (the binary walk keeps one entry per level, the wide walk the
// above; an instance's tree stacks on the top level's). The kernels size
// theirs by specialization constant 5 to what the scene's trees need.
#define BVH_STACK_MAX (2u * (BVH_MAX_DEPTH + WIDE_STACK_PRIM_GROUPS) + INSTANCE_ENTRY_SLOTS)

// SceneParams.accel.x: which node layout the kernels traverse.
#define BVH_LAYOUT_BINARY 0u  // BvhNode: two children per node, float boxes
#define BVH_LAYOUT_WIDE 1u    // WideNode: eight children, quantized boxes
// SceneParams.accel.y: the order in which the wide walk visits a node's hit
// children (wide_walk_step.glsl).
#define WIDE_ORDER_OCTANT 0u   // by the slots of the ray's octant: a fixed order, no sort
#define WIDE_ORDER_DISTANCE 1u // nearest first, by a sorting network over their entry distances
// SceneParams.accel.w: bits choosing how the walks iterate.
#define WALK_ROOT_AT_ENTRY 1u  // the wide walk visits an instance's root in the iteration that enters it
#define WALK_BINARY_FUSED 2u   // each iteration of the binary walk tests a primitive and visits a node (trace_binary_fused)
// A wide node's leaf child holds at most this many primitives, and all its
// leaf children together at most WIDE_MAX_NODE_PRIMS (offsets in 5 bits).
#define WIDE_MAX_LEAF_SIZE 3
#define WIDE_MAX_NODE_PRIMS 24

// Hit.prim: bit 31 marks a sphere; WP_INVALID marks a miss.
#define HIT_SPHERE_BIT 0x80000000u
// Triangle.material of an instance's placeholder in the top level's leaves.
#define PRIM_INSTANCE 0xfffffffeu

#include "kinds.glsl"
#include "layers.glsl"

// Emitter.prim: a point light (index into pointLights) rather than a surface;
// or the environment map; or a triangle that no ray meets, which only light
// sampling sees (CS184's area lights; Scene::lightOnlyTriangles).
#define EMITTER_POINT_BIT 0x40000000u
#define EMITTER_ENVIRONMENT 0x20000000u
#define EMITTER_UNSEEN_BIT 0x10000000u

// SceneParams.mode.x: what the integrator computes (darts integrator names).
#define INTEGRATOR_PATH 0u     // path tracer mis / nee / mats (see SCENE_FLAG_*)
#define INTEGRATOR_NORMALS 1u  // shading normal mapped to colour, (n + 1) / 2
#define INTEGRATOR_AO 2u       // ambient occlusion: one cosine-weighted visibility ray
#define INTEGRATOR_MIXTURE 3u  // one direction from the mixture of BSDF and emitter sampling
#define INTEGRATOR_PHOTONS 4u  // photon mapping: specular paths to a gather from the photon map (photons.glsl)

// PathState.flags bits (above the 16-bit bounce depth).
#define PATH_DEPTH_MASK 0xffffu
#define PATH_SPECULAR 0x10000u  // previous bounce was a delta lobe (or the camera)
#define PATH_DEAD 0x20000u      // finished; only set by kernels that run without path compaction
// The colour channel a path carries alone since it entered a dispersive
// volume (FEATURE_DISPERSION): 0 all three, 1 red, 2 green, 3 blue (in the
// spectral mode: the first, second or third of its wavelengths).
#define PATH_CHANNEL_SHIFT 18u
#define PATH_CHANNEL_MASK 0xc0000u

// SceneParams.flags bits.
#define SCENE_FLAG_NO_NEE 1u      // BSDF sampling only (darts "path tracer mats")
#define SCENE_FLAG_NO_BSDF_MIS 2u // NEE only: emitters hit by BSDF rays are ignored
#define SCENE_FLAG_HEMISPHERE 4u  // directions uniform over the hemisphere, not from the BSDF (CS184 -H)
// CS184's estimator (docs/scene-format.md, "CS184"): emitters outside the
// light table count only for camera rays and after specular bounces (unless
// light sampling is off), emission is seen from both sides, light-only area
// lights give their distance times their radiance (as the course's density
// makes them), escaped rays see the environment only from the camera, and
// Russian roulette continues with probability min(1, 10 luminance(f)) after
// every bounce but a first of several.
#define SCENE_FLAG_CS184 8u
// The environment map in CS184's lat-long layout (its environment_light.cpp):
// +X at the centre column, the image mirrored against wavepath's.
#define SCENE_FLAG_CS184_LATLONG 16u
// The spectral mode (FEATURE_SPECTRAL, spectral.glsl): each path carries
// radiance at PATH_WAVELENGTHS wavelengths, and RGB inputs are uplifted.
#define SCENE_FLAG_SPECTRAL 32u

// Counters[] slots written by the kernels (see CounterSlot in src/gpu).
#define COUNTER_QUEUE0 0u
#define COUNTER_QUEUE1 1u
#define COUNTER_SHADOW 2u
#define COUNTER_TRUNCATED 3u
#define COUNTER_NONFINITE 4u
// Rays traced, as 64-bit counts: the low word in this slot, the high word in
// the next (see count_rays in kernel.glsl).
#define COUNTER_CLOSEST_RAYS 5u
#define COUNTER_SHADOW_RAYS 7u
// The photons kernel (photons.comp): records appended, photons still going.
#define COUNTER_PHOTON_RECORDS 9u
#define COUNTER_PHOTONS_ALIVE 10u
// The blocks of items the tracing kernels' subgroups have taken (trace_items.glsl, kDynamicFetch).
#define COUNTER_TRACE_BLOCKS 11u
#define COUNTER_COUNT 12u

// Sorting paths by material class (variant gpu-sort): between
// extend and shade, the sort kernel appends each path to the queue of its
// sort key, and each key's paths are shaded by a kernel of their own,
// specialized to the material and texture kinds of the key's class (on
// lavapipe a kernel costs every path the code of every kind it holds, taken
// or not). Key 0 holds the rays that hit nothing; key c + 1 the materials of
// shade class c, which compile_scene writes to each Material.children.w.
#define SORT_KEYS 16u
#define SORT_KEY_MISS 0u
#define SHADE_CLASSES_MAX (SORT_KEYS - 1u)
// Queue QUEUE_SORTED + k (after queues 0 and 1) holds the paths of sort key k.
#define QUEUE_SORTED 2u

// Dispatch-indirect argument slots (3 uints each) in the indirect buffer.
#define INDIRECT_EXTEND 0u
#define INDIRECT_CONNECT 1u
#define INDIRECT_SHADE 2u     // one invocation per queued path (sort, shade)
#define INDIRECT_SHADE_KEY0 3u  // sorted: one invocation per path of sort key k in slot INDIRECT_SHADE_KEY0 + k
#define INDIRECT_SLOTS (INDIRECT_SHADE_KEY0 + SORT_KEYS)

// Binary BVH node, 32 bytes. Interior node: count == 0, children at
// leftFirst and leftFirst + 1 (siblings are adjacent so one index suffices).
// Leaf: `count` primitives starting at leftFirst in the primitive array.
struct BvhNode {
  vec3 bmin;
  uint leftFirst;
  vec3 bmax;
  uint count;
};

// Node of the 8-wide compressed BVH (after Ylitie, Karras and Laine, "Efficient
// Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017),
// 80 bytes. Child boxes are quantized to 8 bits per plane on a grid that starts
// at `origin` with cells of 2^(e - 127) per axis, rounded outwards, so the
// decoded box always contains the child.
//
// Each of the 8 child slots has a meta byte: 0 for an empty slot; for an
// interior child 0b001 << 5 | (24 + slot); for a leaf child the number of its
// primitives in unary (0b001, 0b011, 0b111) << 5 | their offset from primBase.
// Either way (meta >> 5) << (meta & 31) is the child's bits in a 32-bit hit
// mask: bits 24-31 for interior slots, bits 0-23 for primitives. Interior
// children are stored consecutively from childBase in slot order, leaf
// primitives consecutively from primBase. The builder puts children in slots
// by direction from the node's centre, so a ray visiting slots in the order
// its direction octant gives meets near children first.
struct WideNode {
  vec3 origin;
  uint exyzImask;  // bytes: exponents e.x, e.y, e.z, then imask (bit s: slot s is interior)
  uint childBase;  // index of the first interior child node
  uint primBase;   // index of the first primitive of the leaf children
  uint meta0123;   // meta bytes of slots 0..3 (slot 0 in the low byte)
  uint meta4567;
  uvec4 qlo;       // quantized lower planes: x slots 0-3, x 4-7, y 0-3, y 4-7
  uvec4 qloZqhiX;  // z lower 0-3, z lower 4-7, x upper 0-3, x upper 4-7
  uvec4 qhi;       // y upper 0-3, y upper 4-7, z upper 0-3, z upper 4-7
};

// The scene's records are read through texel buffers of RGBA32UI texels (see
// bindings.glsl); these are their sizes in texels.
#define BVH_NODE_TEXELS 2
#define WIDE_NODE_TEXELS 5
#define TRIANGLE_TEXELS 3
#define TRIANGLE_SHADING_TEXELS 4
#define TRIANGLE_VERTEX_DATA_TEXELS 8
#define SPHERE_TEXELS 7
#define INSTANCE_TEXELS 7
#define MATERIAL_EXTRA_SLOTS 6
#define MATERIAL_TEXELS (5 + MATERIAL_EXTRA_SLOTS)
#define MATERIAL_MEDIA_TEXEL (4 + MATERIAL_EXTRA_SLOTS)  // Material.media, which material_media (media.glsl) reads alone
#define MEDIUM_TEXELS 9
#define PHOTON_TEXELS 2
#define TEXTURE_TEXELS 6
#define POINT_LIGHT_TEXELS 3
#define EMITTER_TEXELS 1
// Work-buffer records the kernels read through texel views (kernel.glsl).
// The spectral kernels' paths and shadow rays carry a fourth channel
// (common.glsl's Spectrum) in one more texel.
#define PATH_STATE_TEXELS_RGB 5
#define PATH_STATE_TEXELS_SPECTRAL 6
#define PATH_RADIANCE_TEXEL 3  // radiance and bsdfPdf: the texel connect adds to
#define PATH_MEDIUM_TEXEL 4    // the medium, the way since the last scattering vertex, the wavelengths (FEATURE_MEDIA, FEATURE_SPECTRAL only)
#define PATH_FOURTH_TEXEL 5    // the spectral kernels' throughput.w and radiance.w
#define HIT_TEXELS 1
#define SHADOW_RAY_TEXELS_RGB 3
#define SHADOW_RAY_TEXELS_SPECTRAL 4  // contribution.w in the fourth
#ifdef WP_SPECTRUM4
#define PATH_STATE_TEXELS PATH_STATE_TEXELS_SPECTRAL
#define SHADOW_RAY_TEXELS SHADOW_RAY_TEXELS_SPECTRAL
#else
#define PATH_STATE_TEXELS PATH_STATE_TEXELS_RGB
#define SHADOW_RAY_TEXELS SHADOW_RAY_TEXELS_RGB
#endif

// Triangle.material: the material's index in the low bits; above them, what
// the traversal must know before it takes a hit.
#define TRIANGLE_MATERIAL_MASK 0x3fffffffu
#define TRIANGLE_ONE_SIDED 0x40000000u  // its back side is not there: rays pass through it (glTF's doubleSided false)
#define TRIANGLE_CUTOUT 0x80000000u     // its material's alpha cuts it out where below the cutoff (glTF's alphaMode)

// A primitive record in BVH leaf order, 48 bytes: a triangle in world space
// (in its mesh's space below an instance), a sphere's placeholder (material
// == WP_INVALID, `shading` = its index in the sphere array) or an instance's
// (material == PRIM_INSTANCE, `shading` = its index in the instance array,
// v0 and v1 the lower and upper corners of its world box), so leaves of both
// BVH layouts hold one kind of record.
struct Triangle {
  vec3 v0;
  uint material;  // its material | TRIANGLE_* flags; WP_INVALID: sphere `shading`; PRIM_INSTANCE: instance `shading`
  vec3 v1;
  uint emitter;  // index into the emitter table, or WP_INVALID
  vec3 v2;
  uint shading;  // index into triangleShading, or WP_INVALID: flat normal, barycentric UVs
};

// TriangleShading.flags bits.
#define SHADING_NORMALS 1u      // n0..n2 hold vertex normals (else the normal is flat)
#define SHADING_VERTEX_DATA 2u  // the TriangleVertexData of the same index holds the triangle's

// Per-vertex shading normals and UVs of a triangle that has them. 64 bytes;
// only triangles with such data get one, so plain meshes pay nothing.
struct TriangleShading {
  vec3 n0;  // unit vertex normals in world space (with SHADING_NORMALS)
  float u0;
  vec3 n1;
  float v0;
  vec3 n2;
  uint flags;  // SHADING_*
  vec4 uv12;  // (u1, v1, u2, v2)
};

// What glTF meshes carry beyond normals and UVs, per vertex: tangents for
// normal maps, colours, a second UV set. 128 bytes, in an array parallel to
// the TriangleShading records (the one of the same index), which only scenes
// that have such data fill (FEATURE_VERTEX_DATA).
struct TriangleVertexData {
  vec4 tangent0;  // xyz: unit tangent along increasing u, world space (zero: derive it from the UVs); w: +-1, the bitangent's handedness
  vec4 tangent1;
  vec4 tangent2;
  vec4 color0;  // linear RGBA
  vec4 color1;
  vec4 color2;
  vec4 uv1_01;  // the second UV set: (u0, v0, u1, v1)
  vec4 uv1_2;   // (u2, v2, 0, 0)
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
  uint pad;
};

// An instance: a mesh's own BVH (a bottom-level tree, built once however
// many instances place it) placed by an affine transform, whose two
// directions are stored as Sphere's are. A walk meeting an instance's
// placeholder takes the ray into the mesh's space and walks its tree
// (traverse_*.glsl); the hit's surface is taken back to world space
// (surfaces.glsl). 112 bytes.
struct Instance {
  vec4 toWorld0;
  vec4 toWorld1;
  vec4 toWorld2;
  vec4 toObject0;
  vec4 toObject1;
  vec4 toObject2;
  uint root;   // its mesh's root node (in the node array of the scene's layout)
  uint flags;  // INSTANCE_*
  uint mesh;   // its mesh, as compile_scene numbers them
  uint pad;
};
// Instance.flags: the transform mirrors (negative determinant); surface_at
// then takes the placed corners in the other order, so that the mesh's front
// stays the front (glTF's rule).
#define INSTANCE_MIRRORED 1u

// A material. Colours are textures (a constant colour is a constant texture),
// so every colour parameter may vary over the surface.
struct Material {
  uvec4 info;      // x: MAT_* type, y: albedo texture, z: emission texture (WP_INVALID: none),
                   // w: blend amount texture / metal-rough metallic-roughness texture (WP_INVALID: none)
  uvec4 children;  // blend: x material a, y material b; other kinds: x the alpha cutoff of a cut-out (float bits;
                   // negative: stochastic), y metal-rough's transmission texture (WP_INVALID: none);
                   // z: normal map (an image texture, WP_INVALID: none);
                   // w: its sort key, shade class + 1 (SORT_KEYS; compile_scene)
  vec4 params;     // the kind's parameters, as kinds.glsl lists them
  vec4 params2;
  vec4 extra[MATERIAL_EXTRA_SLOTS];  // more of the kind's parameters, as its materials/ file lays them out (metal-rough's
                                     // extensions: MR_* slots, kinds.glsl); a texture's index as uint bits. Zero in
                                     // kinds that use none; the kernels fetch a slot only where a feature reads it
  uvec4 media;         // FEATURE_MEDIA: x the medium behind the surface (against its normal), y the one in front
                       // (indices into the media, 0 the vacuum); WP_INVALID where the surface bounds no medium, so a
                       // ray crossing it stays in its medium. zw: unused
};

// A participating medium (media.glsl), 144 bytes. Coefficients are per unit
// length of the scene; the null coefficient is that of fictitious particles
// (darts' "real fraction" below 1), which neither absorb nor scatter but
// make the tracking estimators take null collisions. A grid medium
// (MEDIUM_NANOVDB) scales its coefficients by the density its NanoVDB grid
// holds at each point, and bounds them by a coarse grid of majorants: the
// largest density in each cell, over the grid's box in index space.
struct Medium {
  uvec4 info;      // x: MEDIUM_* kind. Grid: y the grid's first byte in the volume words (BINDING_VOLUMES), z its
                   // majorant grid's first word, w the majorant grid's cells along x, y, z (10 bits each)
  vec4 sigmaA;     // xyz: absorption coefficient (grid: per unit density); w: the Henyey-Greenstein asymmetry g (0: isotropic)
  vec4 sigmaS;     // xyz: scattering coefficient (grid: per unit density); w: homogeneous: the majorant, one for all
                   // channels, at least sigmaA + sigmaS + sigmaN in each; grid: the largest of sigmaA + sigmaS
  vec4 sigmaN;     // xyz: null coefficient (homogeneous only); w: unused
  vec4 toIndex0;   // grid: the affine map from the scene to the grid's index space (rows; darts' "transform",
  vec4 toIndex1;   // then the grid's own map, both inverted)
  vec4 toIndex2;
  vec4 boundsLo;   // grid: xyz the index-space box outside which the density is 0 (the active voxels' box grown by
  vec4 boundsHi;   // one voxel: trilinear lookups reach that far); w unused
};

// A texture; checker textures refer to two other textures. 96 bytes.
struct Texture {
  uvec4 info;   // x: TEX_* type | TEX_SOLID | TEX_UV1 | wrap modes; checker: y even, z odd; image: y first texel, z width, w height
  vec4 color0;  // constant colour; marble base; image factor (a normal map's: its scale, scale, 1); fresnel: x ior.
                // w: scale (checker, marble), alpha (constant, image: times the image's)
  vec4 color1;  // marble veins
  vec4 map0;    // 3x4 mapping transform (rows), applied to the lookup point
  vec4 map1;
  vec4 map2;
};

// A punctual light (a CS184 point light, glTF's KHR_lights_punctual): a
// point that radiates its intensity in every direction, a spot that radiates
// it within a cone (full up to the inner cone, falling off to zero at the
// outer one, as the glTF extension defines), or a direction from which
// parallel light of an irradiance arrives. 48 bytes.
//
// Every field a kind reads is stored where the kind alone decides its
// meaning: the kernels load `direction` only where a kind that reads it is
// compiled (LIGHTS_READING_DIRECTION), so nothing a point light needs may
// live there.
struct PointLight {
  vec4 position;   // xyz: where it is (point, spot); w: its light kind (LIGHT_POINT, _SPOT, _DIRECTIONAL, _HEMISPHERE)
  vec4 intensity;  // rgb: W/sr (point, spot), W/m^2 across the direction (directional), radiance (hemisphere);
                   // w: cos of a spot's inner cone; a point light's falloff: 1 inverse-square, 0 none (CS184's)
  vec4 direction;  // xyz: the unit direction it shines in (spot, directional), the zenith (hemisphere);
                   // w: cos of a spot's outer cone
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
  vec4 camLens;      // x: tan(vfov/2), or minus the half-height an orthographic camera sees; y: aspect w/h,
                     // z: lens radius, w: focus distance
  vec4 background;   // rgb radiance of escaped rays
  uvec4 image;       // x: width, y: height, z: max bounces, w: Russian roulette start depth
  uvec4 counts;      // x: emitter count, y: seed, z: traversal step cap, w: SCENE_FLAG_*
  uvec4 mode;        // x: INTEGRATOR_*, y: SAMPLER_*, z: samples per pixel (cmj strata), w: light samples per vertex
  uvec4 environment; // x: texture of the environment map (WP_INVALID: constant background), y: emitter index or WP_INVALID, z: width, w: height of its sampling grid
  uvec4 accel;       // x: BVH_LAYOUT_*, y: WIDE_ORDER_*, z: traversal stack slots needed, w: WALK_* bits
  // The kinds the scene uses (kinds.glsl), one bit per kind id: x material
  // kinds, y texture kinds, z light kinds, w other features. The kernels get
  // them as specialization constants and compile out the code of the rest.
  uvec4 kinds;
  vec4 mis;          // x: exponent of the MIS heuristic (darts' "power": 2 the power heuristic, 1 the balance heuristic)
  vec4 camWindow;    // the part of the camera's frame the image covers: its top-left corner and size, as
                     // fractions of the frame ((0, 0, 1, 1): all of it; CS184's -p renders a cell)
  uvec4 media;       // x: the medium the camera sits in (FEATURE_MEDIA; 0 the vacuum); y: the spectral mode's
                     // colour memo's slots (spectral.glsl; a power of two, 0: none), zw: unused
  uvec4 photons;     // INTEGRATOR_PHOTONS: x photons in the map, y the search count (0: every photon within the
                     // search radius), z the search radius squared (float bits), w unused
};

// A photon of the photon map (photons.glsl), 32 bytes. The map is an
// implicit balanced kd-tree: the node of index range [lo, hi) is photon
// (lo + hi) / 2, its children the ranges on either side.
struct Photon {
  vec3 position;  // where it landed
  uint axis;      // the axis its node splits (0, 1, 2)
  vec3 power;     // its flux, its share of the lights' power
  uint from;      // the direction it arrived from (pointing back along its way), octahedral, two snorm16
};


// SceneParams.mode.y: how camera samples are placed.
#define SAMPLER_INDEPENDENT 0u
#define SAMPLER_CMJ 1u

// A path in flight. Stored as PATH_STATE_TEXELS texels, field by field
// (kernel.glsl's read_path and write_path): 80 bytes in RGB, of which the
// last 16 are read and written only where the scene has media
// (FEATURE_MEDIA); the spectral kernels' 96 (the fourth wavelength's
// throughput and radiance last).
struct PathState {
  vec3 origin;
  uint pixel;
  vec3 dir;  // unit length
  uint rng;
  Spectrum throughput;
  uint flags;  // bounce depth in the low 16 bits, PATH_* flags above
  Spectrum radiance;
  float bsdfPdf;  // solid-angle pdf of the direction that produced this ray
  uint medium;      // the medium the ray travels in (index into the media; 0 the vacuum)
  float travelled;  // the way from the last scattering vertex to origin: interfaces passed since (media.glsl)
  uint crossings;   // interfaces passed so far (at most MEDIUM_CROSSINGS_MAX)
  float wavelengths;  // the spectral mode's (FEATURE_SPECTRAL): the sample in [0, 1) its wavelengths follow from (path_wavelengths)
};

// Closest hit of a path's current ray. 32 bytes; the hit buffer holds the
// first 16 for every path and, after them, `instance` where the scene has
// instances (kernel.glsl's read_hit / write_hit).
struct Hit {
  float t;
  uint prim;  // WP_INVALID on a miss
  float u;    // barycentrics for triangles
  float v;
  uint instance;  // the instance through which prim was hit, or WP_INVALID: prim is a record of the top level
  uint pad0;
  uint pad1;
  uint pad2;
};

// A next-event-estimation shadow ray; valid when tmax > 0. Stored as
// SHADOW_RAY_TEXELS texels, field by field (kernel.glsl): 48 bytes in RGB,
// 64 in the spectral kernels (contribution.w last). The ray caster's rays
// are the first 32 bytes (origin, tmax, dir, path).
struct ShadowRay {
  vec3 origin;
  float tmax;  // the segment ends at origin + tmax * dir
  vec3 dir;
  uint path;
  Spectrum contribution;  // added to the path's radiance if the segment is unoccluded
  uint media;  // FEATURE_MEDIA: the medium at origin (low 16 bits), and a seed for its tracking (high 16 bits)
};

// Per-pixel accumulator of one batch, 32 bytes: sum in xyz, sample count in
// sum.w, sum of squares in sumSq.xyz, sum of squared illuminance in sumSq.w. Each batch holds few samples, so float
// is exact enough; the host folds batches into double precision.
struct PixelAccum {
  vec4 sum;
  vec4 sumSq;
};

// One sample's AOV channels: x..w of a then of b, in the table's order.
struct AovSample {
  vec4 a;
  vec4 b;
};

// Per-pixel sums of a batch's AovSamples and of their squares, 64 bytes;
// folded into double precision by the host, as PixelAccum is.
struct AovAccum {
  vec4 sumA;
  vec4 sumB;
  vec4 sumSqA;
  vec4 sumSqB;
};

#endif  // WP_TYPES_GLSL
