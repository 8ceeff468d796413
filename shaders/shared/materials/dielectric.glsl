// dielectric.glsl — smooth glass of index `ior` (params.x): Fresnel reflection
// and refraction, both delta. Lobe functions as no_lobe.glsl describes them.
#ifndef WP_DIELECTRIC_GLSL
#define WP_DIELECTRIC_GLSL

bool dielectric_is_delta(Lobe l) {
  return true;
}

// Reflects with probability F (uPick < F), else refracts.
Spectrum dielectric_sample_delta(Lobe l, vec3 ns, vec3 ng, vec3 wo, float uPick, OUT(vec3) wi) {
  float eta = l.front ? l.params.x : 1.0f / l.params.x;
  float cosI = dot(wo, ns);
  float f = fresnel_dielectric(cosI, eta);
  if (uPick < f) {
    wi = reflect_about(wo, ns);
    if (dot(wi, ng) <= 0.0f) return Spectrum(0.0f);
  } else {
    float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    float cosT = sqrt(max(0.0f, 1.0f - sin2T));
    wi = normalize(ns * (cosI / eta - cosT) - wo / eta);
    if (dot(wi, ng) >= 0.0f) return Spectrum(0.0f);
  }
  // Choosing reflection with probability F cancels F: white either way
  // (radiance is not scaled by eta^2, as in darts).
  return l.color;
}

WP_NO_SMOOTH_LOBE(dielectric)

#endif  // WP_DIELECTRIC_GLSL
