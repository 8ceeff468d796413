// compile_parts.h — the parts of compile_scene (compiled_scene.cpp), one file
// each, and what they hand one another. Each part fills its share of the
// CompiledScene; compile_scene calls them in an order that keeps every
// packed record and every sum as the single function it was split from
// made them. Internal to src/render/.
#pragma once

#include <glm/gtc/packing.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bvh/bvh.h"
#include "render/compiled_scene.h"
#include "scene/scene.h"
#include "shader/types.h"

namespace wp {

// ---- materials and textures (compile_materials.cpp) ----------------------

// The scene's textures and images as the kernels read them: each texture a
// record (types.glsl), the images' texels back to back as RGBA half floats.
struct PackedTextures {
  std::vector<shader::Texture> textures;
  std::vector<glm::uvec2> texels;
};
PackedTextures pack_textures(const Scene& scene);

// Luminance of each material's mean emitted radiance (0: it does not emit).
std::vector<double> material_radiance(const Scene& scene, const PackedTextures& packed);

// Packs the textures and texels, the materials and the float tables' first
// table, the sheen's albedo. Returns material_radiance, which the BVH
// builder and the light table weigh primitives by; it runs first for them.
std::vector<double> compile_materials(const Scene& scene, CompiledScene& out);

// Sets the bits of the triangles' material indices that the traversal reads
// (TRIANGLE_ONE_SIDED, TRIANGLE_CUTOUT). After compile_lights, which indexes
// materialRadiance by the bare indices.
void flag_triangle_materials(const Scene& scene, const std::vector<double>& materialRadiance, CompiledScene& out);

// ---- geometry and instances (compile_geometry.cpp) -----------------------

// What compile_geometry tells the parts after it, beside the arrays it fills.
struct CompiledGeometry {
  Aabb bounds;                // the top level's primitives: the scene's size, for lights at infinity
  size_t firstLightOnly = 0;  // the first light-only triangle's record (after the leaves' records)
  uint32_t stackSlots = 0;    // the traversal stack's entries (SceneParams.accel.z), both levels' walks
};

// The trees (the instanced meshes' and the top level's, in the layout
// options ask for), the primitive records in leaf order with their shading
// and vertex data, the instances and the spheres.
CompiledGeometry compile_geometry(const Scene& scene, const RenderOptions& options, const std::vector<double>& materialRadiance,
                                  CompiledScene& out);

// ---- media (compile_media.cpp) --------------------------------------------

// The media (the vacuum first), their grids in the volume words, and the
// camera's medium.
void compile_media(const Scene& scene, CompiledScene& out);
// Whether paths may meet a medium: any medium, any surface that bounds one
// or is an interface.
bool scene_has_media(const Scene& scene);
// The features the media need (FEATURE_MEDIA, FEATURE_MEDIA_GRID), as bits
// of SceneParams.kinds.w.
uint32_t media_features(const Scene& scene);

// ---- lights and the environment (compile_lights.cpp) ----------------------

// The punctual lights, the emitter table and the environment map's
// distribution (after the sheen's table in the float tables), and the
// background and environment parameters. Returns the emitters' count.
size_t compile_lights(const Scene& scene, const std::vector<double>& materialRadiance, const CompiledGeometry& geometry,
                      CompiledScene& out);

// ---- kinds and shade classes (compile_kinds.cpp) --------------------------

// SceneParams.kinds, less the sampler's and integrator's features, and the
// shade classes. Before the empty arrays get their placeholder element,
// whose kinds no scene uses.
void compile_kinds(const Scene& scene, CompiledScene& out);

// ---- the spectral mode (compile_spectral.cpp) -----------------------------

// Where the kernels may uplift colours they compute, FEATURE_SPECTRAL_TABLE;
// elsewhere the memo of the scene's constant colours with their uplift
// coefficients (BINDING_SPECTRAL_COLOURS) and its slots (SceneParams.media.y).
// One placeholder texel and no slots in RGB or with the table. After
// set_render_params, which chooses the mode, and every part that packs
// colours or sets kinds.
void compile_spectral_colours(CompiledScene& out);

// ---- photons (photon_pass.cpp) --------------------------------------------

// The photon mapper's parameters and, where options ask the host for it,
// its photon map; throws InputError on a scene it cannot render. Last: the
// photons are traced through the finished scene.
void compile_photons(const Scene& scene, const RenderOptions& options, CompiledScene& out);

// ---- shared by the parts --------------------------------------------------

// The integrator's illuminance (compiled_scene.cpp), so that the host weighs
// lights as the kernels measure them.
float luminance(glm::vec3 c);

// An image texel: RGB from two packed half-float pairs (as texel_at in scene.glsl).
inline glm::vec3 texel_rgb(glm::uvec2 packed) {
  glm::vec2 rg = glm::unpackHalf2x16(packed.x);
  return glm::vec3(rg.x, rg.y, glm::unpackHalf2x16(packed.y).x);
}

// The light kind of a punctual light record (types.glsl's PointLight).
inline uint32_t punctual_light_kind(const shader::PointLight& l) {
  return uint32_t(l.position.w);
}

// Whether a primitive record stands for a sphere or an instance.
inline bool is_placeholder(const shader::Triangle& t) {
  return t.material == WP_INVALID || t.material == PRIM_INSTANCE;
}

}  // namespace wp
