// spectral.glsl — the spectral mode (FEATURE_SPECTRAL, SCENE_FLAG_SPECTRAL).
//
// A path carries radiance at PATH_WAVELENGTHS (four) wavelengths in the four
// channels of its colours: a hero wavelength and three more a quarter, a
// half and three quarters of the way round the visible range, each drawn by
// the density of visible_wavelength_pdf (spectrum.glsl). The spectral
// kernels are compiled apart, with vec4 colours (common.glsl's Spectrum), so
// RGB renders carry no fourth channel. Inputs stay RGB
// where the scene gives RGB and are uplifted where the path meets them:
// reflectances by Jakob and Hanika's (2019) smooth spectra, emitters the
// same times D65 (white light is D65; the film applies the factor), indices of refraction and absorption
// unbounded (pbrt-v4's RGBUnboundedSpectrum: 2m times the reflectance
// spectrum of rgb / 2m, m its largest component). A dispersive boundary
// keeps one wavelength (integrator.glsl's disperse). The film converts each
// sample to linear sRGB once, when it is accumulated (sample_rgb): the sum
// over the wavelengths of radiance times the colour matching functions over
// the density, to XYZ, to sRGB, white balanced, so partial sums, merges,
// variance and adaptive sampling see RGB as ever.
//
// The tables (BINDING_SPECTRA, RGBA32F, laid out as spectrum.glsl's
// SPECTRA_* say) are made at build time by wavepath-spectra
// (src/tools/make_spectra.cpp).
#ifndef WP_SPECTRAL_GLSL
#define WP_SPECTRAL_GLSL

// (The RGB kernels never render a spectral scene: the host gives it the
// spectral kernels.)
bool spectral_mode() {
#if defined(__cplusplus) || defined(WP_SPECTRUM4)
  return FEATURE_COMPILED(FEATURE_SPECTRAL) && (scene.counts.w & SCENE_FLAG_SPECTRAL) != 0u;
#else
  return false;
#endif
}

// D65 at lambda, normalised so that its Y is 1: the spectrum of RGB white light.
float illuminant_d65(float lambda) {
  float x = clamp((lambda - SPECTRUM_MIN_NM) * 0.2f, 0.0f, float(CIE_D65_SAMPLES - 1));
  int i = min(int(x), CIE_D65_SAMPLES - 2);
  float f = x - float(i);
  return (1.0f - f) * texelFetch(spectrumTexels, SPECTRA_D65 + i).x + f * texelFetch(spectrumTexels, SPECTRA_D65 + i + 1).x;
}

// smoothstep's inverse on [0, 1]: the x with 3x^2 - 2x^3 = y.
float inverse_smoothstep(float y) {
  return 0.5f - sin(asin(clamp(1.0f - 2.0f * y, -1.0f, 1.0f)) * (1.0f / 3.0f));
}

// The table's brightness values, smoothstep(smoothstep(k / (res - 1))):
// computed, not fetched (the table holds them too, for the host; within an
// ulp of these).
float rgb_to_spectrum_scale(int k) {
  float t = float(k) * (1.0f / float(RGB_TO_SPECTRUM_RES - 1));
  t = t * t * (3.0f - 2.0f * t);
  return t * t * (3.0f - 2.0f * t);
}

