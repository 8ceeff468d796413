// rgb_to_spectrum.h — RGB colours uplifted to smooth spectra for the
// spectral mode (issue 58), after Jakob and Hanika (2019): each linear sRGB
// reflectance in [0, 1] gets the three coefficients of a sigmoid of a
// quadratic in the wavelength (spectrum.glsl's sigmoid_polynomial) whose
// colour under D65, seen by the colour matching functions the film uses
// (cie_xyz_bar), is that RGB. The coefficients come from a table the
// optimizer below fills once for a grid of colours (Gauss-Newton in CIELAB,
// each colour started from its darker neighbour's solution); a colour
// between grid points takes the trilinear blend of theirs.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace wp {

struct RgbToSpectrumTable {
  int res = 0;
  // The grid's brightness values (the largest component), res of them,
  // dense near 0 and 1.
  std::vector<float> scale;
  // Coefficients (sigmoid_polynomial's) of colour (largest component l, brightness
  // index k, the next components' indices j and i): 3 floats at
  // (((l * res + k) * res + j) * res + i) * 3.
  std::vector<float> coefficients;
};

// Fills the table on a res^3 grid per largest component (res >= 4).
RgbToSpectrumTable make_rgb_to_spectrum_table(int res);

// The table the renderer uses (64^3 per component), made on first use.
const RgbToSpectrumTable& rgb_to_spectrum_table();

// The coefficients of the spectrum of a reflectance rgb (clamped to [0, 1]).
glm::vec3 rgb_to_spectrum(const RgbToSpectrumTable& table, glm::vec3 rgb);

// The linear sRGB of the reflectance spectrum with coefficients c under D65,
// by the sums the optimizer matches (5 nm steps, 360-830 nm): what uplifting
// is measured against.
glm::dvec3 spectrum_to_rgb(glm::vec3 c);

}  // namespace wp
