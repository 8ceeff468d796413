// bindings.glsl — the one descriptor set every kernel uses, and the push
// constants. The binding numbers are shared with the host (src/gpu/wavefront.cpp
// binds buffers by these names); the buffer declarations are GLSL only.
#ifndef WP_BINDINGS_GLSL
#define WP_BINDINGS_GLSL

#define BINDING_SCENE 0
#define BINDING_NODES 1
#define BINDING_TRIANGLES 2
#define BINDING_SPHERES 3
#define BINDING_MATERIALS 4
#define BINDING_EMITTERS 5
#define BINDING_PATHS 6
#define BINDING_HITS 7
#define BINDING_QUEUES 8
#define BINDING_SHADOW_RAYS 9
#define BINDING_COUNTERS 10
#define BINDING_INDIRECT 11
#define BINDING_ACCUM 12
#define BINDING_TEXTURES 13
#define BINDING_TEXELS 14
#define BINDING_TRIANGLE_SHADING 15
#define BINDING_POINT_LIGHTS 16
#define BINDING_FLOAT_TABLES 17
#define BINDING_PIXEL_LIST 18
#define BINDING_WIDE_NODES 19
#define BINDING_SORT 20
// Texel-buffer views of work buffers, for reading them (kernel.glsl).
#define BINDING_PATH_TEXELS 21
#define BINDING_HIT_TEXELS 22
#define BINDING_SHADOW_RAY_TEXELS 23
#define BINDING_QUEUE_TEXELS 24  // the queues, R32UI
// AOV layers: each path's first-hit record, and the per-pixel sums.
#define BINDING_AOV_SAMPLES 25
#define BINDING_AOV_ACCUM 26
#define BINDING_VERTEX_DATA 27
#define BINDING_MEDIA 28
#define BINDING_VOLUMES 29  // grid media's NanoVDB grids and majorant grids, R32UI words (pnanovdb.glsl)
#define BINDING_PHOTONS 30  // the photon map (INTEGRATOR_PHOTONS), RGBA32UI texels
#define BINDING_INSTANCES 31  // instances of meshes (FEATURE_INSTANCES)
#define BINDING_SPECTRA 32    // the spectral mode's tables (FEATURE_SPECTRAL; spectral.glsl), RGBA32F texels
#define BINDING_SPECTRAL_COLOURS 33  // the scene's constant colours' uplift coefficients (spectral.glsl), RGBA32F texels
// The walks' records again, as storage buffers over the same memory
// (walk_node_texel and its kin below; variants *-loads).
#define BINDING_NODE_WORDS 34
#define BINDING_WIDE_NODE_WORDS 35
#define BINDING_TRIANGLE_WORDS 36
#define BINDING_COUNT 37

// Where each table starts in the float tables (BINDING_FLOAT_TABLES).
#include "sheen_albedo.glsl"
#define FLOAT_TABLE_SHEEN 0
#define FLOAT_TABLE_ENVIRONMENT (SHEEN_TABLE_SIZE * SHEEN_TABLE_SIZE)

// Specialization constants of the kernels, by id: kernel.glsl declares them
// (SPEC_ANY_HIT in raycast.comp, SPEC_SHADE_KEY in shade.comp, SPEC_MEGAKERNEL_SAMPLES in megakernel.comp), and the host
// sets each by the same name (src/gpu/wavefront.cpp, make_pipeline).
#define SPEC_WORKGROUP_SIZE 0
#define SPEC_INTEGRATOR 1
#define SPEC_LIGHT_SAMPLES 2
#define SPEC_BVH_LAYOUT 3
#define SPEC_FEATURES 4
#define SPEC_STACK_SIZE 5
#define SPEC_COMPACTION 6
#define SPEC_SORT_BY_MATERIAL 7
#define SPEC_RAYS_PER_INVOCATION 8
#define SPEC_WORKGROUP_INTERLEAVE 9
#define SPEC_ANY_HIT 10
#define SPEC_SHADE_KEY 11
#define SPEC_MATERIAL_KINDS 12
#define SPEC_TEXTURE_KINDS 13
#define SPEC_LIGHT_KINDS 14
#define SPEC_AOVS 15
#define SPEC_WIDE_CHILD_ORDER 16
#define SPEC_ROOT_AT_ENTRY 17
#define SPEC_TRACING_FILL 18
#define SPEC_WALK_LOADS 19
#define SPEC_BINARY_FUSED 20
#define SPEC_MEGAKERNEL_SAMPLES 21
#define SPEC_DYNAMIC_FETCH 22
#define SPEC_COUNT 23

// Default workgroup size. Kernel variants set another through specialization
// constant 0 (see kernel.glsl and src/gpu/wavefront.cpp).
#define WORKGROUP_SIZE 64

