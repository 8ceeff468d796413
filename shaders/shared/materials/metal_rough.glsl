// metal_rough.glsl — glTF 2.0's metal-rough material (the specification's
// Appendix B): a GGX specular layer (D, height-correlated G2) over a
// Lambertian base of the base colour for the dielectric part, whose Fresnel
// term is Schlick's with f0 = ((ior - 1) / (ior + 1))^2 (0.04 at ior 1.5),
// mixed by `metallic` with a metal whose Schlick f0 is the base colour:
//   f = (1 - m) [(1 - F_d) base / pi + F_d S] + m F_m S,  S = D G2 / (4 cos_o cos_i),
// both F at wo.h, h the half vector of wo and wi. color is the base colour,
// params at the hit: x alpha (roughness squared, at least GGX_MIN_ALPHA),
// y metallic, z ior (bsdf_at resolves them from the material's factors and
// its metallic-roughness texture). The specular layer is sampled through its
// visible normals, the base by cosine, picked by their estimated
// reflectance at wo. Lobe functions as no_lobe.glsl describes them.
#ifndef WP_METAL_ROUGH_GLSL
#define WP_METAL_ROUGH_GLSL

// The dielectric layer's reflectance at normal incidence, from its ior.
float metal_rough_f0(Lobe l) {
  float r = (l.params.z - 1.0f) / (l.params.z + 1.0f);
  return r * r;
}

// Probability of sampling the specular layer rather than the diffuse base.
float metal_rough_specular_probability(Lobe l, float cosO) {
  float metallic = l.params.y;
  float f0 = metal_rough_f0(l);
  float fd = f0 + (1.0f - f0) * schlick_weight(cosO);
  float specular = (1.0f - metallic) * fd + metallic;
  float diffuse = (1.0f - metallic) * (1.0f - fd) * clamp((l.color.x + l.color.y + l.color.z) * (1.0f / 3.0f), 0.0f, 1.0f);
  return specular + diffuse > 0.0f ? specular / (specular + diffuse) : 1.0f;
}

float metal_rough_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosO = dot(wo, ns);
  if (cosO <= 0.0f || dot(wi, ns) <= 0.0f) return 0.0f;
  float pSpecular = metal_rough_specular_probability(l, cosO);
  return pSpecular * ggx_reflection_pdf(l.params.x, ns, wo, wi) + (1.0f - pSpecular) * lambertian_pdf(l, ns, wo, wi);
}

vec3 metal_rough_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosI = dot(wi, ns);
  if (dot(wo, ns) <= 0.0f || cosI <= 0.0f) return vec3(0.0f);
  float metallic = l.params.y;
  float f0 = metal_rough_f0(l);
  float w = schlick_weight(dot(wo, normalize(wo + wi)));
  float fd = f0 + (1.0f - f0) * w;
  vec3 fm = l.color + (vec3(1.0f) - l.color) * w;
  float specular = ggx_reflection_eval(l.params.x, ns, wo, wi);  // S cos_i
  vec3 dielectric = l.color * ((1.0f - fd) * cosI * WP_INV_PI) + vec3(fd * specular);
  return dielectric * (1.0f - metallic) + fm * (metallic * specular);
}

vec3 metal_rough_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  if (u.z < metal_rough_specular_probability(l, dot(wo, ns))) return ggx_reflection_sample(l.params.x, ns, wo, vec2(u.x, u.y));
  return lambertian_sample(l, ns, wo, u);
}

WP_NO_DELTA_LOBE(metal_rough)

#endif  // WP_METAL_ROUGH_GLSL
