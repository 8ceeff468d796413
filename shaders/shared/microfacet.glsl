// microfacet.glsl — the isotropic GGX (Trowbridge-Reitz) microfacet model
// that the rough conductor, the rough dielectric and glTF's metal-rough
// material share: the normal distribution D, Smith's height-correlated
// masking-shadowing G2, sampling of the normals visible from wo (Heitz,
// "Sampling the GGX Distribution of Visible Normals", JCGT 2018) and the
// Fresnel terms. Angles are given by their cosines to the shading normal;
// alpha is GGX's width (glTF: roughness squared).
#ifndef WP_MICROFACET_GLSL
#define WP_MICROFACET_GLSL

// D(h): microfacet normals per unit projected area, over the solid angle of
// h. The sine comes from the cross product: 1 - cos^2 in float would lose
// the lobe's shape for alpha near GGX_MIN_ALPHA, where sin^2 is about alpha^2.
float ggx_d(vec3 h, vec3 n, float alpha) {
  float c = dot(h, n);
  if (c <= 0.0f) return 0.0f;
  vec3 s = cross(h, n);
  float a2 = alpha * alpha;
  float t = dot(s, s) + c * c * a2;
  return a2 / (WP_PI * t * t);
}

// Smith's Lambda for a direction at cosine c: the masked fraction's measure.
float ggx_lambda(float c, float alpha) {
  float c2 = max(c * c, 1e-12f);
  float tan2 = max(1.0f - c2, 0.0f) / c2;
  return 0.5f * (sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
}

// G1: the fraction of microfacets facing w that w sees.
float ggx_g1(float c, float alpha) {
  return 1.0f / (1.0f + ggx_lambda(c, alpha));
}

// G2, height-correlated: the fraction visible from both directions.
float ggx_g2(float cosO, float cosI, float alpha) {
  return 1.0f / (1.0f + ggx_lambda(cosO, alpha) + ggx_lambda(cosI, alpha));
}

// A microfacet normal h with density ggx_visible_pdf (anisotropic GGX of
// widths ax along x and ay along y: its anisotropic twin): the normals visible
// from wo, each in proportion to its projected area seen from wo. wo and the
// result are in the shading frame (the normal is +z, wo.z > 0). Heitz's
// construction: stretch wo to the configuration where the GGX surface is a
// hemisphere of radius 1, sample the visible half disk of that hemisphere
// (a uniform disk whose lower half is squeezed by the projection), lift the
// point onto the hemisphere and unstretch its normal.
vec3 ggx_sample_visible_anisotropic(vec3 wo, float ax, float ay, vec2 u) {
  vec3 v = normalize(vec3(ax * wo.x, ay * wo.y, wo.z));
  float lenSq = v.x * v.x + v.y * v.y;
  vec3 t1 = lenSq > 0.0f ? vec3(-v.y, v.x, 0.0f) * (1.0f / sqrt(lenSq)) : vec3(1.0f, 0.0f, 0.0f);
  vec3 t2 = cross(v, t1);
  float r = sqrt(u.x);
  float phi = 2.0f * WP_PI * u.y;
  float p1 = r * cos(phi);
  float p2 = r * sin(phi);
  float s = 0.5f * (1.0f + v.z);
  p2 = (1.0f - s) * sqrt(max(1.0f - p1 * p1, 0.0f)) + s * p2;
  vec3 n = t1 * p1 + t2 * p2 + v * sqrt(max(1.0f - p1 * p1 - p2 * p2, 0.0f));
  return normalize(vec3(ax * n.x, ay * n.y, max(n.z, 0.0f)));
}

// The isotropic case.
vec3 ggx_sample_visible(vec3 wo, float alpha, vec2 u) {
  return ggx_sample_visible_anisotropic(wo, alpha, alpha, u);
}

// Density (solid angle of h) of ggx_sample_visible: G1(wo) max(0, wo.h) D(h) / cos(wo).
float ggx_visible_pdf(vec3 wo, vec3 h, vec3 n, float alpha) {
  float cosO = dot(wo, n);
  float woH = dot(wo, h);
  if (cosO <= 0.0f || woH <= 0.0f) return 0.0f;
  return ggx_g1(cosO, alpha) * woH * ggx_d(h, n, alpha) / cosO;
}

// A visible normal in world space around shading normal ns, or a zero vector
// when wo lies below the shading surface.
vec3 ggx_visible_normal(float alpha, vec3 ns, vec3 wo, vec2 u) {
  vec3 t;
  vec3 bt;
  make_frame(ns, t, bt);
  vec3 woLocal = vec3(dot(wo, t), dot(wo, bt), dot(wo, ns));
  if (woLocal.z <= 0.0f) return vec3(0.0f);
  return frame_to_world(ggx_sample_visible(woLocal, alpha, u), t, bt, ns);
}

// The mirror of wo about a visible normal (zero when it points below the surface).
vec3 ggx_reflection_sample(float alpha, vec3 ns, vec3 wo, vec2 u) {
  vec3 h = ggx_visible_normal(alpha, ns, wo, u);
  vec3 wi = reflect_about(wo, h);
  return dot(h, ns) > 0.0f && dot(wi, ns) > 0.0f ? wi : vec3(0.0f);
}

// Density of ggx_reflection_sample's directions: the visible normals' over
// the Jacobian of reflection, 4 wo.h.
float ggx_reflection_pdf(float alpha, vec3 ns, vec3 wo, vec3 wi) {
  if (dot(wo, ns) <= 0.0f || dot(wi, ns) <= 0.0f) return 0.0f;
  vec3 h = normalize(wo + wi);
  return ggx_visible_pdf(wo, h, ns, alpha) / (4.0f * dot(wo, h));
}

// The specular term without its Fresnel factor, times cos(wi): D G2 / (4 cos_o).
float ggx_reflection_eval(float alpha, vec3 ns, vec3 wo, vec3 wi) {
  float cosO = dot(wo, ns);
  float cosI = dot(wi, ns);
  if (cosO <= 0.0f || cosI <= 0.0f) return 0.0f;
  return ggx_d(normalize(wo + wi), ns, alpha) * ggx_g2(cosO, cosI, alpha) / (4.0f * cosO);
}

// Unpolarised Fresnel reflectance of a conductor of complex index eta + i k
// (per channel, relative to the outside medium) at incident cosine cosI.
Spectrum fresnel_conductor(float cosI, Spectrum eta, Spectrum k) {
  float c = clamp(cosI, 0.0f, 1.0f);
  float c2 = c * c;
  float s2 = 1.0f - c2;
  Spectrum eta2 = eta * eta;
  Spectrum k2 = k * k;
  Spectrum t0 = eta2 - k2 - Spectrum(s2);
  Spectrum a2b2 = sqrt(t0 * t0 + eta2 * k2 * 4.0f);  // a^2 + b^2
  Spectrum a = sqrt(max((a2b2 + t0) * 0.5f, Spectrum(0.0f)));
  Spectrum t1 = a2b2 + Spectrum(c2);
  Spectrum t2 = a * (2.0f * c);
  Spectrum rs = (t1 - t2) / max(t1 + t2, Spectrum(1e-12f));
  Spectrum t3 = a2b2 * c2 + Spectrum(s2 * s2);
  Spectrum t4 = t2 * s2;
  Spectrum rp = rs * (t3 - t4) / max(t3 + t4, Spectrum(1e-12f));
  return (rs + rp) * 0.5f;
}

// Schlick's weight (1 - cos)^5, which glTF's Fresnel terms use.
float schlick_weight(float c) {
  float m = clamp(1.0f - c, 0.0f, 1.0f);
  float m2 = m * m;
  return m2 * m2 * m;
}

// Anisotropic GGX in a frame where the normal is +z: D of widths ax along
// x and ay along y, and Smith's Lambda for a direction w in that frame
// (Heitz 2014, "Understanding the Masking-Shadowing Function").
float ggx_anisotropic_d(vec3 h, float ax, float ay) {
  if (h.z <= 0.0f) return 0.0f;
  float x = h.x / ax;
  float y = h.y / ay;
  float t = x * x + y * y + h.z * h.z;
  return 1.0f / (WP_PI * ax * ay * t * t);
}

float ggx_anisotropic_lambda(vec3 w, float ax, float ay) {
  float z2 = max(w.z * w.z, 1e-12f);
  return 0.5f * (sqrt(1.0f + (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / z2) - 1.0f);
}

// Reflectance at normal incidence between media of indices a and b.
float fresnel0_of_iors(float a, float b) {
  float r = (a - b) / (a + b);
  return r * r;
}

// The spectral sensitivity of the XYZ matching functions to an optical path
// difference opd (nm) with phase shift `shift`, as RGB (Belcour and Barla
// 2017's Gaussian fit, which KHR_materials_iridescence's README.md:383-405
// gives with its constants).
vec3 thin_film_sensitivity(float opd, vec3 shift) {
  float phase = 2.0f * WP_PI * opd * 1e-9f;
  vec3 val = vec3(5.4856e-13f, 4.4201e-13f, 5.2481e-13f);
  vec3 pos = vec3(1.6810e+06f, 1.7953e+06f, 2.2084e+06f);
  vec3 var = vec3(4.3278e+09f, 9.3046e+09f, 6.6121e+09f);
  vec3 xyz = val * sqrt(var * (2.0f * WP_PI)) * cos(pos * phase + shift) * exp(-(phase * phase) * var);
  xyz.x += 9.7470e-14f * sqrt(2.0f * WP_PI * 4.5282e+09f) * cos(2.2399e+06f * phase + shift.x) * exp(-4.5282e+09f * phase * phase);
  xyz = xyz * (1.0f / 1.0685e-7f);
  return xyz_to_linear_srgb(xyz);
}

// Reflectance of a thin film (index filmIor, thickness nm) over a base of
// normal-incidence reflectance baseF0, seen from a medium of index 1 at
// cosine c: the airy sum of the film's two interfaces to its second order,
// each a Schlick term, integrated against the eye's sensitivity (Belcour and
// Barla 2017, as KHR_materials_iridescence's README.md:257-377 writes it).
// Without a film (thickness 0) it is the base's own Schlick term. In the
// spectral mode (`wavelengths` THIN_FILM_SPECTRAL plus the path's wavelength
// sample, spectrum.glsl) each component is the reflectance at one of the
// path's wavelengths: the airy sum's terms are cosines of their phase there,
// not integrals against the eye's sensitivity.
Spectrum thin_film_fresnel(float filmIor, float thickness, Spectrum baseF0, float c, float wavelengths) {
  Spectrum f0 = clamp(baseF0, Spectrum(0.0f), Spectrum(0.9999f));
  if (!(thickness > 0.0f)) return f0 + (Spectrum(1.0f) - f0) * schlick_weight(c);
  float r12 = fresnel0_of_iors(filmIor, 1.0f);
  r12 = r12 + (1.0f - r12) * schlick_weight(c);
  float t121 = 1.0f - r12;
  float sin2 = (1.0f - c * c) / (filmIor * filmIor);
  if (sin2 >= 1.0f) return Spectrum(1.0f);  // total internal reflection at the film
  float cos2 = sqrt(1.0f - sin2);
  Spectrum s = sqrt(f0);
  Spectrum baseIor = (Spectrum(1.0f) + s) / (Spectrum(1.0f) - s);
  Spectrum r1 = (baseIor - Spectrum(filmIor)) / (baseIor + Spectrum(filmIor));
  r1 = r1 * r1;
  Spectrum r23 = r1 + (Spectrum(1.0f) - r1) * schlick_weight(cos2);
  float opd = 2.0f * filmIor * thickness * cos2;
  float phi21 = filmIor < 1.0f ? 0.0f : WP_PI;  // phi12 is pi where the film is the thinner medium
  vec4 iors = spectrum_values(baseIor);
  vec4 phi = vec4(phi21) + vec4(iors.x < filmIor ? WP_PI : 0.0f, iors.y < filmIor ? WP_PI : 0.0f, iors.z < filmIor ? WP_PI : 0.0f,
                                iors.w < filmIor ? WP_PI : 0.0f);
  Spectrum r123 = clamp(r23 * r12, Spectrum(1e-5f), Spectrum(0.9999f));
  Spectrum sr123 = sqrt(r123);
  Spectrum rs = r23 * (t121 * t121) / (Spectrum(1.0f) - r123);
  Spectrum intensity = rs + Spectrum(r12);
  Spectrum cm = rs - Spectrum(t121);
  bool spectral = wavelengths >= THIN_FILM_SPECTRAL;
  vec4 lambdas = spectral ? path_wavelengths(wavelengths - THIN_FILM_SPECTRAL) : vec4(1.0f);
  for (int m = 1; m <= 2; ++m) {
    cm = cm * sr123;
    Spectrum sensitivity;
    if (spectral) {
      vec4 phase = vec4(2.0f * WP_PI * float(m) * opd) / lambdas + phi * float(m);
      sensitivity = spectrum_at(vec4(cos(phase.x), cos(phase.y), cos(phase.z), cos(phase.w)));
    } else {
      sensitivity = spectrum_rgb(thin_film_sensitivity(float(m) * opd, vec3(phi.x, phi.y, phi.z) * float(m)));
    }
    intensity += cm * sensitivity * 2.0f;
  }
  return max(intensity, Spectrum(0.0f));
}

#endif  // WP_MICROFACET_GLSL
