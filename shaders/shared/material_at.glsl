// material_at.glsl — the material at a surface point: the radiance it emits,
// and its BSDF (bsdf.glsl) with textures looked up and blends flattened.
#ifndef WP_MATERIAL_AT_GLSL
#define WP_MATERIAL_AT_GLSL

// Radiance the surface emits towards wo (front side only). Emission is
// nearly always one colour: a scene without FEATURE_EMISSION_TEXTURES reads
// it and spares its kernels the copies of texture_eval that shade inlines
// here (the hit's and each light sample's), which lavapipe would run for
// every path.
vec3 emitted_radiance(SurfaceHit s, vec3 wo) {
  uint tex = load_material(s.material).info.z;
  if (tex == WP_INVALID || dot(s.ng, wo) <= 0.0f) return vec3(0.0f);
  if (!FEATURE_COMPILED(FEATURE_EMISSION_TEXTURES)) {
    vec4 c = load_texture(tex).color0;
    return vec3(c.x, c.y, c.z);
  }
  return texture_eval(tex, s.uv, s.p);
}

// The lobe a non-blend material contributes, with its colour and weight.
// Parameters are the material's, except metal-rough's, which its
// metallic-roughness texture scales (glTF: roughness in G, metallic in B).
void bsdf_set_lobe(INOUT(Bsdf) b, uint k, Material m, vec3 color, float w, SurfaceHit s) {
  b.lobeType[k] = m.info.x;
  b.lobeColor[k] = color;
  b.lobeWeight[k] = w;
  vec4 params = m.params;
  if (MATERIAL_COMPILED(MAT_METAL_ROUGH) && m.info.x == MAT_METAL_ROUGH) {
    vec3 mr = m.info.w != WP_INVALID ? texture_eval(m.info.w, s.uv, s.p) : vec3(1.0f);
    float roughness = clamp(m.params.x * mr.y, 0.0f, 1.0f);
    params = vec4(max(roughness * roughness, GGX_MIN_ALPHA), clamp(m.params.y * mr.z, 0.0f, 1.0f), m.params.z, 0.0f);
  }
  bsdf_set_params(b, k, params, m.params2);
}

// Whether a material's step of bsdf_at looks up no texture: the dielectric
// is white, a light adds no lobe, and a Fresnel blend computes its amount.
bool material_needs_no_texture(Material m) {
  if (MATERIAL_COMPILED(MAT_DIELECTRIC) && m.info.x == MAT_DIELECTRIC) return true;
  if (m.info.x == MAT_LIGHT) return true;
  return MATERIAL_COMPILED(MAT_BLEND) && TEXTURE_COMPILED(TEX_FRESNEL) && m.info.x == MAT_BLEND &&
         (load_texture(m.info.w).info.x & TEX_TYPE_MASK) == TEX_FRESNEL;
}

// The BSDF at s seen from wo: textures looked up, blends flattened into
// weighted lobes (depth-first, bounded: the loader allows at most
// BSDF_MAX_LOBES leaves per material).
Bsdf bsdf_at(SurfaceHit s, vec3 wo) {
  Bsdf b;
  b.front = dot(s.ng, wo) >= 0.0f;
  b.ng = b.front ? s.ng : -s.ng;
  b.ns = b.front ? s.ns : -s.ns;
  b.lobeCount = 0u;
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    b.lobeType[i] = MAT_LAMBERTIAN;
    b.lobeColor[i] = vec3(0.0f);
    bsdf_set_params(b, i, vec4(0.0f), vec4(0.0f));
    b.lobeWeight[i] = 0.0f;
  }
  Material m = load_material(s.material);
  if (m.info.x == MAT_LIGHT) return b;  // emits, does not scatter (never compiled out: one comparison)
  if (!MATERIAL_COMPILED(MAT_BLEND)) {  // one lobe
    vec3 color = material_needs_no_texture(m) ? vec3(1.0f) : texture_eval(m.info.y, s.uv, s.p);
    bsdf_set_lobe(b, 0u, m, color, 1.0f, s);
    b.lobeCount = 1u;
    return b;
  }
  // Scenes with blends take every material through the loop, a plain one in
  // one step. Each step looks up one texture, a blend's amount or a lobe's
  // colour, so one copy of texture_eval serves both: lavapipe runs every
  // copy, masked, for every SIMD group, and a separate path for plain
  // materials ran one more.
  uint stackMaterial[BSDF_MAX_LOBES];
  float stackWeight[BSDF_MAX_LOBES];
  stackMaterial[0] = s.material;
  stackWeight[0] = 1.0f;
  uint sp = 1u;
  float total = 0.0f;
  for (uint iter = 0u; iter < 2u * BSDF_MAX_LOBES && sp > 0u; ++iter) {
    sp -= 1u;
    m = load_material(stackMaterial[sp]);
    float w = stackWeight[sp];
    bool blend = m.info.x == MAT_BLEND;
    bool untextured = material_needs_no_texture(m);
    vec3 color = untextured ? vec3(1.0f) : texture_eval(blend ? m.info.w : m.info.y, s.uv, s.p);
    if (blend) {
      // The amount: a texture's mean, or the Fresnel reflectance at the hit.
      float ior = untextured ? load_texture(m.info.w).color0.x : 1.0f;
      float amount = untextured ? fresnel_dielectric(abs(dot(wo, s.ns)), b.front ? ior : 1.0f / ior)
                                : clamp((color.x + color.y + color.z) * (1.0f / 3.0f), 0.0f, 1.0f);
      if (sp + 2u <= BSDF_MAX_LOBES) {
        stackMaterial[sp] = m.children.y;
        stackWeight[sp] = w * amount;
        stackMaterial[sp + 1u] = m.children.x;
        stackWeight[sp + 1u] = w * (1.0f - amount);
        sp += 2u;
      }
      continue;
    }
    if (m.info.x == MAT_LIGHT || w <= 0.0f || b.lobeCount >= BSDF_MAX_LOBES) continue;
    bsdf_set_lobe(b, b.lobeCount, m, color, w, s);
    b.lobeCount += 1u;
    total += w;
  }
  // Weights are sampling probabilities: normalise them and move their sum into
  // the colours, so f is unchanged.
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    if (i < b.lobeCount) {
      b.lobeWeight[i] /= total;
      b.lobeColor[i] *= total;
    }
  }
  return b;
}

#endif  // WP_MATERIAL_AT_GLSL
