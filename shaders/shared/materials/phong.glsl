// phong.glsl — darts' Phong: a cos^n lobe (n = params.x) around the mirror
// direction. As darts defines it, f * cos is the albedo times the sampling
// density. Lobe functions as no_lobe.glsl describes them.
#ifndef WP_PHONG_GLSL
#define WP_PHONG_GLSL

float phong_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return cosine_power_pdf(dot(wi, reflect_about(wo, ns)), l.params.x);
}

Spectrum phong_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return l.color * phong_pdf(l, ns, wo, wi);
}

vec3 phong_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  vec3 r = reflect_about(wo, ns);
  vec3 t;
  vec3 bt;
  make_frame(r, t, bt);
  return frame_to_world(square_to_cosine_power(vec2(u.x, u.y), l.params.x), t, bt, r);
}

WP_NO_DELTA_LOBE(phong)

#endif  // WP_PHONG_GLSL
