// sheen.glsl — glTF's KHR_materials_sheen: the "Charlie" sheen of Conty
// Estevez and Kulla (2017), a back-scattering layer of fibres over a base
// material, as the extension defines it:
//   f_sheen = sheenColor D(h) G / (4 cos_o cos_i),
//   D = (2 + 1/a) sin(theta_h)^(1/a) / (2 pi),   a = sheenRoughness^2,
//   G = 1 / (1 + Lambda(cos_o) + Lambda(cos_i)), Lambda their fitted form.
// The layer's weight over its base is albedo scaling by the directional
// albedo E of this lobe (sheen_albedo.glsl, a table computed by
// scripts/make-sheen-table.py): the base is scaled by
// 1 - max3(sheenColor) max(E(cos_o), E(cos_i)), which bsdf_at and
// bsdf_eval apply (material_at.glsl, bsdf.glsl). Where E exceeds 1, see
// sheen_albedo_bounded. Cosine-sampled: the lobe is
// broad, peaked towards grazing, and a cosine density is exact.
// params.x: sheen roughness, at least SHEEN_MIN_ROUGHNESS (bsdf_at).
// Lobe functions as no_lobe.glsl describes them.
#ifndef WP_SHEEN_GLSL
#define WP_SHEEN_GLSL

// Entry k of the sheen's albedo table (sheen_albedo.glsl): the host's copy
// in C++, the float tables in the kernels.
#ifdef __cplusplus
float sheen_table(int k) {
  return SHEEN_ALBEDO[k];
}
#else
float sheen_table(int k) {
  return texelFetch(floatTables, FLOAT_TABLE_SHEEN + k).x;
}
#endif

// E at (cos_o, r), bilinear between the table's entries.
float sheen_albedo(float cosO, float roughness) {
  float x = clamp(cosO, 0.0f, 1.0f) * float(SHEEN_TABLE_SIZE - 1);
  float y = clamp(roughness, 0.0f, 1.0f) * float(SHEEN_TABLE_SIZE - 1);
  int i = min(int(x), SHEEN_TABLE_SIZE - 2);
  int j = min(int(y), SHEEN_TABLE_SIZE - 2);
  float fx = x - float(i);
  float fy = y - float(j);
  int k = j * SHEEN_TABLE_SIZE + i;
  float lo = sheen_table(k) + (sheen_table(k + 1) - sheen_table(k)) * fx;
  float hi = sheen_table(k + SHEEN_TABLE_SIZE) + (sheen_table(k + SHEEN_TABLE_SIZE + 1) - sheen_table(k + SHEEN_TABLE_SIZE)) * fx;
  return lo + (hi - lo) * fy;
}

// Conty Estevez and Kulla's fit of the exponent in Lambda.
float sheen_l(float x, float a) {
  float t = (1.0f - a) * (1.0f - a);
  float fa = 21.5473f + (25.3245f - 21.5473f) * t;
  float fb = 3.82987f + (3.32435f - 3.82987f) * t;
  float fc = 0.19823f + (0.16801f - 0.19823f) * t;
  float fd = -1.97760f + (-1.27393f + 1.97760f) * t;
  float fe = -4.32054f + (-4.85967f + 4.32054f) * t;
  return fa / (1.0f + fb * pow(x, fc)) + fd * x + fe;
}

float sheen_lambda(float c, float a) {
  return c < 0.5f ? exp(sheen_l(c, a)) : exp(2.0f * sheen_l(0.5f, a) - sheen_l(1.0f - c, a));
}

// E bounded by 1. The extension's lobe reflects more than it receives at
// grazing angles for small roughnesses (E reaches 2.9 at cos_o -> 0, r = 0.07;
// above 1 for cos_o below about 0.06): this lobe divides it by
// max(1, E(cos_o), E(cos_i)), which keeps it reciprocal and its albedo at
// most 1, and changes nothing where E <= 1.
float sheen_albedo_bounded(float cosO, float roughness) {
  return min(sheen_albedo(cosO, roughness), 1.0f);
}

// f * cos(wi) for a white sheen colour.
float sheen_reflectance(float roughness, vec3 ns, vec3 wo, vec3 wi) {
  float cosO = dot(wo, ns);
  float cosI = dot(wi, ns);
  if (cosO <= 0.0f || cosI <= 0.0f) return 0.0f;
  float a = roughness * roughness;
  vec3 h = normalize(wo + wi);
  vec3 s = cross(h, ns);
  float sin2 = min(dot(s, s), 1.0f);
  float d = (2.0f + 1.0f / a) * pow(sin2, 0.5f / a) * (0.5f * WP_INV_PI);
  float bound = max(1.0f, max(sheen_albedo(cosO, roughness), sheen_albedo(cosI, roughness)));
  return d / ((1.0f + sheen_lambda(cosO, a) + sheen_lambda(cosI, a)) * 4.0f * cosO * bound);
}

float sheen_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return lambertian_pdf(l, ns, wo, wi);
}

Spectrum sheen_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  return l.color * sheen_reflectance(l.params.x, ns, wo, wi);
}

vec3 sheen_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) {
  return lambertian_sample(l, ns, wo, u);
}

WP_NO_DELTA_LOBE(sheen)

#endif  // WP_SHEEN_GLSL
