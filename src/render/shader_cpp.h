// shader_cpp.h — the kernels' shared GLSL, compiled as C++.
//
// Structs land in namespace wp::shader. Functions land in structs: the
// scene-independent ones in ShaderMath, the ones that read scene buffers in
// SceneView, whose members have the names the GLSL buffers have, so `nodes[i]`
// means the same thing in both languages. The CPU reference renderer
// and the tests call exactly the code the GPU runs.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>

#include <cmath>
#include <cstddef>

#include "../../shaders/shared/common.glsl"
#include "walk_log.h"

namespace wp::shader {
// GLSL built-ins that GLM lacks for scalars.
inline bool isnan(float x) { return std::isnan(x); }
inline bool isinf(float x) { return std::isinf(x); }
// The kernels' texel buffers are, on the host, the arrays they were made
// from: RGBA32UI records as uvec4, RG32UI image texels as uvec2, the R32F
// environment CDF as float. texelFetch reads them as GLSL does.
inline glm::uvec4 texelFetch(const glm::uvec4* texels, int i) { return texels[i]; }
inline glm::uvec4 texelFetch(const glm::uvec2* texels, int i) { return glm::uvec4(texels[i].x, texels[i].y, 0u, 1u); }
inline glm::vec4 texelFetch(const float* texels, int i) { return glm::vec4(texels[i], 0.0f, 0.0f, 1.0f); }

#include "../../shaders/shared/types.glsl"
#include "../../shaders/shared/bindings.glsl"

// The CPU takes the real branches only; compiling out the kinds a scene
// lacks is the kernels' optimization (kernel.glsl), so here every kind and
// feature counts as present.
#define MATERIAL_KINDS_OF_SCENE ALL_KINDS
#define TEXTURE_KINDS_OF_SCENE ALL_KINDS
#define LIGHT_KINDS_OF_SCENE ALL_KINDS
#define FEATURES_OF_SCENE ALL_KINDS

// NanoVDB's PNanoVDB.h in C, whose buffer SceneView::volume_buf() gives.
#include "../../shaders/shared/pnanovdb.glsl"

// The scene-independent functions (RNG, sampling, intersection, BSDFs). They
// are members only so that C++ treats them as inline; they use no state.
struct ShaderMath {
#include "../../shaders/shared/rng.glsl"
#include "../../shaders/shared/sampling.glsl"
#include "../../shaders/shared/noise.glsl"
#include "../../shaders/shared/intersect.glsl"
#include "../../shaders/shared/bsdf.glsl"
};

// Read-only view of an uploaded scene: the same buffers the kernels bind.
struct SceneView : ShaderMath {
  SceneParams scene{};
  // The texel buffers (bindings.glsl), as the kernels see them.
  const uvec4* nodeTexels = nullptr;
  const uvec4* wideNodeTexels = nullptr;
  const uvec4* triangleTexels = nullptr;
  const uvec4* shadingTexels = nullptr;
  const uvec4* vertexDataTexels = nullptr;
  const uvec4* sphereTexels = nullptr;
  const uvec4* instanceTexels = nullptr;
  const uvec4* materialTexels = nullptr;
  const uvec4* emitterTexels = nullptr;
  const uvec4* textureTexels = nullptr;
  const uvec4* pointLightTexels = nullptr;
  const uvec4* mediumTexels = nullptr;
  const uint32_t* volumeWords = nullptr;  // BINDING_VOLUMES
  size_t volumeWordCount = 0;
  pnanovdb_buf_t volume_buf() const { return pnanovdb_buf_t{volumeWords, volumeWordCount}; }
  const uvec4* photonTexels = nullptr;  // BINDING_PHOTONS
  const uvec2* imageTexels = nullptr;
  const float* floatTables = nullptr;

#define INTEGRATOR_OF_SCENE scene.mode.x  // GLSL: specialization constants (kernel.glsl)
#define LIGHT_SAMPLES_OF_SCENE scene.mode.w
#define LIGHT_SAMPLE_SLOTS MAX_LIGHT_SAMPLES
#define BVH_LAYOUT_OF_SCENE scene.accel.x
#define TRAVERSAL_STACK_SIZE BVH_STACK_MAX  // GLSL: sized for the scene's tree
#define TRAVERSAL_STACK_SLOTS scene.accel.z
  // Whether trace_sample records the first hit for AOV layers (GLSL: a
  // specialization constant).
  bool aovs = false;
#define AOVS_OF_SCENE aovs
  // Where set, the walks record the deepest stack they reach: the tests check
  // it against the slots the host sized the kernels' stacks to.
  uint32_t* stackDepthSeen = nullptr;
  void note_stack_depth(uint32_t sp) const {
    if (stackDepthSeen && sp > *stackDepthSeen) *stackDepthSeen = sp;
    if (walkLog) walkLog->stack_depth(sp);
  }
#define WP_NOTE_STACK_DEPTH(sp) note_stack_depth(sp)
  // Where set, the walks count their iterations: the ray-casting benchmark's
  // measure of a tree's quality, which does not move with the machine's speed.
  uint64_t* stepsTaken = nullptr;
  // Where set, the walks log every iteration: its phases and the texels and
  // stack entries it touches (the SIMT model, src/bench/simt_model.h).
  WalkLog* walkLog = nullptr;
  void note_step() const {
    if (stepsTaken) ++*stepsTaken;
    if (walkLog) walkLog->step();
  }
  void note_phase(uint32_t phase) const {
    if (walkLog) walkLog->phase(phase);
  }
  void note_stack(WalkMemory kind, uint32_t entry) const {
    if (walkLog) walkLog->access(kind, entry);
  }
  WalkMemory memory_of(const void* texels) const {
    if (texels == nodeTexels || texels == wideNodeTexels) return WalkMemory::Nodes;
    if (texels == triangleTexels) return WalkMemory::Primitives;
    if (texels == instanceTexels) return WalkMemory::Instances;
    return WalkMemory::Other;
  }
  // The shared code's texelFetch, noting the texel where a walk is logged.
  template <class T>
  auto texelFetch(const T* texels, int i) const {
    if (walkLog) walkLog->access(memory_of(texels), uint32_t(i));
    return ::wp::shader::texelFetch(texels, i);
  }
#define WP_NOTE_STEP() note_step()
#define WP_NOTE_PHASE(phase) note_phase(phase)
#define WP_NOTE_STACK_READ(entry) note_stack(WalkMemory::StackRead, entry)
#define WP_NOTE_STACK_WRITE(entry) note_stack(WalkMemory::StackWrite, entry)
#include "../../shaders/shared/scene.glsl"
#include "../../shaders/shared/integrator.glsl"
#include "../../shaders/shared/probes.glsl"
};

// Host-side layout checks; tests/test_layout.cpp checks the GLSL side.
static_assert(sizeof(BvhNode) == 16 * BVH_NODE_TEXELS && sizeof(WideNode) == 16 * WIDE_NODE_TEXELS &&
              sizeof(Triangle) == 16 * TRIANGLE_TEXELS && sizeof(TriangleShading) == 16 * TRIANGLE_SHADING_TEXELS &&
              sizeof(TriangleVertexData) == 16 * TRIANGLE_VERTEX_DATA_TEXELS &&
              sizeof(Sphere) == 16 * SPHERE_TEXELS && sizeof(Material) == 16 * MATERIAL_TEXELS &&
              sizeof(Texture) == 16 * TEXTURE_TEXELS && sizeof(PointLight) == 16 * POINT_LIGHT_TEXELS &&
              sizeof(Emitter) == 16 * EMITTER_TEXELS && sizeof(Medium) == 16 * MEDIUM_TEXELS && sizeof(Photon) == 16 * PHOTON_TEXELS && sizeof(PathState) == 16 * PATH_STATE_TEXELS &&
              sizeof(Instance) == 16 * INSTANCE_TEXELS && sizeof(Hit) == 32 && sizeof(ShadowRay) == 16 * SHADOW_RAY_TEXELS);
static_assert(sizeof(BvhNode) == 32 && offsetof(BvhNode, bmax) == 16 && offsetof(BvhNode, count) == 28);
static_assert(sizeof(WideNode) == 80 && offsetof(WideNode, childBase) == 16 && offsetof(WideNode, meta4567) == 28 &&
              offsetof(WideNode, qlo) == 32 && offsetof(WideNode, qhi) == 64);
static_assert(sizeof(Triangle) == 48 && offsetof(Triangle, v2) == 32 && offsetof(Triangle, shading) == 44);
static_assert(sizeof(TriangleShading) == 64 && offsetof(TriangleShading, flags) == 44 && offsetof(TriangleShading, uv12) == 48);
static_assert(sizeof(TriangleVertexData) == 128 && offsetof(TriangleVertexData, color0) == 48 && offsetof(TriangleVertexData, uv1_2) == 112);
static_assert(sizeof(Sphere) == 112 && offsetof(Sphere, material) == 96 && offsetof(Sphere, area) == 104);
static_assert(sizeof(Instance) == 112 && offsetof(Instance, root) == 96 && offsetof(Instance, mesh) == 104);
static_assert(sizeof(Material) == 144 && offsetof(Material, children) == 16 && offsetof(Material, params) == 32 &&
              offsetof(Material, params2) == 48 && offsetof(Material, moreTextures) == 64 && offsetof(Material, volume) == 80 &&
              offsetof(Material, iridescence) == 96 && offsetof(Material, anisotropy) == 112 && offsetof(Material, media) == 128);
static_assert(sizeof(Medium) == 144 && offsetof(Medium, sigmaA) == 16 && offsetof(Medium, sigmaN) == 48 &&
              offsetof(Medium, toIndex0) == 64 && offsetof(Medium, boundsHi) == 128);
static_assert(sizeof(Texture) == 96 && offsetof(Texture, color1) == 32 && offsetof(Texture, map2) == 80);
static_assert(sizeof(PointLight) == 48 && offsetof(PointLight, intensity) == 16 && offsetof(PointLight, direction) == 32);
static_assert(sizeof(Emitter) == 16 && offsetof(Emitter, pmf) == 12);
static_assert(sizeof(Photon) == 32 && offsetof(Photon, power) == 16 && offsetof(Photon, from) == 28);
static_assert(sizeof(SceneParams) == 240 && offsetof(SceneParams, mode) == 112 && offsetof(SceneParams, environment) == 128 &&
              offsetof(SceneParams, accel) == 144 && offsetof(SceneParams, kinds) == 160 && offsetof(SceneParams, mis) == 176 &&
              offsetof(SceneParams, camWindow) == 192 && offsetof(SceneParams, media) == 208 &&
              offsetof(SceneParams, photons) == 224);
static_assert(sizeof(PathState) == 80 && offsetof(PathState, radiance) == 48 && offsetof(PathState, bsdfPdf) == 60 &&
              offsetof(PathState, medium) == 64 && offsetof(PathState, crossings) == 72);
static_assert(sizeof(Hit) == 32 && offsetof(Hit, instance) == 16);
// write_shadow_ray and read_shadow_ray (kernel.glsl) move shadow rays as three
// texels: origin and tmax, dir and path, contribution and media.
static_assert(sizeof(ShadowRay) == 48 && offsetof(ShadowRay, tmax) == 12 && offsetof(ShadowRay, dir) == 16 &&
              offsetof(ShadowRay, path) == 28 && offsetof(ShadowRay, contribution) == 32 && offsetof(ShadowRay, media) == 44);
static_assert(sizeof(PixelAccum) == 32);
static_assert(sizeof(AovSample) == 4 * AOV_CHANNELS && sizeof(AovAccum) == 8 * AOV_CHANNELS);
static_assert(sizeof(KernelPush) == 48);
}  // namespace wp::shader