// Push constants of every kernel. Queues live in one buffer: queue q occupies
// [q * capacity, (q + 1) * capacity); queues 0 and 1 alternate between
// bounces; sorting by material class, queue QUEUE_SORTED + k holds a
// bounce's paths of sort key k.
struct KernelPush {
  uint waveStart;   // first pixel of this wave
  uint pathCount;   // paths in this wave
  uint sampleIndex; // sample number of every path of this wave
  uint queueIn;     // 0 or 1: the queue of paths to extend / shade
  uint capacity;    // path slots per queue
  uint phase;       // prepare kernel: PREPARE_*; generate kernel: GENERATE_*
  uint photonSeed;  // photons kernel: the photon map's seed
  uint accumBase;   // the first pixel of the tile the accumulators hold (accumulate_path)
  uint waveSpan;    // pixels a sample of this wave covers: path i renders pixel i % waveSpan of the wave's, sample
                    // sampleIndex + i / waveSpan (a small image takes several samples a wave)
  uint pad0;
  uint pad1;
  uint pad2;
};

#define PREPARE_EXTEND 0u
#define PREPARE_CONNECT 1u
#define PREPARE_SORT 2u
// Generate kernel: path i renders pixel waveStart + i % waveSpan, or
// (adaptive sampling) pixel pixelList[waveStart + i % waveSpan].
#define GENERATE_CONSECUTIVE 0u
#define GENERATE_FROM_LIST 1u
// Photons kernel: start the batch's photons, or take each a bounce further.
#define PHOTONS_EMIT 0u
#define PHOTONS_BOUNCE 1u

