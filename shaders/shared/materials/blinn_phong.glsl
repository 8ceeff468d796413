// blinn_phong.glsl — darts' Blinn-Phong: the half vector from a cos^n lobe
// (n = params.x) around the normal, wi the mirror of wo about it. As darts
// defines it, f * cos is the albedo times the sampling density. Lobe
// functions as no_lobe.glsl describes them.
#ifndef WP_BLINN_PHONG_GLSL
#define WP_BLINN_PHONG_GLSL

float blinn_phong_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  vec3 h = normalize(wo + wi);
  float woH = dot(wo, h);
  return woH > 0.0f ? cosine_power_pdf(dot(h, ns), l.params.x) / (4.0f * woH) : 0.0f;
}

Spectrum blinn_phong_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return l.color * blinn_phong_pdf(l, ns, wo, wi);
}

vec3 blinn_phong_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  vec3 t;
  vec3 bt;
  make_frame(ns, t, bt);
  vec3 h = frame_to_world(square_to_cosine_power(vec2(u.x, u.y), l.params.x), t, bt, ns);
  return dot(wo, h) > 0.0f ? reflect_about(wo, h) : vec3(0.0f);
}

WP_NO_DELTA_LOBE(blinn_phong)

#endif  // WP_BLINN_PHONG_GLSL
