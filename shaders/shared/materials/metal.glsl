// metal.glsl — darts' metal: the mirror direction plus `roughness` (params.x)
// times a uniform point of the unit sphere, normalised; a delta mirror when
// roughness is 0. (The skeleton's comment speaks of random_in_unit_sphere,
// but the course's reference histograms, metal*-sampled-ref.png, show the
// rim-bright lobe of points on the sphere, not the centre-peaked one of the
// ball: docs/scene-format.md.) As darts
// defines it, f * cos is the albedo times the sampling density, so sampling
// returns exactly the albedo and directions below the surface are absorbed.
// Lobe functions as no_lobe.glsl describes them.
#ifndef WP_METAL_GLSL
#define WP_METAL_GLSL

bool metal_is_delta(Lobe l) {
  return l.params.x <= 0.0f;
}

float metal_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return fuzzed_direction_pdf(wi, reflect_about(wo, ns), l.params.x);
}

Spectrum metal_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return l.color * metal_pdf(l, ns, wo, wi);
}

vec3 metal_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  vec3 d = reflect_about(wo, ns) + square_to_uniform_sphere(vec2(u.x, u.y)) * l.params.x;
  float len = length(d);
  return len > 0.0f ? d / len : vec3(0.0f);
}

Spectrum metal_sample_delta(Lobe l, vec3 ns, vec3 ng, vec3 wo, float uPick, OUT(vec3) wi) {
  wi = reflect_about(wo, ns);
  return dot(wi, ng) > 0.0f ? l.color : Spectrum(0.0f);
}

#endif  // WP_METAL_GLSL
