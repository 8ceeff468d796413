// metal_rough.glsl — glTF 2.0's metal-rough material (the specification's
// Appendix B) with KHR_materials_transmission: a GGX specular layer (D,
// height-correlated G2) over a base of the base colour for the dielectric
// part, whose Fresnel term is Schlick's with f0 = ((ior - 1) / (ior + 1))^2
// (0.04 at ior 1.5), mixed by `metallic` with a metal whose Schlick f0 is the
// base colour. The dielectric's base is Lambertian, or by the transmission
// factor t a thin-walled specular transmission (the extension without
// KHR_materials_volume): the GGX lobe mirrored through the surface, tinted
// by the base colour:
//   reflection:   f = (1 - m) [(1 - F_d)(1 - t) base / pi + F_d S] + m F_m S,
//   transmission: f = (1 - m)(1 - F_d) t base S(wo, wi'),  wi' = wi mirrored to wo's side,
// S = D G2 / (4 cos_o cos_i), both F at wo.h, h the half vector of wo and
// wi (wi'). The mirrored lobe keeps S's reciprocity: f(wo, wi) = f(wi, wo).
// color is the base colour, params at the hit: x alpha (roughness squared,
// at least GGX_MIN_ALPHA), y metallic, z ior, w transmission (bsdf_at
// resolves them from the material's factors and its metallic-roughness
// texture). The specular layer and the transmission are sampled through the
// visible normals, the diffuse base by cosine, picked by their estimated
// reflectance at wo. Lobe functions as no_lobe.glsl describes them.
#ifndef WP_METAL_ROUGH_GLSL
#define WP_METAL_ROUGH_GLSL

// The dielectric layer's reflectance at normal incidence, from its ior.
float metal_rough_f0(Lobe l) {
  float r = (l.params.z - 1.0f) / (l.params.z + 1.0f);
  return r * r;
}

// Probabilities of sampling the specular layer (x) and the transmission (y)
// rather than the diffuse base, by their estimated reflectance at wo.
vec2 metal_rough_probabilities(Lobe l, float cosO) {
  float metallic = l.params.y;
  float transmission = l.params.w;
  float f0 = metal_rough_f0(l);
  float fd = f0 + (1.0f - f0) * schlick_weight(cosO);
  float specular = (1.0f - metallic) * fd + metallic;
  float base = (1.0f - metallic) * (1.0f - fd) * clamp((l.color.x + l.color.y + l.color.z) * (1.0f / 3.0f), 0.0f, 1.0f);
  float total = specular + base;
  if (!(total > 0.0f)) return vec2(1.0f, 0.0f);
  return vec2(specular, base * transmission) / total;
}

// wi mirrored through the surface of normal ns.
vec3 metal_rough_mirrored(vec3 ns, vec3 wi) {
  return wi - ns * (2.0f * dot(wi, ns));
}

float metal_rough_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosO = dot(wo, ns);
  if (cosO <= 0.0f) return 0.0f;
  vec2 p = metal_rough_probabilities(l, cosO);
  if (dot(wi, ns) < 0.0f) return p.y * ggx_reflection_pdf(l.params.x, ns, wo, metal_rough_mirrored(ns, wi));
  return p.x * ggx_reflection_pdf(l.params.x, ns, wo, wi) + (1.0f - p.x - p.y) * lambertian_pdf(l, ns, wo, wi);
}

vec3 metal_rough_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  float cosI = dot(wi, ns);
  if (dot(wo, ns) <= 0.0f || cosI == 0.0f) return vec3(0.0f);
  float metallic = l.params.y;
  float transmission = l.params.w;
  float f0 = metal_rough_f0(l);
  vec3 wr = cosI > 0.0f ? wi : metal_rough_mirrored(ns, wi);
  float w = schlick_weight(dot(wo, normalize(wo + wr)));
  float fd = f0 + (1.0f - f0) * w;
  float specular = ggx_reflection_eval(l.params.x, ns, wo, wr);  // S |cos_i|
  if (cosI < 0.0f) return l.color * ((1.0f - metallic) * (1.0f - fd) * transmission * specular);
  vec3 fm = l.color + (vec3(1.0f) - l.color) * w;
  vec3 dielectric = l.color * ((1.0f - fd) * (1.0f - transmission) * cosI * WP_INV_PI) + vec3(fd * specular);
  return dielectric * (1.0f - metallic) + fm * (metallic * specular);
}

vec3 metal_rough_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  vec2 p = metal_rough_probabilities(l, dot(wo, ns));
  if (u.z < p.x) return ggx_reflection_sample(l.params.x, ns, wo, vec2(u.x, u.y));
  if (u.z < p.x + p.y) {
    vec3 wr = ggx_reflection_sample(l.params.x, ns, wo, vec2(u.x, u.y));
    return wr == vec3(0.0f) ? wr : metal_rough_mirrored(ns, wr);
  }
  return lambertian_sample(l, ns, wo, u);
}

WP_NO_DELTA_LOBE(metal_rough)

#endif  // WP_METAL_ROUGH_GLSL
