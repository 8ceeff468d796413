// cs184_glass.glsl — Berkeley CS184's smooth glass (Project 3-2, Part 1:
// GlassBSDF, and RefractionBSDF where params.y is 1), as the course's
// skeleton sets it out (src/pathtracer/advanced_bsdf.cpp of its first
// commit; docs/scene-format.md cites the lines): reflection picked with
// Schlick's approximation of the Fresnel reflectance at wo, R = R0 + (1 -
// R0)(1 - cos)^5, R0 = ((1 - ior) / (1 + ior))^2, weighted by the
// `reflectance` (params2.xyz); refraction by Snell's law, weighted by the
// transmittance (the lobe's colour) times eta^2, eta the ratio of the
// indices across it (transmitted over incident): radiance is scaled by
// eta^2 on crossing, unlike `dielectric` (darts). Total internal reflection
// reflects; the refraction-only BSDF absorbs it. params: x ior, y 1 for
// refraction only. Lobe functions as no_lobe.glsl describes them.
#ifndef WP_CS184_GLASS_GLSL
#define WP_CS184_GLASS_GLSL

bool cs184_glass_is_delta(Lobe l) {
  return true;
}

Spectrum cs184_glass_sample_delta(Lobe l, vec3 ns, vec3 ng, vec3 wo, float uPick, OUT(vec3) wi) {
  float ior = l.params.x;
  bool refractionOnly = l.params.y > 0.5f;
  Spectrum reflectance = lobe_spectrum(l, vec3(l.params2.x, l.params2.y, l.params2.z), LOBE_FOURTH_PARAMS2);
  float eta = l.front ? ior : 1.0f / ior;
  float cosO = dot(wo, ns);
  float sin2T = (1.0f - cosO * cosO) / (eta * eta);
  float r0 = (1.0f - ior) / (1.0f + ior);
  r0 *= r0;
  float r = sin2T >= 1.0f ? 1.0f : r0 + (1.0f - r0) * pow(1.0f - cosO, 5.0f);
  if (refractionOnly ? sin2T >= 1.0f : uPick < r) {
    wi = reflect_about(wo, ns);
    return dot(wi, ng) > 0.0f && !refractionOnly ? reflectance : Spectrum(0.0f);
  }
  float cosT = sqrt(max(0.0f, 1.0f - sin2T));
  wi = normalize(ns * (cosO / eta - cosT) - wo / eta);
  return dot(wi, ng) < 0.0f ? l.color * (eta * eta) : Spectrum(0.0f);
}

WP_NO_SMOOTH_LOBE(cs184_glass)

#endif  // WP_CS184_GLASS_GLSL
