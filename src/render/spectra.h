// spectra.h — the spectral mode's tables (BINDING_SPECTRA; spectrum.glsl
// lays them out, spectral.glsl reads them), made at build time by
// wavepath-spectra (src/tools/make_spectra.cpp) and linked into the program.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>

namespace wp {

struct SpectraTexels {
  const glm::vec4* texels = nullptr;
  size_t count = 0;
};

// The tables: SPECTRA_TEXELS texels.
SpectraTexels spectra_texels();

// One zero texel: what an RGB render binds in their place.
SpectraTexels spectra_placeholder();

// Measured metals (metal_spectra.glsl) by the names scene files give them
// ("Au", ...): the METAL_* id, or nothing; the names, "|"-separated; and a
// metal's eta and k as an RGB render takes them (SPECTRA_METAL_RGB).
std::optional<uint32_t> metal_named(const std::string& name);
std::string metal_names(const char* separator = "|");
void metal_rgb(uint32_t metal, glm::vec3& eta, glm::vec3& k);

}  // namespace wp
