// shader_cpp.h — the kernels' shared GLSL, compiled as C++: the integrator.
//
// Structs land in namespace wp::shader (shader/types.h, which code that only
// builds or moves records includes instead of this). Functions land in structs: the
// scene-independent ones in ShaderMath, the ones that read scene buffers in
// SceneView, whose members have the names the GLSL buffers have, so `nodes[i]`
// means the same thing in both languages. The CPU reference renderer
// and the tests call exactly the code the GPU runs.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>

#include <cmath>
#include <cstddef>
#include <string>

#include "../../shaders/shared/common.glsl"
#include "shader/pnanovdb.h"
#include "shader/types.h"
#include "util/error.h"
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
inline glm::vec4 texelFetch(const glm::vec4* texels, int i) { return texels[i]; }
// The kernels' choice of a texel fetch or a storage-buffer load
// (bindings.glsl); the host has the texels.
#define walk_node_texel(at) texelFetch(nodeTexels, at)
#define walk_wide_node_texel(at) texelFetch(wideNodeTexels, at)
#define walk_triangle_texel(at) texelFetch(triangleTexels, at)

// The CPU takes the real branches only; compiling out the kinds a scene
// lacks is the kernels' optimization (kernel.glsl), so here every kind and
// feature counts as present.
#define MATERIAL_KINDS_OF_SCENE ALL_KINDS
#define TEXTURE_KINDS_OF_SCENE ALL_KINDS
#define LIGHT_KINDS_OF_SCENE ALL_KINDS
#define FEATURES_OF_SCENE ALL_KINDS

// The scene-independent functions (RNG, sampling, intersection, BSDFs). They
// are members only so that C++ treats them as inline; they use no state.
struct ShaderMath {
  // The channels of a Spectrum (colour.glsl) that count: C++ compiles one
  // vec4 for both modes, whose w only the spectral mode uses (SceneView sets
  // 4 for a spectral scene; the kernels have it as a constant).
  uint spectrumChannels = 3u;
#define SPECTRUM_CHANNELS spectrumChannels
#include "../../shaders/shared/colour.glsl"
#include "../../shaders/shared/rng.glsl"
#include "../../shaders/shared/sampling.glsl"
#include "../../shaders/shared/spectrum.glsl"
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
  const vec4* spectrumTexels = nullptr;  // BINDING_SPECTRA (spectral.glsl)
  const vec4* spectralColourTexels = nullptr;  // BINDING_SPECTRAL_COLOURS

#define INTEGRATOR_OF_SCENE scene.mode.x  // GLSL: specialization constants (kernel.glsl)
#define LIGHT_SAMPLES_OF_SCENE scene.mode.w
#define LIGHT_SAMPLE_SLOTS MAX_LIGHT_SAMPLES
#define BVH_LAYOUT_OF_SCENE scene.accel.x
#define WIDE_CHILD_ORDER_OF_SCENE scene.accel.y
#define ROOT_AT_ENTRY_OF_SCENE ((scene.accel.w & WALK_ROOT_AT_ENTRY) != 0u)
#define BINARY_FUSED_OF_SCENE ((scene.accel.w & WALK_BINARY_FUSED) != 0u)
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
  // Where set below [0, 1), the spectral mode's wavelength samples (the
  // hero's; path_wavelengths) lie in this band of the unit interval: the
  // tests check the integrator band by band.
  glm::vec2 wavelengthBand{0.0f, 1.0f};
  float wavelength_sample(float u) const { return wavelengthBand.x + u * (wavelengthBand.y - wavelengthBand.x); }
#define WP_WAVELENGTH_SAMPLE(u) wavelength_sample(u)
  // A colour the spectral mode uplifts, missing from the memo of a scene
  // whose kernels have no table (compile_spectral_colours left it out): the
  // GPU would render it black.
  [[noreturn]] static void spectral_colour_unlisted(vec3 rgb, uint32_t kind) {
    throw RenderError("internal error: the spectral mode's colour memo lacks (" + std::to_string(rgb.x) + ", " + std::to_string(rgb.y) + ", " +
                      std::to_string(rgb.z) + ") of kind " + std::to_string(kind) + ", and the scene's kernels have no uplift table");
  }
#define WP_SPECTRAL_COLOUR_UNLISTED(rgb, kind) spectral_colour_unlisted(rgb, kind)
#define WP_NOTE_PHASE(phase) note_phase(phase)
#define WP_NOTE_STACK_READ(entry) note_stack(WalkMemory::StackRead, entry)
#define WP_NOTE_STACK_WRITE(entry) note_stack(WalkMemory::StackWrite, entry)
#include "../../shaders/shared/scene.glsl"
#include "../../shaders/shared/integrator.glsl"
#include "../../shaders/shared/probes.glsl"
};

}  // namespace wp::shader