// The sigmoid-polynomial coefficients of reflectance rgb (clamped to [0, 1]):
// the trilinear blend of the table's at the grid colours around it. The
// grid is indexed by the largest component l (its brightness z, on the
// table's scale, dense near 0 and 1) and the next two over z.
vec3 rgb_to_spectrum_coefficients(vec3 rgb) {
  rgb = clamp(rgb, vec3(0.0f), vec3(1.0f));
  if (rgb.x == rgb.y && rgb.y == rgb.z) {
    // A grey: the constant spectrum, sigmoid(c2) = v.
    float v = rgb.x;
    // (1e18: its square is still finite, so the sigmoid saturates to 0 or 1.)
    if (v <= 0.0f) return vec3(0.0f, 0.0f, -1e18f);
    if (v >= 1.0f) return vec3(0.0f, 0.0f, 1e18f);
    return vec3(0.0f, 0.0f, (v - 0.5f) / sqrt(v * (1.0f - v)));
  }
  int l = rgb.x >= rgb.y && rgb.x >= rgb.z ? 0 : rgb.y >= rgb.z ? 1 : 2;
  float z = l == 0 ? rgb.x : l == 1 ? rgb.y : rgb.z;
  float a = l == 0 ? rgb.y : l == 1 ? rgb.z : rgb.x;
  float b = l == 0 ? rgb.z : l == 1 ? rgb.x : rgb.y;
  const int res = RGB_TO_SPECTRUM_RES;
  float x = a / z * float(res - 1);
  float y = b / z * float(res - 1);
  int xi = min(int(x), res - 2);
  int yi = min(int(y), res - 2);
  // The scale is smoothstep(smoothstep(k / (res - 1))): inverted, then the
  // cell whose scale values bracket z (rounding may land one off).
  int zi = clamp(int(inverse_smoothstep(inverse_smoothstep(z)) * float(res - 1)), 0, res - 2);
  float z0 = rgb_to_spectrum_scale(zi);
  float z1 = rgb_to_spectrum_scale(zi + 1);
  if (zi > 0 && z < z0) {
    zi -= 1;
    z1 = z0;
    z0 = rgb_to_spectrum_scale(zi);
  } else if (zi < res - 2 && z >= z1) {
    zi += 1;
    z0 = z1;
    z1 = rgb_to_spectrum_scale(zi + 1);
  }
  float dx = x - float(xi);
  float dy = y - float(yi);
  float dz = (z - z0) / (z1 - z0);
  vec3 c = vec3(0.0f);
  for (int corner = 0; corner < 8; ++corner) {
    int ci = xi + (corner & 1);
    int cj = yi + ((corner >> 1) & 1);
    int ck = zi + (corner >> 2);
    float w = ((corner & 1) != 0 ? dx : 1.0f - dx) * ((corner & 2) != 0 ? dy : 1.0f - dy) * ((corner & 4) != 0 ? dz : 1.0f - dz);
    vec4 t = texelFetch(spectrumTexels, SPECTRA_RGB_COEFFICIENTS + ((l * res + ck) * res + cj) * res + ci);
    c += w * vec3(t.x, t.y, t.z);
  }
  return c;
}

// The smooth spectrum of coefficients c at the path's wavelengths.
Spectrum sigmoid_spectrum(vec3 c, vec4 lambdas) {
  return spectrum_at(vec4(sigmoid_polynomial(c, lambdas.x), sigmoid_polynomial(c, lambdas.y), sigmoid_polynomial(c, lambdas.z),
                          sigmoid_polynomial(c, lambdas.w)));
}

// The kinds of colour the memo below keys: a reflectance (bounded by 1,
// reflectance_spectrum) and an unbounded quantity (unbounded_spectrum).
#define SPECTRAL_COLOUR_REFLECTANCE 0u
#define SPECTRAL_COLOUR_UNBOUNDED 1u

// Whether the kernels uplift colours of a kind that they compute through
// the table: reflectances (a texture's, a blend's; FEATURE_SPECTRAL_TABLE),
// unbounded quantities (a light's at a distance, a textured emitter's;
// FEATURE_SPECTRAL_UNBOUNDED_TABLE). Without it, every colour of that kind
// they uplift is one of the scene's constants, and the memo below holds
// them all: a hash and two or three fetches instead of the table's eight
// texels and its cell search. (On lavapipe, which runs both sides of every
// branch, a memo in front of the table would only add to it.)
bool spectral_table(uint kind) {
  uint feature = kind == SPECTRAL_COLOUR_REFLECTANCE ? FEATURE_SPECTRAL_TABLE : FEATURE_SPECTRAL_UNBOUNDED_TABLE;
  return FEATURE_COMPILED(feature) && (scene.kinds.w & KIND_BIT(feature)) != 0u;
}

