// kernel.glsl — prelude of every compute kernel: the shared headers in order.
#include "common.glsl"
#include "types.glsl"

#include "bindings.glsl"

// Specialization constants (ids in bindings.glsl, shared with the host): the
// host sets them from the scene and the kernel variant when it builds the
// pipelines, and the compiler drops the code they rule out, which on lavapipe
// costs time even when never taken.
// The integrator (INTEGRATOR_*); C++ reads it from the scene (integrator.glsl:
// INTEGRATOR_OF_SCENE).
layout(constant_id = SPEC_INTEGRATOR) const uint kIntegrator = INTEGRATOR_PATH;
#define INTEGRATOR_OF_SCENE kIntegrator
// Light samples per vertex (scene.mode.w), so the usual single sample
// compiles to straight-line code.
layout(constant_id = SPEC_LIGHT_SAMPLES) const uint kLightSamples = 1u;
#define LIGHT_SAMPLES_OF_SCENE kLightSamples
// The shadow-ray array of a vertex is sized by it too: one slot, as a rule.
#define LIGHT_SAMPLE_SLOTS kLightSamples
// The BVH layout (scene.accel.x), the kinds the scene uses (scene.kinds,
// kinds.glsl) and the traversal stack size (accel.z): each kernel holds only
// the traversal it runs, only the code of the materials, textures, lights and
// features the scene has, and a stack no larger than the tree needs (the
// wide walk moves every entry of it on a push or a pop: traverse_wide.glsl).
layout(constant_id = SPEC_BVH_LAYOUT) const uint kBvhLayout = BVH_LAYOUT_WIDE;
layout(constant_id = SPEC_WIDE_CHILD_ORDER) const uint kWideChildOrder = WIDE_ORDER_OCTANT;
layout(constant_id = SPEC_ROOT_AT_ENTRY) const bool kRootAtEntry = false;
layout(constant_id = SPEC_BINARY_FUSED) const bool kBinaryFused = false;
layout(constant_id = SPEC_MATERIAL_KINDS) const uint kMaterialKinds = ALL_KINDS;
layout(constant_id = SPEC_TEXTURE_KINDS) const uint kTextureKinds = ALL_KINDS;
layout(constant_id = SPEC_LIGHT_KINDS) const uint kLightKinds = ALL_KINDS;
layout(constant_id = SPEC_FEATURES) const uint kFeatures = ALL_KINDS;
layout(constant_id = SPEC_STACK_SIZE) const uint kStackSize = BVH_STACK_MAX;
#define BVH_LAYOUT_OF_SCENE kBvhLayout
#define WIDE_CHILD_ORDER_OF_SCENE kWideChildOrder
#define ROOT_AT_ENTRY_OF_SCENE kRootAtEntry
#define BINARY_FUSED_OF_SCENE kBinaryFused
#define MATERIAL_KINDS_OF_SCENE kMaterialKinds
#define TEXTURE_KINDS_OF_SCENE kTextureKinds
#define LIGHT_KINDS_OF_SCENE kLightKinds
#define FEATURES_OF_SCENE kFeatures
#define TRAVERSAL_STACK_SIZE kStackSize
#define TRAVERSAL_STACK_SLOTS kStackSize
#define WP_NOTE_STACK_DEPTH(sp)  // C++ only: the tests check the stack's size
#define WP_NOTE_STEP()  // C++ only: the ray-casting benchmark counts the walks' iterations
#define WP_WAVELENGTH_SAMPLE(u) (u)  // C++ only: tests confine the wavelengths to a band
#define WP_SPECTRAL_COLOUR_UNLISTED(rgb, kind)  // C++ only: the CPU reference checks the host's memo
// C++ only: what each iteration of a walk did and which stack entries it
// touched, for the SIMT model of the walks (src/bench/simt_model.h).
#define WP_NOTE_PHASE(phase)
#define WP_NOTE_STACK_READ(entry)
#define WP_NOTE_STACK_WRITE(entry)
// Path compaction: shade appends only the paths still alive to the next
// bounce's queue, so each bounce dispatches only live paths. Without it
// (variant gpu-nocompact, to measure what compaction is worth) every path
// keeps its queue slot and finished ones are marked PATH_DEAD and skipped.
layout(constant_id = SPEC_COMPACTION) const bool kCompaction = true;
// Sorting paths by material class between extend and shade (variant
// gpu-sort): the sort kernel appends each path to its key's queue, prepare
// sizes one shade dispatch per key, and one shade kernel per key reads its
// queue.
layout(constant_id = SPEC_SORT_BY_MATERIAL) const bool kSortByMaterial = false;
// Rays per invocation of the tracing kernels (trace_items.glsl): several on
// CPU devices, whose SIMD lanes would otherwise wait for the slowest ray of
// their group. A constant, not a push constant: a kernel holding both loops
// ran single rays 10 % slower.
layout(constant_id = SPEC_RAYS_PER_INVOCATION) const uint kRaysPerInvocation = 1u;
// Subgroups sharing items take their blocks from a counter (trace_items.glsl).
layout(constant_id = SPEC_DYNAMIC_FETCH) const bool kDynamicFetch = false;
// The fewest invocations such a kernel is dispatched with, rays permitting:
// TRACING_INVOCATIONS_ON_GPUS on GPUs, 0 on CPU devices (TRACING_INVOCATIONS).
layout(constant_id = SPEC_TRACING_FILL) const uint kTracingFill = 0u;
// Workgroup interleave (dispatch_item below): 1, or for kernels that take
// work in image order on CPU devices, the number of columns a dispatch's
// workgroups are dealt to.
layout(constant_id = SPEC_WORKGROUP_INTERLEAVE) const uint kWorkgroupInterleave = 1u;
// AOV layers (layers.glsl): the first hit of each path is recorded
// (aov_sample) and accumulated beside the colour.
layout(constant_id = SPEC_AOVS) const bool kAovs = false;
#define AOVS_OF_SCENE kAovs
#include "colour.glsl"
#include "rng.glsl"
#include "sampling.glsl"
#include "spectrum.glsl"
#include "noise.glsl"
#include "intersect.glsl"
#include "bsdf.glsl"
#include "scene.glsl"
#include "integrator.glsl"

