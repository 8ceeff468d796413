// make_spectra.cpp — wavepath-spectra, run at build time: writes the
// spectral mode's tables (BINDING_SPECTRA, laid out as spectrum.glsl's
// SPECTRA_* say) as raw RGBA32F texels, which the build links into the
// renderer (src/render/spectra.cpp): the film's white balance, D65
// normalised to Y = 1, the film's weights of wavelength samples, the RGB uplift's coefficient table (fitted here,
// rgb_to_spectrum.cpp) and the measured metals (metal_spectra.glsl).
//
//   wavepath-spectra OUT
//
// Writes OUT.tmp and renames it, so that an interrupted build leaves no
// table that looks whole.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "render/rgb_to_spectrum.h"
#include "render/shader_cpp.h"

int main(int argc, char** argv) {
  using namespace wp;
  if (argc != 2) {
    std::fprintf(stderr, "usage: wavepath-spectra OUT\n");
    return 2;
  }
  std::vector<glm::vec4> texels(size_t(SPECTRA_TEXELS), glm::vec4(0.0f));
  texels[SPECTRA_FILM] = glm::vec4(glm::vec3(film_white_gains()), 0.0f);
  const double d65 = d65_to_unit_luminance();
  for (int i = 0; i < CIE_D65_SAMPLES; ++i) texels[size_t(SPECTRA_D65 + i)].x = float(shader::ShaderMath::CIE_D65[i] * d65);
  // The film's weights of wavelength samples, through the kernels' own
  // functions over the D65 just written.
  shader::SceneView view;
  view.spectrumTexels = texels.data();
  for (int k = 0; k <= FILM_WEIGHT_SEGMENTS; ++k) {
    texels[size_t(SPECTRA_FILM_WEIGHTS + k)] = glm::vec4(view.film_weight_exact(float(k) / float(FILM_WEIGHT_SEGMENTS)), 0.0f);
  }
  const RgbToSpectrumTable table = make_rgb_to_spectrum_table(RGB_TO_SPECTRUM_RES);
  for (int k = 0; k < RGB_TO_SPECTRUM_RES; ++k) texels[size_t(SPECTRA_RGB_SCALE + k)].x = table.scale[size_t(k)];
  for (size_t i = 0; i < table.coefficients.size() / 3; ++i) {
    const float* c = &table.coefficients[i * 3];
    texels[size_t(SPECTRA_RGB_COEFFICIENTS) + i] = glm::vec4(c[0], c[1], c[2], 0.0f);
  }
  for (int i = 0; i < int(METAL_COUNT) * METAL_SPECTRUM_SAMPLES; ++i) {
    texels[size_t(SPECTRA_METALS + i)] = glm::vec4(shader::ShaderMath::METAL_ETA_K[2 * i], shader::ShaderMath::METAL_ETA_K[2 * i + 1], 0.0f, 0.0f);
  }
  // Each metal's eta and k for RGB renders: the projections of their spectra.
  for (int m = 0; m < int(METAL_COUNT); ++m) {
    for (int part = 0; part < 2; ++part) {
      auto s = [&](double lambda) {
        const double x = std::clamp((lambda - SPECTRUM_MIN_NM) / double(METAL_SPECTRUM_STEP_NM), 0.0, double(METAL_SPECTRUM_SAMPLES - 1));
        const int i = std::min(int(x), METAL_SPECTRUM_SAMPLES - 2);
        const double f = x - i;
        const float* t = &shader::ShaderMath::METAL_ETA_K[size_t(m * METAL_SPECTRUM_SAMPLES + i) * 2 + size_t(part)];
        return (1.0 - f) * t[0] + f * t[2];
      };
      texels[size_t(SPECTRA_METAL_RGB + 2 * m + part)] = glm::vec4(glm::vec3(spectrum_to_rgb(s)), 0.0f);
    }
  }
  const std::string out = argv[1], tmp = out + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    std::perror(tmp.c_str());
    return 1;
  }
  const size_t written = std::fwrite(texels.data(), sizeof(glm::vec4), texels.size(), f);
  if (std::fclose(f) != 0 || written != texels.size() || std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::perror(out.c_str());
    return 1;
  }
  return 0;
}