// The memo's first candidate slot for a colour, from its bits (the second:
// pcg_hash of it).
uint spectral_colour_hash(vec3 rgb, uint kind) {
  return pcg_hash(floatBitsToUint(rgb.x) ^ pcg_hash(floatBitsToUint(rgb.y) ^ pcg_hash(floatBitsToUint(rgb.z) ^ kind)));
}

// The coefficients of colour rgb of a kind, where the scene's memo holds
// them: the scene's constant colours of the kinds without their table
// (compile_spectral.cpp lists them) with the coefficients the table gives
// them, in pairs of texels (key: the colour and its kind; value: the
// coefficients), scene.media.y slots, each colour in one of its two
// candidates.
bool spectral_colour_memo(vec3 rgb, uint kind, OUT(vec3) c) {
  c = vec3(0.0f);
  uint slots = scene.media.y;
  if (slots == 0u) return false;
  uint h = spectral_colour_hash(rgb, kind);
  for (uint probe = 0u; probe < 2u; ++probe) {
    int slot = int(probe == 0u ? h & (slots - 1u) : pcg_hash(h) & (slots - 1u));
    vec4 key = texelFetch(spectralColourTexels, 2 * slot);
    if (key.x == rgb.x && key.y == rgb.y && key.z == rgb.z && key.w == float(kind)) {
      vec4 v = texelFetch(spectralColourTexels, 2 * slot + 1);
      c = vec3(v.x, v.y, v.z);
      return true;
    }
  }
  return false;
}

// The sigmoid-polynomial coefficients of colour rgb (>= 0, neither black
// nor grey) of a kind, and the scale its spectrum takes: a reflectance
// brighter than 1 (a lobe's colour carrying its blend's weight or its
// sheen's normalisation) is its largest component m times the spectrum of
// the colour over m; an unbounded quantity is 2m times the reflectance
// spectrum of the colour over 2m (pbrt-v4's RGBUnboundedSpectrum).
vec3 colour_coefficients(vec3 rgb, uint kind, OUT(float) scale) {
  float m = max(max(rgb.x, rgb.y), rgb.z);
  bool unbounded = kind == SPECTRAL_COLOUR_UNBOUNDED;
  scale = unbounded ? 2.0f * m : max(m, 1.0f);
  if (spectral_table(kind)) return rgb_to_spectrum_coefficients(unbounded ? rgb * (0.5f / m) : rgb / scale);
  vec3 c;
  // (The CPU reference fails the render of a colour the host left out.)
  if (!spectral_colour_memo(rgb, kind, c)) WP_SPECTRAL_COLOUR_UNLISTED(rgb, kind);
  return c;
}

// Colour rgb of a kind at the wavelengths; greys (and black) are constant.
Spectrum colour_spectrum(vec3 rgb, uint kind, vec4 lambdas) {
  rgb = max(rgb, vec3(0.0f));
  float m = max(max(rgb.x, rgb.y), rgb.z);
  if (!(m > 0.0f) || (rgb.x == rgb.y && rgb.y == rgb.z)) return Spectrum(rgb.x);
  float scale;
  vec3 c = colour_coefficients(rgb, kind, scale);
  return scale * sigmoid_spectrum(c, lambdas);
}

// A reflectance (an albedo, a tint) at the wavelengths.
Spectrum reflectance_spectrum(vec3 rgb, vec4 lambdas) {
  return colour_spectrum(rgb, SPECTRAL_COLOUR_REFLECTANCE, lambdas);
}

// An unbounded quantity given in RGB (radiance, an index of refraction or of
// absorption, an attenuation coefficient) at the wavelengths.
Spectrum unbounded_spectrum(vec3 rgb, vec4 lambdas) {
  return colour_spectrum(rgb, SPECTRAL_COLOUR_UNBOUNDED, lambdas);
}

