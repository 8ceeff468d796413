// rough_conductor.glsl — a metal as a GGX microfacet conductor: the Fresnel
// reflectance of its complex index of refraction eta + i k (per channel)
// times GGX's D and height-correlated G2, times a tint (the albedo texture,
// white unless given). params: x alpha, yzw eta; params2: xyz k. alpha 0 is
// a perfect mirror with the same Fresnel term (a delta lobe). Sampled
// through the visible normals, so a sample's weight is F G2 / G1(wo).
// Lobe functions as no_lobe.glsl describes them.
#ifndef WP_ROUGH_CONDUCTOR_GLSL
#define WP_ROUGH_CONDUCTOR_GLSL

Spectrum rough_conductor_fresnel(Lobe l, float cosI) {
  return fresnel_conductor(cosI, lobe_spectrum(l, vec3(l.params.y, l.params.z, l.params.w), LOBE_FOURTH_ETA),
                           lobe_spectrum(l, vec3(l.params2.x, l.params2.y, l.params2.z), LOBE_FOURTH_K));
}

bool rough_conductor_is_delta(Lobe l) {
  return l.params.x <= 0.0f;
}

float rough_conductor_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return ggx_reflection_pdf(l.params.x, ns, wo, wi);
}

Spectrum rough_conductor_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float specular = ggx_reflection_eval(l.params.x, ns, wo, wi);
  return specular > 0.0f ? l.color * rough_conductor_fresnel(l, dot(wo, normalize(wo + wi))) * specular : Spectrum(0.0f);
}

vec3 rough_conductor_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  return ggx_reflection_sample(l.params.x, ns, wo, vec2(u.x, u.y));
}

Spectrum rough_conductor_sample_delta(Lobe l, vec3 ns, vec3 ng, vec3 wo, float uPick, OUT(vec3) wi) {
  wi = reflect_about(wo, ns);
  return dot(wi, ng) > 0.0f ? l.color * rough_conductor_fresnel(l, dot(wo, ns)) : Spectrum(0.0f);
}

#endif  // WP_ROUGH_CONDUCTOR_GLSL
