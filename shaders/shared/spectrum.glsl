// spectrum.glsl — wavelengths, for the spectral mode issue 58 builds: the
// density wavelengths are sampled by, and the eye's colour matching
// functions that turn a spectral radiance into CIE XYZ and linear sRGB.
// tests/test_spectrum.cpp checks the sampler against its density with a
// chi-square test and the matching functions against the CIE's integrals.
#ifndef WP_SPECTRUM_GLSL
#define WP_SPECTRUM_GLSL

#define SPECTRUM_MIN_NM 360.0f
#define SPECTRUM_MAX_NM 830.0f

// Wavelengths drawn over the visible range with a density that follows the
// eye's response: p(l) = A / cosh^2(B (l - 538 nm)) on [360, 830] nm, the
// shape pbrt-v4 samples visible wavelengths by (A normalizes it over the
// range), sampled by inverting its CDF, an arctanh.
float visible_wavelength_pdf(float lambda) {
  if (lambda < SPECTRUM_MIN_NM || lambda > SPECTRUM_MAX_NM) return 0.0f;
  float c = cosh(0.0072f * (lambda - 538.0f));
  return 0.0039398042f / (c * c);
}

float sample_visible_wavelength(float u) {
  return 538.0f - 138.888889f * atanh(0.85691062f - 1.82750197f * u);
}

// A lobe of Wyman, Sloan and Shirley's (2013) fit to the CIE 1931 colour
// matching functions: a Gaussian of mean mu, width s1 below it and s2 above.
float cie_lobe(float lambda, float mu, float s1, float s2) {
  float t = (lambda - mu) / (lambda < mu ? s1 : s2);
  return exp(-0.5f * t * t);
}

// The CIE 1931 2-degree observer's x, y and z bar at lambda (nm), by that
// fit (within a few per cent of the tables where they are large).
vec3 cie_xyz_bar(float lambda) {
  float x = 1.056f * cie_lobe(lambda, 599.8f, 37.9f, 31.0f) + 0.362f * cie_lobe(lambda, 442.0f, 16.0f, 26.7f) -
            0.065f * cie_lobe(lambda, 501.1f, 20.4f, 26.2f);
  float y = 0.821f * cie_lobe(lambda, 568.8f, 46.9f, 40.5f) + 0.286f * cie_lobe(lambda, 530.9f, 16.3f, 31.1f);
  float z = 1.217f * cie_lobe(lambda, 437.0f, 11.8f, 36.0f) + 0.681f * cie_lobe(lambda, 459.0f, 26.0f, 13.8f);
  return vec3(x, y, z);
}

// The integral of y bar over the visible range, by which a spectral
// radiance's Y is divided so that a constant spectrum of 1 has Y = 1.
#define CIE_Y_INTEGRAL 106.856895f

// CIE XYZ to linear sRGB (Rec. 709 primaries, D65 white; IEC 61966-2-1).
vec3 xyz_to_linear_srgb(vec3 c) {
  return vec3(3.2404542f * c.x - 1.5371385f * c.y - 0.4985314f * c.z, -0.9692660f * c.x + 1.8760108f * c.y + 0.0415560f * c.z,
              0.0556434f * c.x - 0.2040259f * c.y + 1.0572252f * c.z);
}

#endif  // WP_SPECTRUM_GLSL