// Radiance given in RGB at the wavelengths, over D65: every light's
// spectrum is D65 times its unbounded spectrum (RGB white is D65 and renders
// white), and since every path's light comes from lights, the film applies
// the D65 factor once per sample (spectral_sample_rgb), not each light at
// each vertex.
Spectrum light_spectrum(vec3 rgb, vec4 lambdas) {
  return unbounded_spectrum(rgb, lambdas);
}

// Radiance in the path's terms (at its wavelengths lambdas): as given in
// RGB, uplifted in the spectral mode.
Spectrum path_radiance(vec3 rgb, vec4 lambdas) {
  return spectral_mode() ? light_spectrum(rgb, lambdas) : spectrum_rgb(rgb);
}


// The index of refraction (and absorption) of metal `metal` (METAL_*,
// spectrum.glsl) at lambda, linear between its table's samples.
vec2 metal_index(uint metal, float lambda) {
  float x = clamp((lambda - SPECTRUM_MIN_NM) / METAL_SPECTRUM_STEP_NM, 0.0f, float(METAL_SPECTRUM_SAMPLES - 1));
  int i = min(int(x), METAL_SPECTRUM_SAMPLES - 2);
  float f = x - float(i);
  int at = SPECTRA_METALS + int(metal) * METAL_SPECTRUM_SAMPLES + i;
  vec4 a = texelFetch(spectrumTexels, at);
  vec4 b = texelFetch(spectrumTexels, at + 1);
  return vec2((1.0f - f) * a.x + f * b.x, (1.0f - f) * a.y + f * b.y);
}

// A conductor's eta (params.yzw) and k (params2.xyz; params2.w its name) at
// the wavelengths: a named metal's from its measured table (params2.w,
// kinds.glsl's CONDUCTOR_NAMED), else uplifted from their RGB.
void conductor_at_wavelengths(vec3 etaRgb, vec4 k, vec4 lambdas, OUT(vec4) eta, OUT(vec4) kappa) {
  if (k.w >= CONDUCTOR_NAMED) {
    uint metal = uint(k.w / CONDUCTOR_NAMED) - 1u;
    vec2 a = metal_index(metal, lambdas.x);
    vec2 b = metal_index(metal, lambdas.y);
    vec2 c = metal_index(metal, lambdas.z);
    vec2 d = metal_index(metal, lambdas.w);
    eta = vec4(a.x, b.x, c.x, d.x);
    kappa = vec4(a.y, b.y, c.y, d.y);
    return;
  }
  eta = spectrum_values(unbounded_spectrum(etaRgb, lambdas));
  kappa = spectrum_values(unbounded_spectrum(vec3(k.x, k.y, k.z), lambdas));
}

// Lobe i's colour parameter of LOBE_FOURTH slot `slot` at the path's
// wavelengths: the first three wavelengths' returned as xyz, the fourth's
// kept in Bsdf.lobeFourth.
vec3 bsdf_set_fourth(INOUT(Bsdf) b, uint i, int slot, vec4 values) {
#ifdef WP_SPECTRUM_W
  if (slot == 0) b.lobeFourth[i].x = values.w;
  else b.lobeFourth[i].y = values.w;
#endif
  return vec3(values.x, values.y, values.z);
}

