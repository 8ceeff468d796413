// material_at.glsl — the material at a surface point: the radiance it emits,
// and its BSDF (bsdf.glsl) with textures looked up and blends flattened.
#ifndef WP_MATERIAL_AT_GLSL
#define WP_MATERIAL_AT_GLSL

// Radiance the surface emits towards wo (front side only). Emission is
// nearly always one colour: a scene without FEATURE_EMISSION_TEXTURES reads
// it and spares its kernels the copies of texture_eval that shade inlines
// here (the hit's and each light sample's), which lavapipe would run for
// every path.
//
// A light material with params.x set (FEATURE_COSINE_EMISSION) emits its
// radiance times the cosine towards wo, from the front only: CS184 3-2's
// EmissionBSDF(radiance, direction) (its bsdf.h:274-278), which that
// skeleton gives the quad of every area light.
vec3 emitted_radiance(SurfaceHit s, vec3 wo) {
  Material m = load_material(s.material);
  uint tex = m.info.z;
  // Seen from the front only, or from both sides under CS184's conventions.
  if (tex == WP_INVALID || (dot(s.ng, wo) <= 0.0f && (scene.counts.w & SCENE_FLAG_CS184) == 0u)) return vec3(0.0f);
  float scale = FEATURE_COMPILED(FEATURE_COSINE_EMISSION) && m.info.x == MAT_LIGHT && m.params.x != 0.0f ? max(dot(s.ng, wo), 0.0f) : 1.0f;
  // Under a clear coat, what the coat does not reflect (KHR_materials_clearcoat's
  // coated_emission; at the interpolated normal, not a coat normal map's).
  if (MATERIAL_COMPILED(MAT_CLEARCOAT) && m.info.x == MAT_CLEARCOAT)
    scale = 1.0f - clearcoat_weight(texture_eval(m.info.y, s.uv, s.p).x, clearcoat_f0(m.params.x), dot(s.ns, wo));
  if (!FEATURE_COMPILED(FEATURE_EMISSION_TEXTURES)) {
    vec4 c = load_texture(tex).color0;
    return vec3(c.x, c.y, c.z) * scale;
  }
  return texture_eval(tex, s.uv, s.p) * scale;
}

// Each kind's resolution at the hit, which looks up textures: the second
// half of its materials/ file (bsdf.glsl included the first).
#define WP_MATERIAL_AT_HIT
#include "materials/metal_rough.glsl"

// The lobe a non-blend material contributes, with its colour and weight, and
// its parameters: the material's, or those its kind resolves at the hit
// (stored once: on lavapipe each copy of the stores costs every path).
void bsdf_set_lobe(INOUT(Bsdf) b, uint k, Material m, vec3 color, float w, SurfaceHit s) {
  b.lobeType[k] = m.info.x;
  b.lobeColor[k] = spectrum_rgb(color);
  b.lobeWeight[k] = w;
  Lobe l = lobe_with_params(m.params, m.params2);
  float dispersion = 0.0f;
  if (MATERIAL_COMPILED(MAT_METAL_ROUGH) && m.info.x == MAT_METAL_ROUGH) metal_rough_at(l, dispersion, m, s, b.ns);
  // A dielectric of a named glass (params.w: GLASS_* + 1) disperses by it.
  if (FEATURE_COMPILED(FEATURE_DISPERSION) && (m.info.x == MAT_DIELECTRIC || m.info.x == MAT_ROUGH_DIELECTRIC) && m.params.w > 0.0f)
    dispersion = -m.params.w;
  bsdf_store_params(b, k, l);
  if (FEATURE_COMPILED(FEATURE_DISPERSION)) b.lobeDispersion[k] = dispersion;
}

// The shading normal at s under normal map `tex` (glTF's convention): the
// map's colour c is the tangent-space normal 2 c - 1, scaled by the
// texture's factor (scale, scale, 1), in the frame of s's tangent, its
// handedness and the interpolated normal. Where the frame degenerates or the
// mapped normal turns away from the geometric one, the interpolated normal.
// A mapped normal n can mirror the view direction v below the surface
// (geometric normal ng, v on its side), where a path tracer finds no light
// and a normal-mapped metal goes black at its rims. This returns n itself
// where its reflection of v stays at least t = min(0.9 cos(v), 0.01) above
// the surface, else the normal nearest to n, in the plane of ng and n, whose
// reflection just does (the remedy Cycles applies to shading normals). With
// n' = cos(a) ng + sin(a) x, x the unit tangential part of n, the
// reflection r' of v has dot(ng, r') = vz cos(2a) + vx sin(2a) =
// A cos(2a - phi), A = |(vz, vx)|, phi = atan(vx, vz): valid for 2a within
// acos(t / A) of phi; the bound nearest n's own angle is taken.
vec3 valid_reflection_normal(vec3 ng, vec3 v, vec3 n) {
  float vz = dot(v, ng);
  float t = min(0.9f * vz, 0.01f);
  if (dot(ng, 2.0f * dot(n, v) * n - v) >= t) return n;
  vec3 x = n - ng * dot(n, ng);
  float xl = length(x);
  if (!(xl > 0.0f)) return ng;
  x /= xl;
  float vx = dot(v, x);
  float a = sqrt(vz * vz + vx * vx);
  if (!(a > 0.0f)) return ng;
  float phi = atan(vx, vz);
  float delta = acos(clamp(t / a, -1.0f, 1.0f));
  float angle = 2.0f * atan(xl, dot(n, ng)) > phi ? 0.5f * (phi + delta) : 0.5f * (phi - delta);
  return ng * cos(angle) + x * sin(angle);
}

