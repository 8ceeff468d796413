// pack_helpers.h — what several kinds' packs share (internal to src/scene/materials).
#pragma once

#include "scene/materials/material_module.h"

namespace wp::materials {

// GGX's alpha from a perceptual roughness (alpha = roughness^2, as glTF
// defines it); 0, a smooth delta lobe, below GGX_MIN_ALPHA.
inline float ggx_alpha(float roughness) { return roughness * roughness >= GGX_MIN_ALPHA ? roughness * roughness : 0.0f; }

// A blend's part or a layer's base (parameter `key`): a surface, so never a
// light (emission belongs to the surface's own material) nor an interface.
uint32_t surface_part(const MaterialInputs& in, const std::string& key);

// A layer's base: a surface part that does not emit (the layer carries the
// surface's emission), within the kernels' limits on lobes, layers and
// sheens once the layer (a sheen if `sheen`) lies over it.
uint32_t layer_base(const MaterialInputs& in, bool sheen);

// A conductor's index of refraction and absorption (params "eta" and "k",
// or "metal", a measured metal by name: spectra.h) into eta, k, and the
// value of params2.w that names its metal (CONDUCTOR_NAMED, kinds.glsl;
// 0 for RGB given). Both kinds of conductor take these three params
// (conductor_params).
void pack_conductor_index(const MaterialInputs& in, glm::vec3& eta, glm::vec3& k, float& named);
std::vector<ParamSpec> conductor_params();

// A dielectric's index of refraction: param "ior", or "glass", a named
// glass (glasses.glsl), whose index at the d line it takes; `glass` is
// GLASS_* + 1, or 0 for an ior given (the dielectric kinds' params.w). Both
// dielectric kinds take these two params (dielectric_params), and a named
// glass needs FEATURE_DISPERSION (dielectric_features).
float pack_dielectric_ior(const MaterialInputs& in, float& glass);
std::vector<ParamSpec> dielectric_params();
uint32_t dielectric_features(const shader::Material& record);

}  // namespace wp::materials
