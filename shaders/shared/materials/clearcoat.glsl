// clearcoat.glsl — glTF's KHR_materials_clearcoat: a clear GGX coat over a
// base material. The extension mixes the coat's specular lobe with the base
// by the coat's Fresnel reflectance at the view direction,
//   f = (1 - c F_c) f_base + c F_c f_coat,
//   F_c = f0 + (1 - f0) (1 - |wo . n_c|)^5,  f0 = ((ior - 1) / (ior + 1))^2 (0.04),
//   f_coat = D G2 / (4 |cos_o| |cos_i|) about the coat's normal n_c, alpha = coat roughness^2,
// which depends on wo only, so bsdf_at flattens it as a blend: this lobe of
// weight c F_c and the base's lobes of weight 1 - c F_c. This file is the
// coat's lobe: untinted (its colour is white), sampled through the visible
// normals about n_c.
// params.x: alpha (at least GGX_MIN_ALPHA); params2.xyz: n_c, on wo's side
// (bsdf_at resolves both at the hit). The material: its albedo texture is the
// coat factor (red), info.w its roughness (green), params.x its ior
// (glTF: 1.5), children.x the base, children.z the coat's normal map. Lobe functions as no_lobe.glsl
// describes them; ns, the base's normal, is not the coat's.
#ifndef WP_CLEARCOAT_GLSL
#define WP_CLEARCOAT_GLSL

vec3 clearcoat_normal(Lobe l) {
  return vec3(l.params2.x, l.params2.y, l.params2.z);
}

// Its reflectance at normal incidence, from the coat's index of refraction.
float clearcoat_f0(float ior) {
  float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}

// The coat's weight over its base: its factor times its Fresnel reflectance
// at wo (normal-incidence reflectance f0).
float clearcoat_weight(float factor, float f0, float cosO) {
  return factor * (f0 + (1.0f - f0) * schlick_weight(abs(cosO)));
}

float clearcoat_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return ggx_reflection_pdf(l.params.x, clearcoat_normal(l), wo, wi);
}

Spectrum clearcoat_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return l.color * ggx_reflection_eval(l.params.x, clearcoat_normal(l), wo, wi);
}

vec3 clearcoat_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  return ggx_reflection_sample(l.params.x, clearcoat_normal(l), wo, vec2(u.x, u.y));
}

WP_NO_DELTA_LOBE(clearcoat)

#endif  // WP_CLEARCOAT_GLSL