vec3 normal_mapped(SurfaceHit s, uint tex) {
  Texture t = load_texture(tex);
  vec4 c = image_lookup(t, texture_point(t, s.uv, s.p));
  vec3 tn = (vec3(c.x, c.y, c.z) * 2.0f - vec3(1.0f)) * vec3(t.color0.x, t.color0.y, t.color0.z);
  vec3 tangent = vec3(s.tangent.x, s.tangent.y, s.tangent.z);
  tangent -= s.ns * dot(s.ns, tangent);
  float len = length(tangent);
  if (!(len > 0.0f)) return s.ns;
  tangent /= len;
  vec3 bitangent = cross(s.ns, tangent) * s.tangent.w;
  vec3 n = tangent * tn.x + bitangent * tn.y + s.ns * tn.z;
  float nl = length(n);
  if (!(nl > 0.0f) || dot(n, s.ng) <= 0.0f) return s.ns;
  return n / nl;
}

// Whether a material's step of bsdf_at looks up no texture: the dielectric
// is white, a light adds no lobe, and a Fresnel blend computes its amount.
bool material_needs_no_texture(Material m) {
  if (MATERIAL_COMPILED(MAT_DIELECTRIC) && m.info.x == MAT_DIELECTRIC) return true;
  if (m.info.x == MAT_LIGHT) return true;
  return MATERIAL_COMPILED(MAT_BLEND) && TEXTURE_COMPILED(TEX_FRESNEL) && m.info.x == MAT_BLEND &&
         (load_texture(m.info.w).info.x & TEX_TYPE_MASK) == TEX_FRESNEL;
}

// The fraction of light a path keeps over a segment of length t inside the
// volume that material `material` bounds (KHR_materials_volume's
// Beer-Lambert law, T = exp(-sigma t)), 1 for other materials; in the
// spectral mode at the path's wavelengths `lambdas`.
Spectrum volume_transmittance(uint material, float t, vec4 lambdas) {
  Material m = surface_material(load_material(material));
  vec4 v = m.extra[MR_VOLUME];
  if (m.info.x != MAT_METAL_ROUGH || !(v.w > 0.0f)) return Spectrum(1.0f);
  Spectrum sigma = spectral_mode() ? unbounded_spectrum(vec3(v.x, v.y, v.z), lambdas) : spectrum_rgb(vec3(v.x, v.y, v.z));
  return exp(-sigma * t);
}

// The shading normal at s under a normal map (FEATURE_NORMAL_MAPS) or the
// interpolated one, on wo's side or not, valid for reflecting wo.
vec3 mapped_normal(SurfaceHit s, uint normalMap, vec3 wo, bool front) {
  if (!FEATURE_COMPILED(FEATURE_NORMAL_MAPS) || !TEXTURE_COMPILED(TEX_IMAGE) || normalMap == WP_INVALID) return s.ns;
  return valid_reflection_normal(s.ng, front ? wo : -wo, normal_mapped(s, normalMap));
}

// A clear coat's lobe (MAT_CLEARCOAT) at lobe k, of weight w times the coat's
// (clearcoat_weight); returns that weight. Its factor is `factor`, its
// roughness r.
float bsdf_add_clearcoat(INOUT(Bsdf) b, uint k, Material m, SurfaceHit s, vec3 wo, float w, float factor, float r) {
  vec3 nc = mapped_normal(s, m.children.z, wo, b.front);
  nc = b.front ? nc : -nc;
  float wc = w * clearcoat_weight(clamp(factor, 0.0f, 1.0f), clearcoat_f0(m.params.x), dot(wo, nc));
  b.lobeType[k] = MAT_CLEARCOAT;
  b.lobeColor[k] = Spectrum(1.0f);
  b.lobeWeight[k] = wc;
  float alpha = clamp(r, 0.0f, 1.0f);
  bsdf_set_params(b, k, vec4(max(alpha * alpha, GGX_MIN_ALPHA), 0.0f, 0.0f, 0.0f), vec4(nc.x, nc.y, nc.z, 0.0f));
  return wc;
}

