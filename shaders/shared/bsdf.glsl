// bsdf.glsl — materials as sample / eval / pdf triples in world space.
//
// At a hit, scene.glsl resolves the material (blends flattened, textures looked
// up) into a Bsdf: up to BSDF_MAX_LOBES weighted lobes whose weights sum to 1.
// Lobes are either smooth (they have a density: Lambertian, rough metal, Phong,
// Blinn-Phong) or delta (mirror metal, dielectric): eval and pdf see only the
// smooth lobes, and bsdf_sample reports when it picked a delta lobe.
//
// Conventions: wo points away from the surface towards the previous vertex, wi
// towards the next; ns and ng face wo. eval returns f * |cos(wi)|, sample returns
// f * |cos| / pdf. The darts glossy lobes (metal, Phong, Blinn-Phong) define
// f * cos as albedo times their sampling density, as darts does, so sampling
// them returns exactly the albedo and directions below the surface are absorbed.
#ifndef WP_BSDF_GLSL
#define WP_BSDF_GLSL

#define BSDF_MAX_LOBES 4

struct Bsdf {
  vec3 ns;  // shading normal, on wo's side of the geometric surface
  uint lobeCount;
  vec3 ng;  // geometric normal, on wo's side
  bool front;  // wo is on the front (outer) side: a dielectric is entered, not left
  uint lobeType[BSDF_MAX_LOBES];    // MAT_* of each lobe
  vec3 lobeColor[BSDF_MAX_LOBES];   // albedo (white for the dielectric)
  float lobeParam[BSDF_MAX_LOBES];  // exponent, roughness or ior
  float lobeWeight[BSDF_MAX_LOBES];
};

bool lobe_is_delta(uint type, float param) {
  return type == MAT_DIELECTRIC || (type == MAT_METAL && param <= 0.0f);
}

bool bsdf_has_smooth_lobe(Bsdf b) {
  for (uint i = 0u; i < b.lobeCount; ++i) {
    if (!lobe_is_delta(b.lobeType[i], b.lobeParam[i])) return true;
  }
  return false;
}

bool bsdf_has_delta_lobe(Bsdf b) {
  for (uint i = 0u; i < b.lobeCount; ++i) {
    if (lobe_is_delta(b.lobeType[i], b.lobeParam[i])) return true;
  }
  return false;
}

vec3 reflect_about(vec3 wo, vec3 n) {
  return n * (2.0f * dot(wo, n)) - wo;
}

// Unpolarised Fresnel reflectance of a smooth dielectric boundary. cosI is the
// cosine on the incident side, eta the ratio transmitted-side / incident-side ior.
float fresnel_dielectric(float cosI, float eta) {
  cosI = clamp(cosI, 0.0f, 1.0f);
  float sin2T = (1.0f - cosI * cosI) / (eta * eta);
  if (sin2T >= 1.0f) return 1.0f;  // total internal reflection
  float cosT = sqrt(1.0f - sin2T);
  float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
  float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return 0.5f * (rs * rs + rp * rp);
}

// Density (solid angle) with which smooth lobe `i` samples wi.
float lobe_pdf(Bsdf b, uint i, vec3 wo, vec3 wi) {
  uint type = b.lobeType[i];
  float param = b.lobeParam[i];
  if (type == MAT_LAMBERTIAN) return max(dot(b.ns, wi), 0.0f) * WP_INV_PI;
  if (type == MAT_METAL) return fuzzed_direction_pdf(wi, reflect_about(wo, b.ns), param);
  if (type == MAT_PHONG) return cosine_power_pdf(dot(wi, reflect_about(wo, b.ns)), param);
  if (type == MAT_BLINN_PHONG) {
    vec3 h = normalize(wo + wi);
    float cosH = dot(h, b.ns);
    float woH = dot(wo, h);
    return woH > 0.0f ? cosine_power_pdf(cosH, param) / (4.0f * woH) : 0.0f;
  }
  return 0.0f;  // delta lobes
}

// f * cos of lobe i (smooth lobes only; zero below the surface).
vec3 lobe_eval(Bsdf b, uint i, vec3 wo, vec3 wi) {
  if (b.lobeType[i] == MAT_LAMBERTIAN) return b.lobeColor[i] * (max(dot(b.ns, wi), 0.0f) * WP_INV_PI);
  return b.lobeColor[i] * lobe_pdf(b, i, wo, wi);
}

// Reflection only: both directions on the same side of the geometric and the
// shading surface, so shading normals cannot leak light through a surface.
bool bsdf_reflects(Bsdf b, vec3 wi) {
  return dot(wi, b.ng) > 0.0f && dot(wi, b.ns) > 0.0f;
}