// The BSDF's colours at the wavelengths lambdas of sample u (path_wavelengths):
// each lobe's colour, and the parameters its kind reads as colours; a thin
// film learns the sample, as it interferes per wavelength.
// (Bsdf.lobeColor arrives holding the RGB colour in its first three
// channels: material_at.glsl.)
void bsdf_at_wavelengths(INOUT(Bsdf) b, float u, vec4 lambdas) {
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    if (i >= b.lobeCount) continue;
    b.lobeColor[i] = reflectance_spectrum(spectrum_xyz(b.lobeColor[i]), lambdas);
    uint kind = b.lobeType[i];
    if ((MATERIAL_COMPILED(MAT_ROUGH_CONDUCTOR) && kind == MAT_ROUGH_CONDUCTOR) ||
        (MATERIAL_COMPILED(MAT_BECKMANN_CONDUCTOR) && kind == MAT_BECKMANN_CONDUCTOR)) {
      vec4 k = b.lobeParams2[i];
      vec4 eta;
      vec4 kappa;
      conductor_at_wavelengths(b.lobeParamYzw[i], k, lambdas, eta, kappa);
      b.lobeParamYzw[i] = bsdf_set_fourth(b, i, LOBE_FOURTH_ETA, eta);
      vec3 k3 = bsdf_set_fourth(b, i, LOBE_FOURTH_K, kappa);
      b.lobeParams2[i] = vec4(k3.x, k3.y, k3.z, k.w);
    }
    if (MATERIAL_COMPILED(MAT_CS184_GLASS) && kind == MAT_CS184_GLASS) {
      vec4 p = b.lobeParams2[i];
      vec3 r = bsdf_set_fourth(b, i, LOBE_FOURTH_PARAMS2, spectrum_values(reflectance_spectrum(vec3(p.x, p.y, p.z), lambdas)));
      b.lobeParams2[i] = vec4(r.x, r.y, r.z, p.w);
    }
    if (MATERIAL_COMPILED(MAT_METAL_ROUGH) && kind == MAT_METAL_ROUGH) {
      if (FEATURE_COMPILED(FEATURE_SPECULAR_TINT)) {
        // params2.xyz: the specular colour less 1.
        vec4 p = b.lobeParams2[i];
        vec4 tint = spectrum_values(reflectance_spectrum(vec3(1.0f + p.x, 1.0f + p.y, 1.0f + p.z), lambdas)) - vec4(1.0f);
        vec3 t = bsdf_set_fourth(b, i, LOBE_FOURTH_PARAMS2, tint);
        b.lobeParams2[i] = vec4(t.x, t.y, t.z, p.w);
      }
      if (FEATURE_COMPILED(FEATURE_DIFFUSE_TRANSMISSION)) {
        vec4 dt = bsdf_extra(b, i, MR_LOBE_DIFFUSE_TRANSMISSION);
        vec3 c = bsdf_set_fourth(b, i, LOBE_FOURTH_TRANSMISSION, spectrum_values(reflectance_spectrum(vec3(dt.x, dt.y, dt.z), lambdas)));
        bsdf_set_extra(b, i, MR_LOBE_DIFFUSE_TRANSMISSION, vec4(c.x, c.y, c.z, dt.w));
      }
      if (FEATURE_COMPILED(FEATURE_IRIDESCENCE)) {
        vec4 film = bsdf_extra(b, i, MR_LOBE_FILM);
        bsdf_set_extra(b, i, MR_LOBE_FILM, vec4(film.x, film.y, film.z, THIN_FILM_SPECTRAL + u));
      }
    }
  }
}

// The index of refraction at lambda (nm) of a glass of index ior at the
// d line (587.56 nm) and dispersion 20 / V (V its Abbe number): the Cauchy
// fit through the F, d and C lines that KHR_materials_dispersion gives.
float dispersed_ior_at(float ior, float dispersion, float lambda) {
  float n = ior + (ior - 1.0f) * dispersion * (1.0f / 20.0f) * (523655.0f / (lambda * lambda) - 1.5168f);
  return max(n, METAL_ROUGH_MIN_IOR);
}

// Whether b has a dispersive lobe (FEATURE_DISPERSION).
bool bsdf_disperses(Bsdf b) {
  bool dispersive = false;
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    if (i < b.lobeCount && b.lobeDispersion[i] != 0.0f) dispersive = true;
  }
  return dispersive;
}

