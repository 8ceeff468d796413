// spectrum.glsl — wavelengths, for the spectral mode issue 58 builds: the
// density wavelengths are sampled by, and the eye's colour matching
// functions that turn a spectral radiance into CIE XYZ and linear sRGB, the
// D65 illuminant, and the smooth spectra RGB colours are uplifted to.
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

// CIE XYZ to linear sRGB (Rec. 709 primaries, D65 white; IEC 61966-2-1),
// as a vector of type V (the host's uplift fit takes it in double:
// rgb_to_spectrum.cpp).
#define WP_XYZ_TO_LINEAR_SRGB(V, x, y, z)                                                                          \
  V(3.2404542f * (x) - 1.5371385f * (y) - 0.4985314f * (z), -0.9692660f * (x) + 1.8760108f * (y) + 0.0415560f * (z), \
    0.0556434f * (x) - 0.2040259f * (y) + 1.0572252f * (z))
vec3 xyz_to_linear_srgb(vec3 c) {
  return WP_XYZ_TO_LINEAR_SRGB(vec3, c.x, c.y, c.z);
}

// CIE standard illuminant D65, relative spectral power at 5 nm steps from
// 360 to 830 nm (100 at 560 nm): CIE 15:2004 Colorimetry, Table T.1 (also
// ISO 11664-2). The table is host only: wavepath-spectra fits the RGB
// uplift under it and copies it, normalised, into the spectral tables
// (SPECTRA_D65 below) that the kernels read.
#define CIE_D65_SAMPLES 95
#ifdef __cplusplus
WP_TABLE(CIE_D65, CIE_D65_SAMPLES)
    46.6383f, 49.3637f, 52.0891f, 51.0323f, 49.9755f, 52.3118f, 54.6482f, 68.7015f, 82.7549f, 87.1204f,
    91.486f, 92.4589f, 93.4318f, 90.057f, 86.6823f, 95.7736f, 104.865f, 110.936f, 117.008f, 117.41f,
    117.812f, 116.336f, 114.861f, 115.392f, 115.923f, 112.367f, 108.811f, 109.082f, 109.354f, 108.578f,
    107.802f, 106.296f, 104.79f, 106.239f, 107.689f, 106.047f, 104.405f, 104.225f, 104.046f, 102.023f,
    100.0f, 98.1671f, 96.3342f, 96.0611f, 95.788f, 92.2368f, 88.6856f, 89.3459f, 90.0062f, 89.8026f,
    89.5991f, 88.6489f, 87.6987f, 85.4936f, 83.2886f, 83.4939f, 83.6992f, 81.863f, 80.0268f, 80.1207f,
    80.2146f, 81.2462f, 82.2778f, 80.281f, 78.2842f, 74.0027f, 69.7213f, 70.6652f, 71.6091f, 72.979f,
    74.349f, 67.9765f, 61.604f, 65.7448f, 69.8856f, 72.4863f, 75.087f, 69.3398f, 63.5927f, 55.0054f,
    46.4182f, 56.6118f, 66.8054f, 65.0941f, 63.3828f, 63.8434f, 64.304f, 61.8779f, 59.4519f, 55.7054f,
    51.959f, 54.6998f, 57.4406f, 58.8765f, 60.3125f
WP_TABLE_END

// D65 at lambda (nm), linear between the table's samples, 0 outside it.
float cie_d65(float lambda) {
  float x = (lambda - SPECTRUM_MIN_NM) / 5.0f;
  if (x < 0.0f || x > float(CIE_D65_SAMPLES - 1)) return 0.0f;
  int i = min(int(x), CIE_D65_SAMPLES - 2);
  float f = x - float(i);
  return (1.0f - f) * CIE_D65[i] + f * CIE_D65[i + 1];
}
#endif

// Jakob and Hanika's (2019) smooth reflectance spectrum of three
// coefficients c: a sigmoid of a quadratic in the wavelength mapped to
// [0, 1] over the visible range (in nm the coefficients of saturated colours
// cancel to nothing in float), in [0, 1] at every wavelength; c2 = inf gives
// 1 and -inf gives 0 (the sigmoid's limits).
float sigmoid_polynomial(vec3 c, float lambda) {
  float l = (lambda - SPECTRUM_MIN_NM) * (1.0f / (SPECTRUM_MAX_NM - SPECTRUM_MIN_NM));
  float x = fma(fma(c.x, l, c.y), l, c.z);
  if (isinf(x)) return x > 0.0f ? 1.0f : 0.0f;
  return 0.5f + x / (2.0f * sqrt(1.0f + x * x));
}