// The workgroup size (WORKGROUP_SIZE unless a kernel variant sets it), so one
// SPIR-V module serves every size.
layout(local_size_x_id = SPEC_WORKGROUP_SIZE) in;
layout(constant_id = SPEC_WORKGROUP_SIZE) const uint kWorkgroupSize = WORKGROUP_SIZE;

// The item of this invocation in a dispatch over `count` items, one to an
// invocation (the tracing kernels' one-ray path, the megakernel; the host
// interleaves the megakernel and the ray caster's camera rays).
// lavapipe deals a dispatch's workgroups out to its threads in one contiguous
// block per thread, and work in image order costs unevenly (the sky is cheap,
// the model is not): one thread then idled while the other traced the costly
// rows. So with kWorkgroupInterleave = T > 1, workgroup w takes the items of
// workgroup (w % R) * T + w / R, for R = ceil(G / T) and G the workgroups the
// items need: the workgroups in rows of T, read by columns, so that each
// thread's block spreads over all the rows. A workgroup's items stay
// consecutive (coherent camera rays stay together). Such dispatches have
// R * T workgroups (the host rounds up); an invocation mapped past the items
// gets an item >= count and takes none. (The wavefront kernels are left in
// queue order: interleaved, shade made renders 5 % slower, its queue reads
// spread out and the queue it appends to scrambled for the next extend, and
// extend and connect 9 % slower on the Cornell box.)
uint dispatch_item(uint count) {
  if (kWorkgroupInterleave == 1u) return gl_GlobalInvocationID.x;
  uint groups = (count + kWorkgroupSize - 1u) / kWorkgroupSize;
  uint rows = (groups + kWorkgroupInterleave - 1u) / kWorkgroupInterleave;
  uvec2 wr = div_mod(gl_WorkGroupID.x, rows);  // workgroup ids are below 2^16
  uint group = wr.y * kWorkgroupInterleave + wr.x;
  return group * kWorkgroupSize + gl_LocalInvocationID.x;
}