// A sheen's lobe (MAT_SHEEN) at lobe k: weight w times its albedo at wo, the
// colour scaled to match; records the albedo scaling of the lobes it covers
// (b.sheen). Returns the lobe's weight (0 where it adds none).
float bsdf_add_sheen(INOUT(Bsdf) b, uint k, vec3 color, float r, vec3 wo, float w) {
  float roughness = clamp(r, SHEEN_MIN_ROUGHNESS, 1.0f);
  float strength = max(max(color.x, color.y), color.z);
  float albedo = strength * sheen_albedo_bounded(dot(wo, b.ns), roughness);
  b.sheen = vec4(strength, roughness, albedo, 0.0f);
  if (!(albedo > 1e-6f)) return 0.0f;
  b.lobeType[k] = MAT_SHEEN;
  b.lobeColor[k] = spectrum_rgb(color / albedo);
  b.lobeWeight[k] = w * albedo;
  bsdf_set_params(b, k, vec4(roughness, 0.0f, 0.0f, 0.0f), vec4(0.0f));
  return w * albedo;
}

// The BSDF at s seen from wo: textures looked up, blends flattened into
// weighted lobes (depth-first, bounded: the loader allows at most
// BSDF_MAX_LOBES leaves per material).
Bsdf bsdf_at(SurfaceHit s, vec3 wo) {
  Bsdf b;
  Material m = load_material(s.material);
  b.front = dot(s.ng, wo) >= 0.0f;
  // A layer's normal map is its coat's; the surface's is its base's.
  vec3 ns = mapped_normal(s, surface_material(m).children.z, wo, b.front);
  b.ng = b.front ? s.ng : -s.ng;
  b.ns = b.front ? ns : -ns;
  b.lobeCount = 0u;
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    b.lobeType[i] = MAT_LAMBERTIAN;
    b.lobeColor[i] = Spectrum(0.0f);
#ifdef WP_SPECTRUM_W
    b.lobeFourth[i] = vec4(0.0f);
#endif
    bsdf_set_params(b, i, vec4(0.0f), vec4(0.0f));
    b.lobeWeight[i] = 0.0f;
    if (FEATURE_COMPILED(FEATURE_DISPERSION)) b.lobeDispersion[i] = 0.0f;
  }
  b.sheen = vec4(0.0f);
  b.sheenCovers = 0u;
  if (m.info.x == MAT_LIGHT) return b;  // emits, does not scatter (never compiled out: one comparison)
  if (MATERIAL_COMPILED(MAT_INTERFACE) && m.info.x == MAT_INTERFACE) return b;  // no surface at all
  // Vertex colours tint every lobe (glTF: they multiply the base colour).
  vec3 tint = FEATURE_COMPILED(FEATURE_VERTEX_DATA) ? vec3(s.color.x, s.color.y, s.color.z) : vec3(1.0f);
  if (!COMPOSITE_MATERIALS_COMPILED) {  // one lobe
    vec3 color = tint * (material_needs_no_texture(m) ? vec3(1.0f) : texture_eval(m.info.y, s.uv, s.p));
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
  // The stack slot a sheen's base took: lobes from entries popped at or
  // above it lie under the sheen (a material holds at most one sheen).
  uint sheenFloor = BSDF_MAX_LOBES;
  for (uint iter = 0u; iter < 2u * BSDF_MAX_LOBES && sp > 0u; ++iter) {
    sp -= 1u;
    m = load_material(stackMaterial[sp]);
    float w = stackWeight[sp];
    if (sp < sheenFloor) sheenFloor = BSDF_MAX_LOBES;
    bool underSheen = MATERIAL_COMPILED(MAT_SHEEN) && sheenFloor < BSDF_MAX_LOBES;
    bool blend = MATERIAL_COMPILED(MAT_BLEND) && m.info.x == MAT_BLEND;
    bool untextured = material_needs_no_texture(m);
    vec3 color = untextured ? vec3(1.0f) : texture_eval(blend ? m.info.w : m.info.y, s.uv, s.p);
    if (LAYER_MATERIALS_COMPILED && (m.info.x == MAT_CLEARCOAT || m.info.x == MAT_SHEEN)) {
      // A layer: its own lobe, and its base in the rest of the weight. Its
      // albedo texture is the coat's factor (red) or the sheen's colour;
      // info.w its roughness (green).
      float r = texture_eval(m.info.w, s.uv, s.p).y;
      float layer = 0.0f;
      if (b.lobeCount < BSDF_MAX_LOBES && w > 0.0f) {
        if (MATERIAL_COMPILED(MAT_CLEARCOAT) && m.info.x == MAT_CLEARCOAT) layer = bsdf_add_clearcoat(b, b.lobeCount, m, s, wo, w, color.x, r);
        if (MATERIAL_COMPILED(MAT_SHEEN) && m.info.x == MAT_SHEEN) layer = bsdf_add_sheen(b, b.lobeCount, color, r, wo, w);
      }
      if (layer > 0.0f) {
        if (underSheen) b.sheenCovers |= 1u << b.lobeCount;
        b.lobeCount += 1u;
        total += layer;
      }
      stackMaterial[sp] = m.children.x;
      stackWeight[sp] = w - layer;
      if (MATERIAL_COMPILED(MAT_SHEEN) && m.info.x == MAT_SHEEN) sheenFloor = sp;
      sp += 1u;
      continue;
    }
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
    bsdf_set_lobe(b, b.lobeCount, m, tint * color, w, s);
    if (underSheen) b.sheenCovers |= 1u << b.lobeCount;
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