// The wavelengths a path carries in the spectral mode (spectral.glsl): one
// a channel of the spectral kernels' colours (common.glsl's Spectrum), as
// pbrt-v4 and Mitsuba 3 carry four.
#define PATH_WAVELENGTHS 4

// The path's wavelengths (nm) from its sample u in [0, 1): the hero, then u
// rotated by a quarter, a half and three quarters, each through the
// density's inverse CDF (each is distributed by the density; together they
// stratify it).
// Sample i of a randomly shifted sequence of wavelength samples (shift:
// 32 random bits): i times the silver ratio's fraction, sqrt(2) - 1, in
// 32-bit fixed point (exact at any index). Its points spread evenly over
// the interval, so a pixel's heroes do (what a dispersed path keeps), and
// so do four times them, which is what the four wavelengths' estimate
// repeats with (path_wavelengths has period 1/4). The golden ratio's thirds
// clumped when paths carried three wavelengths: its colour error over a
// pixel's samples was 1.8 to 11 times this one's (docs/experiments.md).
float wavelength_sequence(uint shift, uint i) {
  return float((shift + i * 1779033704u) >> 8) * (1.0f / 16777216.0f);
}

vec4 path_wavelengths(float u) {
  return vec4(sample_visible_wavelength(u), sample_visible_wavelength(fract(u + 0.25f)), sample_visible_wavelength(fract(u + 0.5f)),
              sample_visible_wavelength(fract(u + 0.75f)));
}

// A thin film's Lobe.extra slot holds, in w, THIN_FILM_SPECTRAL plus the
// path's wavelength sample in the spectral mode (0 in RGB).
#define THIN_FILM_SPECTRAL 1.0f

// Measured metals: their ids (METAL_*) and indices of refraction; named
// glasses (GLASS_*).
#include "metal_spectra.glsl"
#include "glasses.glsl"

// The spectral mode's tables (BINDING_SPECTRA, RGBA32F texels), from
// SPECTRA_FILM: the film's white balance (xyz: linear sRGB is divided by
// it); from SPECTRA_D65 D65 normalised to Y = 1 (x); from
// SPECTRA_RGB_SCALE the uplift table's brightness values (x); from
// SPECTRA_METALS each metal's eta (x) and k (y) at METAL_SPECTRUM_SAMPLES
// wavelengths from 360 nm; from SPECTRA_METAL_RGB each metal's eta and k
// (xyz, two texels) as an RGB render takes them: their spectra's linear
// sRGB projections (spectrum_to_rgb), as Mitsuba's RGB modes take measured
// spectra; from SPECTRA_FILM_WEIGHTS the film's weight of a wavelength
// sample u (xyz: the matching functions times D65 over the density, at
// sample_visible_wavelength(u)) at u = k / FILM_WEIGHT_SEGMENTS, k from 0 to
// FILM_WEIGHT_SEGMENTS; and last, from SPECTRA_RGB_COEFFICIENTS, the uplift table's
// coefficients (xyz) of colour (largest component l, brightness k, next
// components j, i) at ((l * RES + k) * RES + j) * RES + i: 99 % of the
// texels, which a scene whose kernels have no table
// (FEATURE_SPECTRAL_TABLE) does not upload.
#define RGB_TO_SPECTRUM_RES 64
#define SPECTRA_FILM 0
#define SPECTRA_D65 1
#define SPECTRA_RGB_SCALE (SPECTRA_D65 + CIE_D65_SAMPLES)
#define SPECTRA_METALS (SPECTRA_RGB_SCALE + RGB_TO_SPECTRUM_RES)
#define SPECTRA_METAL_RGB (SPECTRA_METALS + int(METAL_COUNT) * METAL_SPECTRUM_SAMPLES)
#define FILM_WEIGHT_SEGMENTS 2048
#define SPECTRA_FILM_WEIGHTS (SPECTRA_METAL_RGB + 2 * int(METAL_COUNT))
#define SPECTRA_RGB_COEFFICIENTS (SPECTRA_FILM_WEIGHTS + FILM_WEIGHT_SEGMENTS + 1)
#define SPECTRA_TEXELS (SPECTRA_RGB_COEFFICIENTS + 3 * RGB_TO_SPECTRUM_RES * RGB_TO_SPECTRUM_RES * RGB_TO_SPECTRUM_RES)

#endif  // WP_SPECTRUM_GLSL
