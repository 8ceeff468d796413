// lambertian.glsl — the ideal diffuse lobe, cosine-sampled. Lobe functions
// as no_lobe.glsl describes them.
#ifndef WP_LAMBERTIAN_GLSL
#define WP_LAMBERTIAN_GLSL

float lambertian_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return max(dot(ns, wi), 0.0f) * WP_INV_PI;
}

Spectrum lambertian_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return l.color * (max(dot(ns, wi), 0.0f) * WP_INV_PI);
}

vec3 lambertian_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  vec3 t;
  vec3 bt;
  make_frame(ns, t, bt);
  return frame_to_world(square_to_cosine_hemisphere(vec2(u.x, u.y)), t, bt, ns);
}

WP_NO_DELTA_LOBE(lambertian)

#endif  // WP_LAMBERTIAN_GLSL
