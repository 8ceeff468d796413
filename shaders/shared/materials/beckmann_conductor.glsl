// beckmann_conductor.glsl — Berkeley CS184's microfacet conductor (Project
// 3-2), as the course's skeleton defines it (src/pathtracer/bsdf.h and
// advanced_bsdf.cpp of its first commit; docs/scene-format.md cites the
// lines):
//   f = F(wi) G(wo, wi) D(h) / (4 (n.wo)(n.wi)),
// D Beckmann's distribution of width alpha; G = 1 / (1 + L(wo) + L(wi)) with
// the skeleton's L(w) = (erf(a) - 1 + exp(-a^2) / (a pi)) / 2, a =
// 1 / (alpha tan(theta)), where Smith's Beckmann term has sqrt(pi) for pi:
// with pi, L can fall below 0 and G rise above 1, and the lobe reflects up
// to about 1.4 times what it receives (Bsdf.SmoothLobesConserveEnergy...).
// params2.w picks: 1 the skeleton's L (what every student's image shows),
// 0 Smith's; F the
// course's air-conductor Fresnel approximation at wi's angle to the macro
// normal, per channel from eta and k. The half vector is sampled as the
// course samples it: theta_h = atan(sqrt(-alpha^2 ln(1 - r1))), phi_h =
// 2 pi r2, so its density is D(h) cos(theta_h); directions reflected below
// the surface are absorbed. color tints f (white in CS184's files).
// params: x alpha (> 0), yzw eta; params2: xyz k, w 1 for the skeleton's
// Lambda. Lobe functions as
// no_lobe.glsl describes them.
#ifndef WP_BECKMANN_CONDUCTOR_GLSL
#define WP_BECKMANN_CONDUCTOR_GLSL

// erf(x) for x >= 0 (Abramowitz and Stegun 7.1.26, |error| < 1.5e-7);
// GLSL has none.
float erf_positive(float x) {
  float t = 1.0f / (1.0f + 0.3275911f * x);
  float poly = t * (0.254829592f + t * (-0.284496736f + t * (1.421413741f + t * (-1.453152027f + t * 1.061405429f))));
  return 1.0f - poly * exp(-x * x);
}

float beckmann_d(float alpha, float cosH) {
  if (cosH <= 0.0f) return 0.0f;
  float c2 = cosH * cosH;
  float tan2 = (1.0f - c2) / c2;
  return exp(-tan2 / (alpha * alpha)) / (WP_PI * alpha * alpha * c2 * c2);
}

// Smith's Lambda for Beckmann at the cosine c of w to the macro normal (its
// angle clamped as the skeleton clamps it); the skeleton's, with pi for
// sqrt(pi), where `skeleton`.
float cs184_lambda(float alpha, float c, bool skeleton) {
  float theta = acos(clamp(c, -1.0f + 1e-5f, 1.0f - 1e-5f));
  float a = 1.0f / (alpha * tan(theta));
  return 0.5f * (erf_positive(a) - 1.0f + exp(-a * a) / (a * (skeleton ? WP_PI : sqrt(WP_PI))));
}

// The course's Fresnel reflectance of air over a conductor eta + i k, at
// cosine c.
Spectrum cs184_fresnel(Spectrum eta, Spectrum k, float c) {
  Spectrum t = eta * eta + k * k;
  float c2 = c * c;
  Spectrum rs = (t - eta * (2.0f * c) + Spectrum(c2)) / (t + eta * (2.0f * c) + Spectrum(c2));
  Spectrum rp = (t * c2 - eta * (2.0f * c) + Spectrum(1.0f)) / (t * c2 + eta * (2.0f * c) + Spectrum(1.0f));
  return (rs + rp) * 0.5f;
}

float beckmann_conductor_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosI = dot(wi, ns);
  if (dot(wo, ns) <= 0.0f || cosI <= 0.0f) return 0.0f;
  vec3 h = normalize(wo + wi);
  float cosH = dot(h, ns);
  return beckmann_d(l.params.x, cosH) * cosH / (4.0f * dot(wi, h));
}

Spectrum beckmann_conductor_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosO = dot(wo, ns);
  float cosI = dot(wi, ns);
  if (cosO <= 0.0f || cosI <= 0.0f) return Spectrum(0.0f);
  float alpha = l.params.x;
  vec3 h = normalize(wo + wi);
  // (params2.w above CONDUCTOR_NAMED names a metal: kinds.glsl.)
  bool skeleton = l.params2.w - CONDUCTOR_NAMED * floor(l.params2.w / CONDUCTOR_NAMED) > 0.5f;
  float g = 1.0f / (1.0f + cs184_lambda(alpha, cosI, skeleton) + cs184_lambda(alpha, cosO, skeleton));
  Spectrum fresnel = cs184_fresnel(lobe_spectrum(l, vec3(l.params.y, l.params.z, l.params.w), LOBE_FOURTH_ETA),
                                    lobe_spectrum(l, vec3(l.params2.x, l.params2.y, l.params2.z), LOBE_FOURTH_K), cosI);
  return l.color * fresnel * (g * beckmann_d(alpha, dot(h, ns)) / (4.0f * cosO));  // f cos_i
}

vec3 beckmann_conductor_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  float alpha = l.params.x;
  float thetaH = atan(sqrt(-alpha * alpha * log(1.0f - u.x)));
  float phiH = 2.0f * WP_PI * u.y;
  vec3 t;
  vec3 bt;
  make_frame(ns, t, bt);
  vec3 h = frame_to_world(vec3(sin(thetaH) * cos(phiH), sin(thetaH) * sin(phiH), cos(thetaH)), t, bt, ns);
  vec3 wi = reflect_about(wo, h);
  return dot(wi, ns) > 0.0f && dot(wo, ns) > 0.0f ? wi : vec3(0.0f);
}

WP_NO_DELTA_LOBE(beckmann_conductor)

#endif  // WP_BECKMANN_CONDUCTOR_GLSL