// Work-buffer records read through their texel views (bindings.glsl), field
// by field as types.glsl lays them out; fields left unused cost nothing.
// A path's fifth texel (its medium, and its wavelengths) is moved only where
// media or the spectral mode are compiled.
#define PATH_MEDIUM_TEXEL_COMPILED ((FEATURES_OF_SCENE & (KIND_BIT(FEATURE_MEDIA) | KIND_BIT(FEATURE_SPECTRAL))) != 0u)
PathState read_path(uint i) {
  int at = int(i) * PATH_STATE_TEXELS;
  uvec4 a = texelFetch(pathTexels, at);
  uvec4 b = texelFetch(pathTexels, at + 1);
  uvec4 c = texelFetch(pathTexels, at + 2);
  uvec4 d = texelFetch(pathTexels, at + PATH_RADIANCE_TEXEL);
  PathState p;
  p.origin = texel_xyz(a);
  p.pixel = a.w;
  p.dir = texel_xyz(b);
  p.rng = b.w;
  p.flags = c.w;
  p.bsdfPdf = uintBitsToFloat(d.w);
  uvec4 e = PATH_MEDIUM_TEXEL_COMPILED ? texelFetch(pathTexels, at + PATH_MEDIUM_TEXEL) : uvec4(0u);
  p.medium = e.x;
  p.travelled = uintBitsToFloat(e.y);
  p.crossings = e.z;
  p.wavelengths = uintBitsToFloat(e.w);
#ifdef WP_SPECTRUM4
  vec2 f = uintBitsToFloat(texelFetch(pathTexels, at + PATH_FOURTH_TEXEL).xy);
  p.throughput = vec4(texel_xyz(c), f.x);
  p.radiance = vec4(texel_xyz(d), f.y);
#else
  p.throughput = texel_xyz(c);
  p.radiance = texel_xyz(d);
#endif
  return p;
}

Hit read_hit(uint i) {
  uvec4 a = texelFetch(hitTexels, int(i) * HIT_TEXELS);
  Hit h;
  h.t = uintBitsToFloat(a.x);
  h.prim = a.y;
  h.u = uintBitsToFloat(a.z);
  h.v = uintBitsToFloat(a.w);
  h.instance = FEATURE_COMPILED(FEATURE_INSTANCES) ? texelFetch(hitTexels, int(pc.capacity + i)).x : WP_INVALID;
  return h;
}

// Entry i of queue q (read_queue's view is of the queue buffer).
uint read_queue(uint q, uint i) {
  return texelFetch(queueTexels, int(q * pc.capacity + i)).x;
}

// Work-buffer records written as whole texels (bindings.glsl), in the layout
// the read_* functions read.
void write_hit(uint i, Hit h) {
  hitRecords[i * HIT_TEXELS] = uvec4(floatBitsToUint(h.t), h.prim, floatBitsToUint(h.u), floatBitsToUint(h.v));
  // Instances: after the capacity's hits, so that scenes without keep 16 bytes a hit.
  if (FEATURE_COMPILED(FEATURE_INSTANCES)) hitRecords[pc.capacity + i] = uvec4(h.instance, 0u, 0u, 0u);
}

#ifndef WP_PATH_RADIANCE_ATOMICS
void write_path(uint i, PathState p) {
  uint at = i * PATH_STATE_TEXELS;
  pathTexelsOut[at] = uvec4(floatBitsToUint(p.origin), p.pixel);
  pathTexelsOut[at + 1u] = uvec4(floatBitsToUint(p.dir), p.rng);
  pathTexelsOut[at + 2u] = uvec4(floatBitsToUint(spectrum_xyz(p.throughput)), p.flags);
  pathTexelsOut[at + uint(PATH_RADIANCE_TEXEL)] = uvec4(floatBitsToUint(spectrum_xyz(p.radiance)), floatBitsToUint(p.bsdfPdf));
  if (PATH_MEDIUM_TEXEL_COMPILED)
    pathTexelsOut[at + uint(PATH_MEDIUM_TEXEL)] = uvec4(p.medium, floatBitsToUint(p.travelled), p.crossings, floatBitsToUint(p.wavelengths));
#ifdef WP_SPECTRUM4
  pathTexelsOut[at + uint(PATH_FOURTH_TEXEL)] = uvec4(floatBitsToUint(p.throughput.w), floatBitsToUint(p.radiance.w), 0u, 0u);
#endif
}
#endif

