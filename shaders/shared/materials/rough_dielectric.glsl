// rough_dielectric.glsl — rough glass: a GGX microfacet boundary of index
// `ior` (params.x; the outside is 1) with width alpha (params.y) that
// reflects and refracts (Walter et al., "Microfacet Models for Refraction
// through Rough Surfaces", EGSR 2007), tinted by the albedo texture (white
// unless given). alpha 0 is the smooth dielectric (dielectric.glsl).
//
// A visible normal h is sampled; the boundary reflects about it with
// probability F(wo.h) and refracts otherwise, so a sample's weight is
// G2 / G1(wo). As darts' smooth dielectric does, radiance is not scaled by
// eta^2 on crossing: f here is the radiance BTDF times eta^2, eta the ratio
// of the indices on wi's and on wo's side. (Through a closed object the two
// factors cancel.) Lobe functions as no_lobe.glsl describes them.
#ifndef WP_ROUGH_DIELECTRIC_GLSL
#define WP_ROUGH_DIELECTRIC_GLSL

bool rough_dielectric_is_delta(Lobe l) {
  return l.params.y <= 0.0f;
}

// The ratio of indices, wi's side over wo's, when wi is transmitted.
float rough_dielectric_eta(Lobe l) {
  return l.front ? l.params.x : 1.0f / l.params.x;
}

// The microfacet normal that takes wo to wi (facing ns), and whether one
// does: reflection about it, or refraction through it with both directions
// on the sides of it that the two sides of the surface require.
bool rough_dielectric_half_vector(Lobe l, vec3 ns, vec3 wo, vec3 wi, OUT(vec3) h) {
  bool reflection = dot(wi, ns) > 0.0f;
  h = reflection ? wo + wi : wo + wi * rough_dielectric_eta(l);
  float len = length(h);
  if (len <= 0.0f) return false;
  h = h / len;
  if (dot(h, ns) < 0.0f) h = -h;
  return dot(wo, h) > 0.0f && (reflection ? dot(wi, h) > 0.0f : dot(wi, h) < 0.0f);
}

float rough_dielectric_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosO = dot(wo, ns);
  vec3 h;
  if (cosO <= 0.0f || !rough_dielectric_half_vector(l, ns, wo, wi, h)) return 0.0f;
  float eta = rough_dielectric_eta(l);
  float woH = dot(wo, h);
  float wiH = dot(wi, h);
  float pdfH = ggx_visible_pdf(wo, h, ns, l.params.y);
  float f = fresnel_dielectric(woH, eta);
  if (wiH > 0.0f) return f * pdfH / (4.0f * woH);
  float denom = woH + eta * wiH;
  return (1.0f - f) * pdfH * eta * eta * abs(wiH) / (denom * denom);
}

Spectrum rough_dielectric_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosO = dot(wo, ns);
  vec3 h;
  if (cosO <= 0.0f || !rough_dielectric_half_vector(l, ns, wo, wi, h)) return Spectrum(0.0f);
  float alpha = l.params.y;
  float eta = rough_dielectric_eta(l);
  float woH = dot(wo, h);
  float wiH = dot(wi, h);
  float cosI = abs(dot(wi, ns));
  float dg = ggx_d(h, ns, alpha) * ggx_g2(cosO, cosI, alpha);
  float f = fresnel_dielectric(woH, eta);
  if (wiH > 0.0f) return l.color * (f * dg / (4.0f * cosO));
  float denom = woH + eta * wiH;
  return l.color * ((1.0f - f) * dg * eta * eta * woH * abs(wiH) / (cosO * denom * denom));
}

vec3 rough_dielectric_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  vec3 h = ggx_visible_normal(l.params.y, ns, wo, vec2(u.x, u.y));
  if (dot(h, ns) <= 0.0f) return vec3(0.0f);
  float eta = rough_dielectric_eta(l);
  float woH = dot(wo, h);
  vec3 wi;
  if (u.z < fresnel_dielectric(woH, eta)) {  // 1 under total internal reflection
    wi = reflect_about(wo, h);
    return dot(wi, ns) > 0.0f ? wi : vec3(0.0f);
  }
  float cosT = sqrt(max(0.0f, 1.0f - (1.0f - woH * woH) / (eta * eta)));
  wi = normalize(h * (woH / eta - cosT) - wo / eta);
  return dot(wi, ns) < 0.0f ? wi : vec3(0.0f);
}

Spectrum rough_dielectric_sample_delta(Lobe l, vec3 ns, vec3 ng, vec3 wo, float uPick, OUT(vec3) wi) {
  return dielectric_sample_delta(l, ns, ng, wo, uPick, wi);
}

#endif  // WP_ROUGH_DIELECTRIC_GLSL