// b's dispersive lobes at the index of the one channel a path kept (1 to 3
// in RGB): its wavelength in lambdas in the spectral mode (always the
// hero's, channel 1), else the Fraunhofer line of its RGB channel (C, d, F).
void disperse_lobes(INOUT(Bsdf) b, uint channel, vec4 lambdas) {
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    if (!(i < b.lobeCount && b.lobeDispersion[i] != 0.0f)) continue;
    float lambda = spectral_mode() ? lambdas.x : (channel == 1u ? FRAUNHOFER_C_NM : channel == 2u ? FRAUNHOFER_D_NM : FRAUNHOFER_F_NM);
    float d = b.lobeDispersion[i];
    if (d < 0.0f) {
      b.lobeParam[i] = glass_ior(uint(-d) - 1u, lambda);  // the dielectric kinds' ior: params.x
    } else {
      b.lobeParamYzw[i].y = spectral_mode() ? dispersed_ior_at(b.lobeParamYzw[i].y, d, lambda) : dispersed_ior(b.lobeParamYzw[i].y, d, channel);
    }
  }
}

// The film's weight of wavelength sample u: the colour matching functions
// times D65 over the density, at the sample's wavelength
// (sample_visible_wavelength(u)). The table holds it every
// 1 / FILM_WEIGHT_SEGMENTS of u (at most 0.95 nm apart, at the range's ends)
// and the film takes it linearly between: two fetches instead of the
// wavelength's arctanh, the density's cosh and the fit's seven exponentials
// (film_weight_exact, which the table is made of).
vec3 film_weight(float u) {
  float x = clamp(u, 0.0f, 1.0f) * float(FILM_WEIGHT_SEGMENTS);
  int i = min(int(x), FILM_WEIGHT_SEGMENTS - 1);
  float f = x - float(i);
  vec4 a = texelFetch(spectrumTexels, SPECTRA_FILM_WEIGHTS + i);
  vec4 b = texelFetch(spectrumTexels, SPECTRA_FILM_WEIGHTS + i + 1);
  return vec3(a.x + (b.x - a.x) * f, a.y + (b.y - a.y) * f, a.z + (b.z - a.z) * f);
}

vec3 film_weight_exact(float u) {
  float lambda = clamp(sample_visible_wavelength(u), SPECTRUM_MIN_NM, SPECTRUM_MAX_NM);  // (the ends, rounded outside)
  return cie_xyz_bar(lambda) * (illuminant_d65(lambda) / visible_wavelength_pdf(lambda));
}

// The sample's linear sRGB: radiance l over D65 (light_spectrum) at the
// wavelengths of sample u (path_wavelengths' rotations of u), through each
// one's film weight, averaged (a path that kept one wavelength carries it
// at four times its weight: disperse), to XYZ and to white-balanced sRGB
// (the film's gains put D65 at (1, 1, 1), as the uplift's table assumes).
vec3 spectral_sample_rgb(Spectrum radiance, float u) {
  vec4 l = spectrum_values(radiance);
  vec3 xyz = l.x * film_weight(u) + l.y * film_weight(fract(u + 0.25f)) + l.z * film_weight(fract(u + 0.5f)) +
             l.w * film_weight(fract(u + 0.75f));
  vec3 rgb = xyz_to_linear_srgb(xyz * (1.0f / (float(PATH_WAVELENGTHS) * CIE_Y_INTEGRAL)));
  vec4 gains = texelFetch(spectrumTexels, SPECTRA_FILM);
  return vec3(rgb.x / gains.x, rgb.y / gains.y, rgb.z / gains.z);
}

// What a finished path adds to its pixel: its radiance, in linear sRGB.
vec3 sample_rgb(PathState p) {
  return spectral_mode() ? spectral_sample_rgb(p.radiance, p.wavelengths) : spectrum_xyz(p.radiance);
}

#endif  // WP_SPECTRAL_GLSL
