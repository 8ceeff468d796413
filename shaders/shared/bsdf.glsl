// bsdf.glsl — materials as sample / eval / pdf triples in world space.
// Convention: wo points away from the surface towards the previous vertex,
// wi towards the next; n is the normal on wo's side. eval returns f * |cos(wi)|.
#ifndef WP_BSDF_GLSL
#define WP_BSDF_GLSL

bool material_scatters(Material m) {
  return m.info.x != MAT_LIGHT;
}

bool material_emits(Material m) {
  return m.emission.x > 0.0f || m.emission.y > 0.0f || m.emission.z > 0.0f;
}

// f(wo, wi) * |cos theta_i|; zero when wi leaves through the other side.
vec3 bsdf_eval(Material m, vec3 n, vec3 wo, vec3 wi) {
  float c = dot(n, wi);
  if (c <= 0.0f || !material_scatters(m)) return vec3(0.0f);
  return vec3(m.albedo.x, m.albedo.y, m.albedo.z) * (c * WP_INV_PI);
}

float bsdf_pdf(Material m, vec3 n, vec3 wo, vec3 wi) {
  float c = dot(n, wi);
  if (c <= 0.0f || !material_scatters(m)) return 0.0f;
  return c * WP_INV_PI;
}

// Samples wi; returns the weight f * |cos| / pdf (zero when sampling failed) and
// writes the pdf. Lambertian: cosine-weighted hemisphere, weight = albedo.
vec3 bsdf_sample(Material m, vec3 n, vec3 wo, vec2 u, OUT(vec3) wi, OUT(float) pdf) {
  vec3 t;
  vec3 b;
  make_frame(n, t, b);
  vec3 local = square_to_cosine_hemisphere(u);
  wi = frame_to_world(local, t, b, n);
  pdf = square_to_cosine_hemisphere_pdf(local);
  if (pdf <= 0.0f || !material_scatters(m)) {
    pdf = 0.0f;
    return vec3(0.0f);
  }
  return vec3(m.albedo.x, m.albedo.y, m.albedo.z);
}

#endif  // WP_BSDF_GLSL
