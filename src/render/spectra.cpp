// spectra.cpp — the spectral mode's tables, as the build linked them
// (spectra_data.S.in includes the file wavepath-spectra wrote).
#include "render/spectra.h"

#include <cstdint>

#include "render/shader_cpp.h"
#include "util/error.h"

extern "C" {
extern const unsigned char wp_spectra_begin[];
extern const unsigned char wp_spectra_end[];
}

namespace wp {

SpectraTexels spectra_texels() {
  const size_t bytes = size_t(wp_spectra_end - wp_spectra_begin);
  if (bytes != size_t(SPECTRA_TEXELS) * sizeof(glm::vec4) || reinterpret_cast<uintptr_t>(wp_spectra_begin) % alignof(glm::vec4) != 0) {
    throw RenderError("internal error: the spectral tables linked in have " + std::to_string(bytes) + " bytes, not " +
                      std::to_string(size_t(SPECTRA_TEXELS) * sizeof(glm::vec4)));
  }
  return SpectraTexels{reinterpret_cast<const glm::vec4*>(wp_spectra_begin), size_t(SPECTRA_TEXELS)};
}

namespace {

#define WP_METAL_NAME(id, name) name,
const char* const kMetalNames[] = {WP_METALS(WP_METAL_NAME)};
#undef WP_METAL_NAME

}  // namespace

std::optional<uint32_t> metal_named(const std::string& name) {
  for (uint32_t m = 0; m < METAL_COUNT; ++m)
    if (name == kMetalNames[m]) return m;
  return std::nullopt;
}

std::string metal_names(const char* separator) {
  std::string out;
  for (const char* n : kMetalNames) out += (out.empty() ? "" : separator) + std::string(n);
  return out;
}

void metal_rgb(uint32_t metal, glm::vec3& eta, glm::vec3& k) {
  const SpectraTexels t = spectra_texels();
  eta = glm::vec3(t.texels[SPECTRA_METAL_RGB + 2 * int(metal)]);
  k = glm::vec3(t.texels[SPECTRA_METAL_RGB + 2 * int(metal) + 1]);
}

SpectraTexels spectra_placeholder() {
  static const glm::vec4 zero(0.0f);
  return SpectraTexels{&zero, 1};
}

}  // namespace wp
