// rgb_to_spectrum.h — RGB colours uplifted to smooth spectra for the
// spectral mode (issue 58), after Jakob and Hanika (2019): each linear sRGB
// reflectance in [0, 1] gets the three coefficients of a sigmoid of a
// quadratic in the wavelength (spectrum.glsl's sigmoid_polynomial) whose
// colour under D65, seen by the colour matching functions the film uses
// (cie_xyz_bar), is that RGB. The coefficients come from a table the
// optimizer below fills once for a grid of colours (Gauss-Newton in CIELAB,
// each colour started from its darker neighbour's solution); a colour
// between grid points takes the trilinear blend of theirs (spectral.glsl's
// rgb_to_spectrum_coefficients, on the kernels and the CPU alike).
#pragma once

#include <cstdint>
#include <functional>
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
// wavepath-spectra (src/tools/make_spectra.cpp) runs it at build time for
// the tables the renderer links (spectra.h); it takes seconds.
RgbToSpectrumTable make_rgb_to_spectrum_table(int res);

// The linear sRGB of the reflectance spectrum with coefficients c under D65,
// by the sums the optimizer matches (5 nm steps, 360-830 nm): what uplifting
// is measured against.
glm::dvec3 spectrum_to_rgb(glm::vec3 c);
// The same for any spectrum s (a function of the wavelength in nm): its
// projection on linear sRGB, (v, v, v) for a constant v.
glm::dvec3 spectrum_to_rgb(const std::function<double(double)>& s);

// The film's constants, from the sums the optimizer matches: the linear
// sRGB of D65 white (Y = 1) by the film's matching functions, which the film
// divides by so that it renders as (1, 1, 1); and the factor that takes D65
// (100 at 560 nm) to Y = 1 under them (CIE_Y_INTEGRAL over its integral
// with y bar).
glm::dvec3 film_white_gains();
double d65_to_unit_luminance();

}  // namespace wp