// f(wo, wi) * |cos(wi)| summed over the smooth lobes.
vec3 bsdf_eval(Bsdf b, vec3 wo, vec3 wi) {
  vec3 f = vec3(0.0f);
  if (!bsdf_reflects(b, wi)) return f;
  for (uint i = 0u; i < b.lobeCount; ++i) {
    if (!lobe_is_delta(b.lobeType[i], b.lobeParam[i])) f += lobe_eval(b, i, wo, wi) * b.lobeWeight[i];
  }
  return f;
}

// Density with which bsdf_sample produces wi through its smooth lobes.
float bsdf_pdf(Bsdf b, vec3 wo, vec3 wi) {
  float pdf = 0.0f;
  if (!bsdf_reflects(b, wi)) return pdf;
  for (uint i = 0u; i < b.lobeCount; ++i) {
    if (!lobe_is_delta(b.lobeType[i], b.lobeParam[i])) pdf += lobe_pdf(b, i, wo, wi) * b.lobeWeight[i];
  }
  return pdf;
}

// Direction from smooth lobe i, or a zero vector when the lobe produced none.
vec3 lobe_sample(Bsdf b, uint i, vec3 wo, vec3 u) {
  uint type = b.lobeType[i];
  float param = b.lobeParam[i];
  vec3 t;
  vec3 bt;
  if (type == MAT_LAMBERTIAN) {
    make_frame(b.ns, t, bt);
    return frame_to_world(square_to_cosine_hemisphere(vec2(u.x, u.y)), t, bt, b.ns);
  }
  if (type == MAT_METAL) {
    vec3 d = reflect_about(wo, b.ns) + square_to_uniform_ball(u) * param;
    float len = length(d);
    return len > 0.0f ? d / len : vec3(0.0f);
  }
  if (type == MAT_PHONG) {
    vec3 r = reflect_about(wo, b.ns);
    make_frame(r, t, bt);
    return frame_to_world(square_to_cosine_power(vec2(u.x, u.y), param), t, bt, r);
  }
  // Blinn-Phong: a half vector around the normal, then the mirror of wo about it.
  make_frame(b.ns, t, bt);
  vec3 h = frame_to_world(square_to_cosine_power(vec2(u.x, u.y), param), t, bt, b.ns);
  return dot(wo, h) > 0.0f ? reflect_about(wo, h) : vec3(0.0f);
}

// Samples wi. Returns f * |cos| / pdf (zero when the sample is absorbed), writes
// the pdf (of the smooth lobes' mixture) and whether a delta lobe was taken, in
// which case pdf is 0 and MIS does not apply. u.z picks the lobe and is then
// reused (rescaled) for the dielectric's choice between reflection and refraction.
vec3 bsdf_sample(Bsdf b, vec3 wo, vec4 u, OUT(vec3) wi, OUT(float) pdf, OUT(bool) isDelta) {
  wi = vec3(0.0f);
  pdf = 0.0f;
  isDelta = false;
  if (b.lobeCount == 0u) return vec3(0.0f);
  uint k = b.lobeCount - 1u;
  float uPick = u.z;
  for (uint i = 0u; i + 1u < b.lobeCount; ++i) {
    if (uPick < b.lobeWeight[i]) {
      k = i;
      break;
    }
    uPick -= b.lobeWeight[i];
  }
  uPick = clamp(uPick / b.lobeWeight[k], 0.0f, 0.99999994f);
  uint type = b.lobeType[k];
  if (type == MAT_DIELECTRIC) {
    isDelta = true;
    float eta = b.front ? b.lobeParam[k] : 1.0f / b.lobeParam[k];
    float cosI = dot(wo, b.ns);
    float f = fresnel_dielectric(cosI, eta);
    if (uPick < f) {
      wi = reflect_about(wo, b.ns);
      if (dot(wi, b.ng) <= 0.0f) return vec3(0.0f);
    } else {
      float sin2T = (1.0f - cosI * cosI) / (eta * eta);
      float cosT = sqrt(max(0.0f, 1.0f - sin2T));
      wi = normalize(b.ns * (cosI / eta - cosT) - wo / eta);
      if (dot(wi, b.ng) >= 0.0f) return vec3(0.0f);
    }
    // Choosing reflection with probability F cancels F: white either way
    // (radiance is not scaled by eta^2, as in darts).
    return b.lobeColor[k];
  }
  if (type == MAT_METAL && b.lobeParam[k] <= 0.0f) {
    isDelta = true;
    wi = reflect_about(wo, b.ns);
    return dot(wi, b.ng) > 0.0f ? b.lobeColor[k] : vec3(0.0f);
  }
  wi = lobe_sample(b, k, wo, vec3(u.x, u.y, u.w));
  pdf = bsdf_pdf(b, wo, wi);
  if (pdf <= 0.0f) {
    pdf = 0.0f;
    return vec3(0.0f);
  }
  return bsdf_eval(b, wo, wi) / pdf;
}

#endif  // WP_BSDF_GLSL
