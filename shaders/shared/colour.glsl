// colour.glsl — what the shared code does with a Spectrum (common.glsl) as a
// whole: build one from RGB or from values at the path's wavelengths, and
// reduce one to a number. Every sum or maximum over a colour's channels goes
// through these, so that the spectral kernels count the fourth wavelength
// and C++ renders in RGB leave its unused w out.
#ifndef WP_COLOUR_GLSL
#define WP_COLOUR_GLSL

// The channels a Spectrum carries: 3 in RGB, 4 in the spectral mode. C++
// compiles one vec4 for both and reads the count from the scene (SceneView).
#ifndef __cplusplus
#ifdef WP_SPECTRUM4
#define SPECTRUM_CHANNELS 4u
#else
#define SPECTRUM_CHANNELS 3u
#endif
#endif

// A colour given in RGB as a Spectrum, for the RGB mode (the spectral mode
// uplifts instead: spectral.glsl).
Spectrum spectrum_rgb(vec3 rgb) {
#ifdef WP_SPECTRUM_W
  return Spectrum(rgb.x, rgb.y, rgb.z, 0.0f);
#else
  return rgb;
#endif
}

// Values at the path's four wavelengths (spectral.glsl) as a Spectrum (the
// RGB kernels, which never run the spectral mode, keep three).
Spectrum spectrum_at(vec4 v) {
#ifdef WP_SPECTRUM_W
  return v;
#else
  return vec3(v.x, v.y, v.z);
#endif
}

// The four channels of c (the RGB kernels' fourth is 0).
vec4 spectrum_values(Spectrum c) {
#ifdef WP_SPECTRUM_W
  return c;
#else
  return vec4(c.x, c.y, c.z, 0.0f);
#endif
}

// The first three channels: the colour itself in RGB.
vec3 spectrum_xyz(Spectrum c) {
  return vec3(c.x, c.y, c.z);
}

float spectrum_max(Spectrum c) {
  float m = max(c.x, max(c.y, c.z));
#ifdef WP_SPECTRUM_W
  if (SPECTRUM_CHANNELS == 4u) m = max(m, c.w);
#endif
  return m;
}

float spectrum_sum(Spectrum c) {
  float s = c.x + c.y + c.z;
#ifdef WP_SPECTRUM_W
  if (SPECTRUM_CHANNELS == 4u) s += c.w;
#endif
  return s;
}

float spectrum_average(Spectrum c) {
  return spectrum_sum(c) * (1.0f / float(SPECTRUM_CHANNELS));
}

// Whether any channel is above 0.
bool spectrum_positive(Spectrum c) {
  return spectrum_max(c) > 0.0f;
}

// A path that keeps channel `channel` (1 to SPECTRUM_CHANNELS) alone: that
// channel of c times the channel count, the others 0 (integrator.glsl's
// disperse: the paths that kept the others estimate their light).
Spectrum spectrum_keep_channel(Spectrum c, uint channel) {
  float n = float(SPECTRUM_CHANNELS);
  vec4 v = spectrum_values(c);
  return spectrum_at(vec4(channel == 1u ? n * v.x : 0.0f, channel == 2u ? n * v.y : 0.0f, channel == 3u ? n * v.z : 0.0f,
                          channel == 4u ? n * v.w : 0.0f));
}

#endif  // WP_COLOUR_GLSL