#ifndef __cplusplus
layout(std140, set = 0, binding = BINDING_SCENE) uniform SceneBlock { SceneParams scene; };
// Everything the scene holds is read through uniform texel buffers: records
// as RGBA32UI texels, decoded by scene.glsl's load_* functions. On lavapipe a
// texel fetch compiles to plain loads, while a storage-buffer load at a
// per-lane address becomes a loop with a branch and a bounds check per lane:
// traversal ran twice as fast this way. Texel buffers also reach 2 GiB (128M
// texels), where lavapipe's storage buffers stop at 128 MiB.
layout(set = 0, binding = BINDING_NODES) uniform usamplerBuffer nodeTexels;
layout(set = 0, binding = BINDING_WIDE_NODES) uniform usamplerBuffer wideNodeTexels;
layout(set = 0, binding = BINDING_TRIANGLES) uniform usamplerBuffer triangleTexels;
layout(set = 0, binding = BINDING_TRIANGLE_SHADING) uniform usamplerBuffer shadingTexels;
layout(set = 0, binding = BINDING_VERTEX_DATA) uniform usamplerBuffer vertexDataTexels;
layout(set = 0, binding = BINDING_SPHERES) uniform usamplerBuffer sphereTexels;
layout(set = 0, binding = BINDING_INSTANCES) uniform usamplerBuffer instanceTexels;
layout(set = 0, binding = BINDING_MATERIALS) uniform usamplerBuffer materialTexels;
layout(set = 0, binding = BINDING_EMITTERS) uniform usamplerBuffer emitterTexels;
layout(set = 0, binding = BINDING_TEXTURES) uniform usamplerBuffer textureTexels;
layout(set = 0, binding = BINDING_POINT_LIGHTS) uniform usamplerBuffer pointLightTexels;
layout(set = 0, binding = BINDING_MEDIA) uniform usamplerBuffer mediumTexels;
layout(set = 0, binding = BINDING_VOLUMES) uniform usamplerBuffer volumeWords;
layout(set = 0, binding = BINDING_PHOTONS) uniform usamplerBuffer photonTexels;
// On a GPU a storage-buffer load takes the load path rather than the texture
// unit's: the variants *-loads (SPEC_WALK_LOADS) read the walks' nodes and
// primitives that way (walk_*_texel below), from views of the same
// buffers, within the device's storage-buffer range.
layout(constant_id = SPEC_WALK_LOADS) const bool kWalkLoads = false;
layout(std430, set = 0, binding = BINDING_NODE_WORDS) restrict readonly buffer NodeWords { uvec4 nodeWords[]; };
layout(std430, set = 0, binding = BINDING_WIDE_NODE_WORDS) restrict readonly buffer WideNodeWords { uvec4 wideNodeWords[]; };
layout(std430, set = 0, binding = BINDING_TRIANGLE_WORDS) restrict readonly buffer TriangleWords { uvec4 triangleWords[]; };
// One function a buffer, with a branch: the host's specialization removes a
// branch on a constant, whereas a ternary becomes a select, whose unused
// storage load lavapipe would still run in every other variant.
uvec4 walk_node_texel(int at) {
  if (kWalkLoads) return nodeWords[at];
  return texelFetch(nodeTexels, at);
}
uvec4 walk_wide_node_texel(int at) {
  if (kWalkLoads) return wideNodeWords[at];
  return texelFetch(wideNodeTexels, at);
}
uvec4 walk_triangle_texel(int at) {
  if (kWalkLoads) return triangleWords[at];
  return texelFetch(triangleTexels, at);
}
// Image texels, RG32UI: RGBA half floats (linear), all images back to back
// (lavapipe has no descriptor indexing, so one buffer holds every image).
layout(set = 0, binding = BINDING_TEXELS) uniform usamplerBuffer imageTexels;
// Tables of floats, R32F: the sheen's albedo table (sheen_albedo.glsl) from
// FLOAT_TABLE_SHEEN, then from FLOAT_TABLE_ENVIRONMENT the environment map's
// sampling distribution: the CDF over rows (height + 1 values), then one CDF
// over the columns of each row (width + 1 values each).
layout(set = 0, binding = BINDING_FLOAT_TABLES) uniform samplerBuffer floatTables;
// The spectral mode's tables, RGBA32F (spectral.glsl lays them out): the
// film's white balance, D65, the RGB uplift's coefficients, the metals'
// indices. One placeholder texel where the render is in RGB.
layout(set = 0, binding = BINDING_SPECTRA) uniform samplerBuffer spectrumTexels;
// The scene's constant colours with their uplift coefficients, looked up
// once on the host (spectral.glsl's spectral_colour_memo), RGBA32F.
layout(set = 0, binding = BINDING_SPECTRAL_COLOURS) uniform samplerBuffer spectralColourTexels;
// Work buffers, written by the kernels. Paths, hits and shadow rays are also
// read through texel-buffer views of the same memory (read_path, read_hit,
// read_shadow_ray in kernel.glsl): on lavapipe a storage-buffer read at a
// per-lane address is a loop over the lanes, a texel fetch a few vector
// loads. An invocation reads a record through the view only before any
// dispatch writes it again, or before it writes it itself.
layout(set = 0, binding = BINDING_PATH_TEXELS) uniform usamplerBuffer pathTexels;
layout(set = 0, binding = BINDING_HIT_TEXELS) uniform usamplerBuffer hitTexels;
layout(set = 0, binding = BINDING_SHADOW_RAY_TEXELS) uniform usamplerBuffer shadowRayTexels;
layout(set = 0, binding = BINDING_QUEUE_TEXELS) uniform usamplerBuffer queueTexels;
// Paths, hits and shadow rays are written as whole 16-byte texels
// (write_path, write_hit, write_shadow_ray in kernel.glsl): lavapipe stores
// to a per-lane address in a loop over the lanes, one loop per store, so one
// 16-byte store beats a store per field. Only connect_multi sees paths as
// floats, for its float atomics on the radiance.
#ifdef WP_PATH_RADIANCE_ATOMICS
layout(std430, set = 0, binding = BINDING_PATHS) buffer PathBuffer { float pathFloats[]; };
#else
layout(std430, set = 0, binding = BINDING_PATHS) buffer PathBuffer { uvec4 pathTexelsOut[]; };
#endif
layout(std430, set = 0, binding = BINDING_HITS) writeonly buffer HitBuffer { uvec4 hitRecords[]; };
layout(std430, set = 0, binding = BINDING_QUEUES) buffer QueueBuffer { uint queues[]; };
layout(std430, set = 0, binding = BINDING_SHADOW_RAYS) buffer ShadowBuffer { uvec4 shadowRayTexelsOut[]; };
layout(std430, set = 0, binding = BINDING_COUNTERS) buffer CounterBuffer { uint counters[]; };
layout(std430, set = 0, binding = BINDING_INDIRECT) buffer IndirectBuffer { uint indirect[]; };
layout(std430, set = 0, binding = BINDING_ACCUM) buffer AccumBuffer { PixelAccum accum[]; };
layout(std430, set = 0, binding = BINDING_AOV_SAMPLES) buffer AovSampleBuffer { AovSample aovSamples[]; };
layout(std430, set = 0, binding = BINDING_AOV_ACCUM) buffer AovAccumBuffer { AovAccum aovAccum[]; };
// Sorting by material class (kSortByMaterial): per sort key, the paths in
// its queue (QUEUE_SORTED + key).
layout(std430, set = 0, binding = BINDING_SORT) buffer SortBuffer { uint sortBins[SORT_KEYS]; };
// The pixels still sampled under adaptive sampling.
layout(std430, set = 0, binding = BINDING_PIXEL_LIST) readonly buffer PixelListBuffer { uint pixelList[]; };
layout(push_constant) uniform PushBlock { KernelPush pc; };
#endif

#endif  // WP_BINDINGS_GLSL