void write_shadow_ray(uint i, ShadowRay r) {
  uint at = i * SHADOW_RAY_TEXELS;
  shadowRayTexelsOut[at] = uvec4(floatBitsToUint(r.origin), floatBitsToUint(r.tmax));
  shadowRayTexelsOut[at + 1u] = uvec4(floatBitsToUint(r.dir), r.path);
  shadowRayTexelsOut[at + 2u] = uvec4(floatBitsToUint(spectrum_xyz(r.contribution)), r.media);
#ifdef WP_SPECTRUM4
  shadowRayTexelsOut[at + 3u] = uvec4(floatBitsToUint(r.contribution.w), 0u, 0u, 0u);
#endif
}

// Shadow ray i's contribution alone (connect's read when the ray is unoccluded).
Spectrum shadow_ray_contribution(uint i) {
  int at = int(i) * SHADOW_RAY_TEXELS;
  vec3 c = texel_xyz(texelFetch(shadowRayTexels, at + 2));
#ifdef WP_SPECTRUM4
  return vec4(c, uintBitsToFloat(texelFetch(shadowRayTexels, at + 3).x));
#else
  return c;
#endif
}

ShadowRay read_shadow_ray(uint i) {
  int at = int(i) * SHADOW_RAY_TEXELS;
  uvec4 a = texelFetch(shadowRayTexels, at);
  uvec4 b = texelFetch(shadowRayTexels, at + 1);
  uvec4 c = texelFetch(shadowRayTexels, at + 2);
  ShadowRay r;
  r.origin = texel_xyz(a);
  r.tmax = uintBitsToFloat(a.w);
  r.dir = texel_xyz(b);
  r.path = b.w;
#ifdef WP_SPECTRUM4
  r.contribution = vec4(texel_xyz(c), uintBitsToFloat(texelFetch(shadowRayTexels, at + 3).x));
#else
  r.contribution = texel_xyz(c);
#endif
  r.media = c.w;
  return r;
}

// Adds a finished path's radiance (and its square) to its pixel's sums, and
// where the render records AOVs, its first hit's (`aov`); a non-finite
// sample is counted and dropped, never allowed to poison a pixel, and its
// AOVs with it, so that every layer has the same count. A wave holds each
// pixel at most once, so no atomics are needed.
void accumulate_path(PathState p, AovSample aov) {
  vec3 l = sample_rgb(p);
  if (!radiance_is_finite(l)) {
    atomicAdd(counters[COUNTER_NONFINITE], 1u);
    return;
  }
  // The accumulators hold one tile of the image, from pixel pc.accumBase.
  uint at = p.pixel - pc.accumBase;
  PixelAccum s = sample_moments(l);
  PixelAccum a = accum[at];
  a.sum += s.sum;
  a.sumSq += s.sumSq;
  accum[at] = a;
  if (kAovs) {
    AovAccum s2 = aov_moments(aov);
    AovAccum b = aovAccum[at];
    b.sumA += s2.sumA;
    b.sumB += s2.sumB;
    b.sumSqA += s2.sumSqA;
    b.sumSqB += s2.sumSqB;
    aovAccum[at] = b;
  }
}

// Adds n to the 64-bit ray count at counters[slot] (low word) and
// counters[slot + 1] (high word): the one add that wraps the low word sees
// its old value within n of the top, and carries.
void count_rays(uint slot, uint n) {
  uint old = atomicAdd(counters[slot], n);
  if (old > 0xffffffffu - n) atomicAdd(counters[slot + 1u], 1u);
}

// The pixel of path i of a wave: consecutive pixels, or those of the adaptive
// sampler's list.
uint wave_pixel(uint i) {
  uint j = i % pc.waveSpan;
  return pc.phase == GENERATE_FROM_LIST ? pixelList[pc.waveStart + j] : pc.waveStart + j;
}

// The sample path i of the wave renders.
uint wave_sample(uint i) {
  return pc.sampleIndex + i / pc.waveSpan;
}

// The queue a path is sorted into (gpu-sort): the sort key of the material its
// ray hit, or SORT_KEY_MISS.
uint sort_key(Hit h) {
  uint m = hit_material(h);
  return m == WP_INVALID ? SORT_KEY_MISS : load_material(m).children.w;
}
